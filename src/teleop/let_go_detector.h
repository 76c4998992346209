#pragma once
// Knows when the operator has let go of the device, from its motion alone: a device that nobody holds accelerates
// under the displayed force as its own mass does (m·a = f, in every direction), a held one as the hand and the
// device together (the hand adds its own mass and its own push). Once let go, the leader stops showing the
// follower's load and
// damps the device to rest (a damper only takes energy: the port stays passive), as haptic consoles do with their
// operator-presence input; this detector stands in where no such input exists (the sigma.7's is the clutch button,
// which the operator may keep pressed when letting go).
//
// Real time: Update() is noexcept and allocation-free.

#include "src/core/pose.h"

namespace robossis::teleop {

struct LetGoConfig {
  double device_mass_kg = 0.2;     // [assumed] the sigma.7's translational mass at the handle
  // [assumed] nobody holds it when m·a matches the displayed force within 1 − 1/1.5 of |f| (along the force: an
  // apparent mass 0.75-1.5 × the device's)
  double mass_ratio = 1.5;
  double min_force_n = 1.0;        // [assumed] below this the acceleration says nothing about the mass
  // [assumed] that long without a break before the let-go is believed: 10 ms, because the passivity controller's
  // taper fades the load over tens of milliseconds after the hand let go, leaving a force to judge the mass by, and a
  // single tick is fooled by the held hand's own decelerations (`robossis bilateral-matrix --let-go-detector
  // --let-go-confirm-s 0.001`: false let-gos with classic at 50 ms; none at 0.01). The tick-by-tick controller
  // (reserve_j 0) cuts the load the tick after the let-go and needs one tick (0.001); on hardware the velocity's noise
  // needs a longer window or the operator-presence input.
  double confirm_s = 0.01;
  // [assumed] a sample is not judged where the controller's damper makes more than half the displayed force
  double max_damper_share = 0.5;
  double rest_damping_n_s_per_m = 10;  // [assumed] the damper once let go: the device (0.2 kg) settles in ~0.1 s
  void Validate() const;           // throws std::invalid_argument naming the field
};

class LetGoDetector {
 public:
  explicit LetGoDetector(const LetGoConfig& config);
  // One sample: the force the device displayed over the last dt, the device's velocity before and after it (linear,
  // in O), and the passivity controller's damper in that force (FeedbackPassivity::damping(), N·s/m). True from the
  // sample the let-go is believed until Reset(). A sample whose force is mostly that damper's (max_damper_share) is
  // not judged and breaks the confirmation: under a force proportional to the velocity a device's mass cannot be
  // told from its motion (a held hand's own damping b makes hand and device, M, decelerate as the device alone
  // would, (alpha + b)/M = alpha/m, at b ~ 2.5 alpha: `robossis bilateral-matrix --let-go-detector`, network, 517 N,
  // 0 ms: a false let-go at 1.56 s under the taper's damper alone). A device let go while that damper acts is brought
  // to rest by it (feedback_passivity.h).
  bool Update(const Eigen::Vector3d& force_O, const Eigen::Vector3d& v_before_O, const Eigen::Vector3d& v_after_O,
              double dt, double damping_n_s_per_m) noexcept;
  void Reset() noexcept;  // the operator took the device again (the clutch pressed anew)
  bool let_go() const noexcept { return let_go_; }
  const LetGoConfig& config() const noexcept { return config_; }

 private:
  LetGoConfig config_;
  double free_s_ = 0;
  bool let_go_ = false;
};

}  // namespace robossis::teleop
