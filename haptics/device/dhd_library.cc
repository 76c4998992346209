#include "haptics/device/dhd_library.h"

#include <dlfcn.h>

#include <cstdlib>
#include <stdexcept>

namespace robossis::haptics {

std::shared_ptr<SharedLibrary> SharedLibrary::OpenFirst(const std::string& what,
                                                        const std::vector<std::string>& candidates) {
  std::string tried;
  for (const std::string& path : candidates) {
    // RTLD_NOW: a library that cannot resolve its own dependencies fails here, not in the haptic loop.
    if (void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) {
      return std::shared_ptr<SharedLibrary>(new SharedLibrary(handle, path));
    }
    const char* error = dlerror();
    const std::string reason = error != nullptr ? error : "not found";
    // dlerror names the file already when it was looked up by path.
    tried += "\n  " + (reason.rfind(path, 0) == 0 ? reason : path + ": " + reason);
  }
  throw std::runtime_error(what + " not found; tried:" + tried);
}

SharedLibrary::~SharedLibrary() { dlclose(handle_); }

void* SharedLibrary::Find(const char* symbol) const noexcept { return dlsym(handle_, symbol); }

namespace {

std::vector<std::string> Candidates(const std::string& explicit_path, const char* env_var, const char* stem) {
  if (!explicit_path.empty()) return {explicit_path};
  std::vector<std::string> out;
  if (const char* env = std::getenv(env_var); env != nullptr && *env != '\0') out.emplace_back(env);
  const std::string so = std::string(stem) + ".so";
  // The SDK's Linux archives ship lib<stem>.so with the major version 3; users copy it to /usr/local/lib or point
  // the loader's path at the SDK's lib/release/lnx-x86_64-gcc folder.
  for (const std::string& name : {so, so + ".3"}) out.push_back(name);
  for (const std::string& name : {so, so + ".3"}) out.push_back("/usr/local/lib/" + name);
  out.push_back("/opt/forcedimension/lib/" + so);
  return out;
}

// Looks up `name` and stores it in `fn` (a function pointer of the declared signature).
template <typename Fn>
void Bind(const SharedLibrary& library, const char* name, Fn& fn) {
  void* symbol = library.Find(name);
  if (symbol == nullptr) {
    throw std::runtime_error(library.path() + ": the SDK function '" + name +
                             "' is missing (an SDK older than 3.3, or not the Force Dimension library)");
  }
  fn = reinterpret_cast<Fn>(symbol);
}

}  // namespace

std::vector<std::string> DhdLibraryCandidates(const std::string& explicit_path) {
  return Candidates(explicit_path, "ROBOSSIS_DHD_LIBRARY", "libdhd");
}

std::vector<std::string> DrdLibraryCandidates(const std::string& explicit_path) {
  return Candidates(explicit_path, "ROBOSSIS_DRD_LIBRARY", "libdrd");
}

#define ROBOSSIS_BIND(api, library, fn) Bind(library, #fn, api.fn)

DhdApi LoadDhdApi(const SharedLibrary& library) {
  DhdApi api{};
  ROBOSSIS_BIND(api, library, dhdGetDeviceCount);
  ROBOSSIS_BIND(api, library, dhdOpenID);
  ROBOSSIS_BIND(api, library, dhdOpenSerial);
  ROBOSSIS_BIND(api, library, dhdClose);
  ROBOSSIS_BIND(api, library, dhdStop);
  ROBOSSIS_BIND(api, library, dhdGetSystemType);
  ROBOSSIS_BIND(api, library, dhdGetSystemName);
  ROBOSSIS_BIND(api, library, dhdGetSDKVersion);
  ROBOSSIS_BIND(api, library, dhdGetSerialNumber);
  ROBOSSIS_BIND(api, library, dhdEnableForce);
  ROBOSSIS_BIND(api, library, dhdConfigLinearVelocity);
  ROBOSSIS_BIND(api, library, dhdConfigAngularVelocity);
  ROBOSSIS_BIND(api, library, dhdGetPositionAndOrientationFrame);
  ROBOSSIS_BIND(api, library, dhdGetLinearVelocity);
  ROBOSSIS_BIND(api, library, dhdGetAngularVelocityRad);
  ROBOSSIS_BIND(api, library, dhdGetButtonMask);
  ROBOSSIS_BIND(api, library, dhdGetGripperAngleRad);
  ROBOSSIS_BIND(api, library, dhdSetForceAndTorqueAndGripperForce);
  ROBOSSIS_BIND(api, library, dhdErrorGetLast);
  ROBOSSIS_BIND(api, library, dhdErrorGetStr);
  return api;
}

DrdApi LoadDrdApi(const SharedLibrary& library) {
  DrdApi api{};
  ROBOSSIS_BIND(api, library, drdOpenID);
  ROBOSSIS_BIND(api, library, drdClose);
  ROBOSSIS_BIND(api, library, drdStart);
  ROBOSSIS_BIND(api, library, drdRegulatePos);
  ROBOSSIS_BIND(api, library, drdRegulateRot);
  ROBOSSIS_BIND(api, library, drdGetPositionAndOrientation);
  ROBOSSIS_BIND(api, library, drdMoveTo);
  ROBOSSIS_BIND(api, library, drdHold);
  ROBOSSIS_BIND(api, library, drdStop);
  return api;
}

#undef ROBOSSIS_BIND

}  // namespace robossis::haptics
