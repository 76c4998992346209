// A fake of the Force Dimension SDK for the tests: the C functions of libdhd (and, built with FAKE_DHD_WITH_DRD, of
// libdrd, which carries libdhd inside it) over the simulated sigma.7 and hand of haptics/device/device_sim.h. Built
// as libdhd.so / libdrd.so; a variant built with FAKE_DHD_OMIT_FORCE_CALL lacks dhdSetForceAndTorqueAndGripperForce.
//
// Only the signatures are the SDK's (public); the behaviour is a model written for these tests: a device call fails
// with -1 and sets the error that dhdErrorGetLast returns; the physics advances one tick per force write.

#include <cmath>
#include <limits>
#include <memory>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "haptics/device/device_sim.h"
#include "robot/sigma7_model.h"
#include "src/core/pose.h"
#include "tests/haptics/fake_dhd/fake_dhd_control.h"

namespace {

using robossis::haptics::HandParams;
using robossis::haptics::HandTarget;
using robossis::haptics::SimulatedSigma7;

// SDK values (public dhdc.h).
constexpr int kErrorCom = 2;
constexpr int kErrorNoDeviceFound = 5;
constexpr int kErrorInvalidIndex = 15;
constexpr int kTypeSigma331 = 104;
constexpr int kTypeSigma331Left = 105;
constexpr int kTypeOmega3 = 33;
constexpr int kMaxDevices = 4;
// The fake's DRD regulation gains (a stiff PD, well inside the sigma.7's 20 N).
constexpr double kHoldStiffness = 2000, kHoldDamping = 30, kHoldRotStiffness = 1.0, kHoldRotDamping = 0.02;

struct Device {
  int type = kTypeSigma331;
  int serial = 1234;
  bool open = false;
};

struct Fake {
  Device devices[kMaxDevices];
  int count = 1;
  int current = -1;
  bool unplugged = false;
  int fail_count = 0, fail_error = 0, nan_count = 0;
  int last_error = 0;
  int forces_enabled = 0;
  int linear_window_ms = 20, angular_window_ms = 20;  // the SDK's default
  double dt = 0.25e-3;
  Eigen::Vector3d f = Eigen::Vector3d::Zero(), tau = Eigen::Vector3d::Zero();
  double gripper_force = 0;
  unsigned int buttons = 1;
  HandParams hand;
  HandTarget target;
  std::unique_ptr<SimulatedSigma7> sim;  // a unique_ptr: the simulation holds a reference, so it is not assignable
  bool at_limit = false;
  long force_writes = 0, force_writes_held = 0;
  bool drd_open = false, drd_running = false;
  Eigen::Isometry3d hold_target = Eigen::Isometry3d::Identity();
  double elapsed_s = 0;          // device time: one tick per force write
  double delayed_target_at_s = -1;  // < 0: none pending
  Eigen::Vector3d delayed_target = Eigen::Vector3d::Zero();
};

const robossis::robot::Sigma7Model& Model() {
  static const robossis::robot::Sigma7Model model = robossis::robot::Sigma7Model::Default();
  return model;
}

Fake& State() {
  static Fake fake;
  return fake;
}

void Reset() {
  Fake& s = State();
  s = Fake{};
  Eigen::Isometry3d centre = Eigen::Isometry3d::Identity();
  centre.translation() = Model().p_center_O();
  s.sim = std::make_unique<SimulatedSigma7>(Model(), robossis::haptics::DeviceSimParams{}, s.hand);
  s.sim->Reset(centre);
  s.target.X_OH = centre;
}

Fake& Get() {
  Fake& s = State();
  if (!s.sim) Reset();
  return s;
}

int Fail(int error) {
  Get().last_error = error;
  return -1;
}

// The device an SDK call addresses (id -1: the current one), or nullptr after setting the error.
Device* Address(char id) {
  Fake& s = Get();
  const int index = id < 0 ? s.current : id;
  if (index < 0 || index >= s.count) {
    Fail(kErrorInvalidIndex);
    return nullptr;
  }
  return &s.devices[index];
}

// A call that talks to the device over USB: false (error set) when unplugged, not open or an injected failure.
bool Talk(char id) {
  Fake& s = Get();
  int error = 0;
  Device* d = s.unplugged ? nullptr : Address(id);
  if (s.unplugged) {
    error = kErrorNoDeviceFound;
  } else if (d == nullptr) {
    return false;  // Address set the error
  } else if (!d->open) {
    error = kErrorCom;
  } else if (s.fail_count > 0) {
    --s.fail_count;
    error = s.fail_error;
  }
  if (error != 0) Fail(error);
  return error == 0;
}

void Step(const Eigen::Vector3d& f, const Eigen::Vector3d& tau) {
  Fake& s = Get();
  s.elapsed_s += s.dt;
  if (s.delayed_target_at_s >= 0 && s.elapsed_s >= s.delayed_target_at_s) {
    s.target.X_OH.translation() = s.delayed_target;
    s.delayed_target_at_s = -1;
  }
  s.at_limit = s.sim->Step(s.dt, f, tau, s.target).at_mechanical_limit;
}

// The DRD regulation's own tick: a PD toward the held pose.
void StepHold() {
  Fake& s = Get();
  const Eigen::Isometry3d& X = s.sim->pose();
  const Eigen::Vector3d f =
      kHoldStiffness * (s.hold_target.translation() - X.translation()) - kHoldDamping * s.sim->velocity();
  const Eigen::Vector3d tau =
      kHoldRotStiffness * robossis::RotationVector(s.hold_target.linear() * X.linear().transpose()) -
      kHoldRotDamping * s.sim->angular_velocity();
  Step(f, tau);
}

int OpenIndex(int index) {
  Fake& s = Get();
  if (s.unplugged) return Fail(kErrorNoDeviceFound);
  if (index < 0 || index >= s.count) return Fail(kErrorNoDeviceFound);
  s.devices[index].open = true;
  s.current = index;
  return index;
}

}  // namespace

