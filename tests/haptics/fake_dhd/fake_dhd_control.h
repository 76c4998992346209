#pragma once
// Test controls of the fake Force Dimension SDK (fake_dhd.cc). The tests reach these through dlsym on the same
// library the back end opened (dlopen of the same path returns the same instance), so one fake serves both.

#ifdef __cplusplus
extern "C" {
#endif

// What the fake device saw and did, for the tests to check.
struct FakeDhdState {
  double p[3];              // handle position (m)
  double v[3];              // handle velocity (m/s)
  double f[3];              // last force command (N), as received
  double tau[3];            // last torque command (N·m)
  double gripper_force;     // last gripper force command (N)
  int forces_enabled;       // dhdEnableForce's last value
  int linear_window_ms;     // dhdConfigLinearVelocity's window
  int angular_window_ms;    // dhdConfigAngularVelocity's window
  int open_devices;         // devices open now
  long force_writes;        // dhdSetForceAndTorqueAndGripperForce calls
  long force_writes_held;   // ... of them while the DRD regulation was running
  int drd_running;          // the regulation thread is running
  int at_mechanical_limit;  // the last physics step hit the sigma.7's stops
};

// Back to one connected sigma.7 (serial 1234) at its workspace centre, at rest, the hand holding it there, a
// 0.25 ms tick (4 kHz), forces disabled, nothing injected.
void fake_dhd_reset(void);
// Replaces the connected devices (types as dhdGetSystemType reports them; at most 4). The sigma.7 physics is shared.
void fake_dhd_set_devices(int count, const int* types, const int* serials);
// The physics advances by this step on every force write (and on every read while the DRD regulation runs).
void fake_dhd_set_tick(double dt_s);
// Where the simulated hand pulls the handle (m, device frame), and how stiffly (N/m).
void fake_dhd_set_hand_target(double x, double y, double z);
// The same, once `delay_s` of device time (ticks of fake_dhd_set_tick) has passed.
void fake_dhd_set_hand_target_after(double delay_s, double x, double y, double z);
void fake_dhd_set_hand_stiffness(double stiffness_n_per_m);
void fake_dhd_set_buttons(unsigned int mask);
// The device disappears: every later call fails with DHD_ERROR_NO_DEVICE_FOUND (until fake_dhd_reset).
void fake_dhd_unplug(void);
// The next `count` device calls fail with this SDK error code (DHD_ERROR_TIMEOUT = 7, DHD_ERROR_COM = 2, ...).
void fake_dhd_fail_next(int count, int error);
// The next `count` position reads return NaN.
void fake_dhd_nan_next(int count);
void fake_dhd_get_state(struct FakeDhdState* out);

#ifdef __cplusplus
}
#endif
