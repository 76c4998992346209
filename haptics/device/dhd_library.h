#pragma once
// The Force Dimension SDK (libdhd, and libdrd for the robotic regulation), loaded at run time.
//
// The SDK is proprietary and not packaged, so nothing of it is vendored or linked: the library is opened with
// dlopen and only the functions this back end calls are looked up, each declared here with the SDK's public C
// signature (the trailing `char id` selects the device; -1 means the SDK's current device). The program builds and
// runs without the SDK; opening it then fails with an error naming every path tried.

#include <memory>
#include <string>
#include <vector>

namespace robossis::haptics {

// The SDK's public constants this back end relies on (values from the SDK's public C header, dhdc.h).
namespace dhd {
// dhd_errors: what dhdErrorGetLast() returns after a call returned a negative value.
inline constexpr int kNoError = 0;
inline constexpr int kError = 1;
inline constexpr int kErrorCom = 2;
inline constexpr int kErrorDhcBusy = 3;
inline constexpr int kErrorNoDriverFound = 4;
inline constexpr int kErrorNoDeviceFound = 5;
inline constexpr int kErrorNotAvailable = 6;
inline constexpr int kErrorTimeout = 7;
inline constexpr int kErrorDeviceNotReady = 12;
// Device types (dhdGetSystemType): the sigma.7 is the SDK's "sigma.331", right- or left-handed.
inline constexpr int kDeviceSigma331 = 104;
inline constexpr int kDeviceSigma331Left = 105;
// dhdConfigLinearVelocity / dhdConfigAngularVelocity mode: a moving window of the given length.
inline constexpr int kVelocityWindowing = 0;
// The SDK's own default window (ms).
inline constexpr int kDefaultVelocityWindowMs = 20;
// Size of the DRD's per-axis arrays (DHD_MAX_DOF): x, y, z, three orientation angles, gripper, one spare.
inline constexpr int kMaxDof = 8;
}  // namespace dhd

// libdhd's functions used by DhdDevice (public signatures; return < 0 on error unless noted).
struct DhdApi {
  int (*dhdGetDeviceCount)();
  int (*dhdOpenID)(char id);         // returns the id
  int (*dhdOpenSerial)(int serial);  // returns the id
  int (*dhdClose)(char id);
  int (*dhdStop)(char id);
  int (*dhdGetSystemType)(char id);
  const char* (*dhdGetSystemName)(char id);
  void (*dhdGetSDKVersion)(int* major, int* minor, int* release, int* revision);
  int (*dhdGetSerialNumber)(unsigned short* serial, char id);
  int (*dhdEnableForce)(unsigned char on, char id);
  int (*dhdConfigLinearVelocity)(int window_ms, int mode, char id);
  int (*dhdConfigAngularVelocity)(int window_ms, int mode, char id);
  int (*dhdGetPositionAndOrientationFrame)(double* px, double* py, double* pz, double matrix[3][3], char id);
  int (*dhdGetLinearVelocity)(double* vx, double* vy, double* vz, char id);
  int (*dhdGetAngularVelocityRad)(double* wx, double* wy, double* wz, char id);
  unsigned int (*dhdGetButtonMask)(char id);  // no error channel: a failed read shows in the other calls
  int (*dhdGetGripperAngleRad)(double* angle, char id);
  int (*dhdSetForceAndTorqueAndGripperForce)(double fx, double fy, double fz, double tx, double ty, double tz,
                                             double fg, char id);
  int (*dhdErrorGetLast)();
  const char* (*dhdErrorGetStr)(int error);
};

// libdrd's functions used for the optional hold (the SDK's regulation thread holds the handle at a pose). libdrd
// carries libdhd inside it: when the hold is wanted, both tables come from libdrd, so that one SDK instance owns
// the USB device (loading libdhd and libdrd side by side would open it twice).
struct DrdApi {
  int (*drdOpenID)(char id);
  int (*drdClose)(char id);
  int (*drdStart)(char id);
  int (*drdRegulatePos)(bool on, char id);
  int (*drdRegulateRot)(bool on, char id);
  int (*drdGetPositionAndOrientation)(double p[dhd::kMaxDof], double rot[3][3], char id);
  int (*drdMoveTo)(double p[dhd::kMaxDof], bool block, char id);
  int (*drdHold)(char id);
  int (*drdStop)(bool keep_forces, char id);
};

// An opened shared library (dlclose on destruction).
class SharedLibrary {
 public:
  // Opens the first of `candidates` that dlopen accepts. Throws std::runtime_error naming `what`, every candidate
  // tried and dlopen's reason for each.
  static std::shared_ptr<SharedLibrary> OpenFirst(const std::string& what, const std::vector<std::string>& candidates);
  ~SharedLibrary();
  SharedLibrary(const SharedLibrary&) = delete;
  SharedLibrary& operator=(const SharedLibrary&) = delete;

  // The symbol, or nullptr.
  void* Find(const char* symbol) const noexcept;
  const std::string& path() const { return path_; }

 private:
  SharedLibrary(void* handle, std::string path) : handle_(handle), path_(std::move(path)) {}
  void* handle_;
  std::string path_;
};

// Where to look for libdhd: `explicit_path` alone if given; else $ROBOSSIS_DHD_LIBRARY (if set), then the names
// the SDK installs (found through the loader's path: LD_LIBRARY_PATH, ld.so.conf) and its usual install folders.
std::vector<std::string> DhdLibraryCandidates(const std::string& explicit_path);
// The same for libdrd ($ROBOSSIS_DRD_LIBRARY).
std::vector<std::string> DrdLibraryCandidates(const std::string& explicit_path);

// The function tables. Each throws std::runtime_error naming the library and the first function it lacks.
DhdApi LoadDhdApi(const SharedLibrary& library);
DrdApi LoadDrdApi(const SharedLibrary& library);

}  // namespace robossis::haptics
