#pragma once
// Knows when the operator has let go of the device, from its motion alone: a device that nobody holds accelerates
// under the displayed force as its own mass does, a held one as the hand and the device together (the hand adds at
// least its own mass and the grasp's stiffness). Once let go, the leader stops showing the follower's load and
// damps the device to rest (a damper only takes energy: the port stays passive), as haptic consoles do with their
// operator-presence input; this detector stands in where no such input exists (the sigma.7's is the clutch button,
// which the operator may keep pressed when letting go).
//
// Real time: Update() is noexcept and allocation-free.

#include "src/core/pose.h"

namespace robossis::teleop {

struct LetGoConfig {
  double device_mass_kg = 0.2;     // [assumed] the sigma.7's translational mass at the handle
  double mass_ratio = 1.5;         // [assumed] apparent mass below 1.5 × the device's: nobody holds it
  double min_force_n = 1.0;        // [assumed] below this the acceleration says nothing about the mass
  // [assumed] that long without a break before the let-go is believed: one 1 kHz tick, because the passivity
  // controller cuts the load the tick after the hand let go (the device then moves along a load whose energy is
  // spent) and no force is left to judge the mass by; on hardware the velocity's noise needs a longer window or the
  // operator-presence input.
  double confirm_s = 0.001;
  double rest_damping_n_s_per_m = 10;  // [assumed] the damper once let go: the device (0.2 kg) settles in ~0.1 s
  void Validate() const;           // throws std::invalid_argument naming the field
};

class LetGoDetector {
 public:
  explicit LetGoDetector(const LetGoConfig& config);
  // One sample: the force the device displayed over the last dt and the device's velocity before and after it
  // (linear, in O). True from the sample the let-go is believed until Reset().
  bool Update(const Eigen::Vector3d& force_O, const Eigen::Vector3d& v_before_O, const Eigen::Vector3d& v_after_O,
              double dt) noexcept;
  void Reset() noexcept;  // the operator took the device again (the clutch pressed anew)
  bool let_go() const noexcept { return let_go_; }
  const LetGoConfig& config() const noexcept { return config_; }

 private:
  LetGoConfig config_;
  double free_s_ = 0;
  bool let_go_ = false;
};

}  // namespace robossis::teleop