extern "C" {

// ---- libdhd ----

int dhdGetDeviceCount() { return Get().unplugged ? 0 : Get().count; }
int dhdOpen() { return OpenIndex(0); }
int dhdOpenID(char id) { return OpenIndex(id); }
int dhdOpenSerial(int serial) {
  Fake& s = Get();
  for (int i = 0; i < s.count; ++i) {
    if (s.devices[i].serial == serial) return OpenIndex(i);
  }
  return Fail(kErrorNoDeviceFound);
}
int dhdClose(char id) {
  Device* d = Address(id);
  if (d == nullptr) return -1;
  d->open = false;
  return 0;
}
int dhdStop(char id) {
  if (!Talk(id)) return -1;
  Get().forces_enabled = 0;
  return 0;
}
int dhdGetSystemType(char id) {
  Device* d = Address(id);
  return d == nullptr ? -1 : d->type;
}
const char* dhdGetSystemName(char id) {
  Device* d = Address(id);
  if (d == nullptr) return nullptr;
  switch (d->type) {
    case kTypeSigma331: return "sigma.7";
    case kTypeSigma331Left: return "sigma.7 left";
    case kTypeOmega3: return "omega.3";
    default: return "custom";
  }
}
void dhdGetSDKVersion(int* major, int* minor, int* release, int* revision) {
  *major = 3;
  *minor = 99;  // no real release: the fake says so in its version
  *release = 0;
  *revision = 1;
}
int dhdGetSerialNumber(unsigned short* serial, char id) {
  Device* d = Address(id);
  if (d == nullptr) return -1;
  *serial = static_cast<unsigned short>(d->serial);
  return 0;
}
int dhdEnableForce(unsigned char on, char id) {
  if (!Talk(id)) return -1;
  Get().forces_enabled = on != 0;
  return 0;
}
int dhdConfigLinearVelocity(int window_ms, int /*mode*/, char id) {
  if (!Talk(id)) return -1;
  Get().linear_window_ms = window_ms;
  return 0;
}
int dhdConfigAngularVelocity(int window_ms, int /*mode*/, char id) {
  if (!Talk(id)) return -1;
  Get().angular_window_ms = window_ms;
  return 0;
}
int dhdGetPositionAndOrientationFrame(double* px, double* py, double* pz, double matrix[3][3], char id) {
  if (!Talk(id)) return -1;
  Fake& s = Get();
  if (s.drd_running) StepHold();
  const Eigen::Isometry3d& X = s.sim->pose();
  *px = X.translation().x();
  *py = X.translation().y();
  *pz = X.translation().z();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) matrix[i][j] = X.linear()(i, j);
  }
  if (s.nan_count > 0) {
    --s.nan_count;
    *px = std::numeric_limits<double>::quiet_NaN();
  }
  return 0;
}
int dhdGetLinearVelocity(double* vx, double* vy, double* vz, char id) {
  if (!Talk(id)) return -1;
  const Eigen::Vector3d& v = Get().sim->velocity();
  *vx = v.x();
  *vy = v.y();
  *vz = v.z();
  return 0;
}
int dhdGetAngularVelocityRad(double* wx, double* wy, double* wz, char id) {
  if (!Talk(id)) return -1;
  const Eigen::Vector3d& w = Get().sim->angular_velocity();
  *wx = w.x();
  *wy = w.y();
  *wz = w.z();
  return 0;
}
unsigned int dhdGetButtonMask(char id) { return Talk(id) ? Get().buttons : 0u; }
int dhdGetGripperAngleRad(double* angle, char id) {
  if (!Talk(id)) return -1;
  *angle = 0.3;  // a half-open gripper
  return 0;
}
#ifndef FAKE_DHD_OMIT_FORCE_CALL
int dhdSetForceAndTorqueAndGripperForce(double fx, double fy, double fz, double tx, double ty, double tz, double fg,
                                        char id) {
  if (!Talk(id)) return -1;
  Fake& s = Get();
  ++s.force_writes;
  if (s.drd_running) {
    ++s.force_writes_held;
    return 0;
  }
  s.f = Eigen::Vector3d(fx, fy, fz);
  s.tau = Eigen::Vector3d(tx, ty, tz);
  s.gripper_force = fg;
  if (s.forces_enabled) {
    Step(s.f, s.tau);
  } else {
    Step(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  }
  return 0;
}
#endif
int dhdErrorGetLast() { return Get().last_error; }
const char* dhdErrorGetStr(int error) {
  switch (error) {
    case 0: return "no error";
    case kErrorCom: return "communication error between the host and the device";
    case kErrorNoDeviceFound: return "no compatible device found";
    case 7: return "timeout";
    default: return "error";
  }
}

// ---- libdrd (the regulation runs "in the background": one PD step per position read) ----
#ifdef FAKE_DHD_WITH_DRD
int drdOpenID(char id) {
  if (!Talk(id)) return -1;
  Get().drd_open = true;
  return id;
}
int drdClose(char /*id*/) {
  Get().drd_open = false;
  Get().drd_running = false;
  return 0;
}
int drdStart(char id) {
  if (!Talk(id) || !Get().drd_open) return -1;
  Fake& s = Get();
  s.drd_running = true;
  s.forces_enabled = 1;
  s.hold_target = s.sim->pose();
  return 0;
}
int drdRegulatePos(bool /*on*/, char id) { return Talk(id) ? 0 : -1; }
int drdRegulateRot(bool /*on*/, char id) { return Talk(id) ? 0 : -1; }
int drdGetPositionAndOrientation(double p[8], double rot[3][3], char id) {
  if (!Talk(id)) return -1;
  const Eigen::Isometry3d& X = Get().sim->pose();
  for (int i = 0; i < 8; ++i) p[i] = 0;
  for (int i = 0; i < 3; ++i) {
    p[i] = X.translation()(i);
    for (int j = 0; j < 3; ++j) rot[i][j] = X.linear()(i, j);
  }
  return 0;
}
int drdMoveTo(double p[8], bool /*block*/, char id) {
  if (!Talk(id) || !Get().drd_running) return Fail(kErrorCom);
  Get().hold_target.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
  return 0;
}
int drdHold(char id) {
  if (!Talk(id) || !Get().drd_running) return Fail(kErrorCom);
  Get().hold_target = Get().sim->pose();
  return 0;
}
int drdStop(bool keep_forces, char id) {
  if (!Talk(id)) return -1;
  Fake& s = Get();
  s.drd_running = false;
  if (!keep_forces) s.forces_enabled = 0;
  return 0;
}
#endif

// ---- test controls ----

void fake_dhd_reset(void) { Reset(); }
void fake_dhd_set_devices(int count, const int* types, const int* serials) {
  Fake& s = Get();
  s.count = count < 0 ? 0 : (count > kMaxDevices ? kMaxDevices : count);
  for (int i = 0; i < s.count; ++i) s.devices[i] = Device{types[i], serials[i], false};
}
void fake_dhd_set_tick(double dt_s) { Get().dt = dt_s; }
void fake_dhd_set_hand_target(double x, double y, double z) {
  Get().target.X_OH.translation() = Eigen::Vector3d(x, y, z);
}
void fake_dhd_set_hand_target_after(double delay_s, double x, double y, double z) {
  Fake& s = Get();
  s.delayed_target = Eigen::Vector3d(x, y, z);
  s.delayed_target_at_s = s.elapsed_s + delay_s;
}
void fake_dhd_set_hand_stiffness(double stiffness_n_per_m) {
  Fake& s = Get();
  s.hand.stiffness_n_per_m = stiffness_n_per_m;
  s.sim->set_hand(s.hand);
}
void fake_dhd_set_buttons(unsigned int mask) { Get().buttons = mask; }
void fake_dhd_unplug(void) { Get().unplugged = true; }
void fake_dhd_fail_next(int count, int error) {
  Get().fail_count = count;
  Get().fail_error = error;
}
void fake_dhd_nan_next(int count) { Get().nan_count = count; }
void fake_dhd_get_state(FakeDhdState* out) {
  Fake& s = Get();
  for (int i = 0; i < 3; ++i) {
    out->p[i] = s.sim->pose().translation()(i);
    out->v[i] = s.sim->velocity()(i);
    out->f[i] = s.f(i);
    out->tau[i] = s.tau(i);
  }
  out->gripper_force = s.gripper_force;
  out->forces_enabled = s.forces_enabled;
  out->linear_window_ms = s.linear_window_ms;
  out->angular_window_ms = s.angular_window_ms;
  out->open_devices = 0;
  for (int i = 0; i < s.count; ++i) out->open_devices += s.devices[i].open ? 1 : 0;
  out->force_writes = s.force_writes;
  out->force_writes_held = s.force_writes_held;
  out->drd_running = s.drd_running;
  out->at_mechanical_limit = s.at_limit;
}

}  // extern "C"
