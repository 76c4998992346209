#pragma once
// The time-domain passivity observer and controller on the leader's force-feedback port: the follower's load, shown
// on the hand, never gives the hand more energy than the scheme allows, whatever the link's delay, jitter or loss.
//
// The port: the hand moves at the twist [v; w] (in O), the device displays the feedback wrench [f; tau] on it (the
// part of the displayed wrench that is the follower's load: after the device caps, the walls' own share removed).
// Power into the hand P = f·v + tau·w; the hand gave energy where P < 0 (E_in), took it where P > 0 (E_out).
//
// Schemes:
//   kOff      observed, not controlled (the "uncontrolled run").
//   kClassic  the one-port time-domain passivity observer/controller of Hannaford and Ryu (IEEE Trans. Robotics and
//             Automation, 2002; Ryu, Kwon and Hannaford, IEEE Trans. Control Systems Technology, 2004): the port
//             gives back no more than it took, E_out(k) <= E_in(k).
//   kNetwork  the delay-aware network form of Artigas, Ryu, Preusche and Hirzinger (IROS 2011, "Network
//             representation and passivity of delayed teleoperation systems"; flown in KONTUR-2): the channel
//             between the two ports is a two-port observed by the energies each side sends with its packets; the
//             leader's output may not exceed the energy that entered the network at the follower, as it is received
//             (E_out(k) <= G·E_in,F(k − T), G the feedback gain: the leader displays G times the follower's power).
//             The follower side of the form (follower_passivity.h) bounds what the channel gives the environment
//             by what the hand put in. Energy that a preloaded environment (the muscles' traction) releases into
//             the follower's port still enters the network (up to G·F²/2k, 0.16 J at the hand for 517 N on
//             20.7 kN/m); the budget is therefore also capped by the port's own input, E_out(k) <= E_in(k), so that
//             the hand never gets more than it gave, as the one-port requires, at every sample.
//
// Controller: an impedance-causality passivity controller, a variable damper f -= alpha·v (Ryu et al. 2004), with
// alpha chosen to bring the output energy back to the budget in that sample; alpha is capped
// (max_damping_*: a large damper at a near-zero velocity is what makes TDPA chatter); beyond the cap the load itself
// is scaled down just enough for the sample (cut where the caps would turn it), so the bound holds at every sample.
// Chatter: the tick-by-tick controller switches its damper on and off and drops the load for single samples, a force
// rich above 25 Hz. Its action is therefore released smoothly (release_s): the damper decays exponentially from
// its last value and the load's share recovers at a bounded rate, while any sample that needs more still gets it at
// once. This follows the gradient-limited controller action of Panzirsch et al. (DLR: the passivity controller's
// force limited in its rate of change rather than switched tick by tick), in its simplest form: a decaying damper
// and a slowly restored load only ever remove energy from the port, so the bound still holds at every sample.
//
// Real time: Apply() is noexcept, allocation-free.

#include <cstdint>
#include <string>

#include "src/core/pose.h"

namespace robossis::teleop {

enum class FeedbackPassivityScheme : std::uint8_t { kOff, kClassic, kNetwork };
const char* ToString(FeedbackPassivityScheme scheme);
// "off", "classic", "network"; throws std::invalid_argument naming the value.
FeedbackPassivityScheme ParseFeedbackPassivityScheme(const char* where, const std::string& value);

struct FeedbackPassivityConfig {
  FeedbackPassivityScheme scheme = FeedbackPassivityScheme::kClassic;  // leader.yaml: the one bound at the hand
  // [assumed] the largest damper the controller adds, linear and angular: 30 N·s/m is twice the walls' eq. 18 damping
  // (15 N·s/m, paper §VI-A), 0.05 N·m·s/rad the same share of the torque cap; the sigma.7 renders both stably.
  double max_damping_n_s_per_m = 30.0;
  double max_damping_nm_s_per_rad = 0.05;
  // [assumed] The controller's action released over this time constant (0: sample by sample, the classic TDPA
  // controller, which chatters); 0.25 s brings the force's share above 25 Hz from up to 52 % to <= 7.6 % (classic)
  // and <= 5.5 % (network) in `robossis bilateral-matrix --release-s 0.25`, at a price in force tracking (README).
  double release_s = 0;
  void Validate() const;  // throws std::invalid_argument naming the field
};

// v scaled down to norm `max` if longer (the direction kept), as HapticDevice limits a force or a torque.
Eigen::Vector3d CapNorm(const Eigen::Vector3d& v, double max) noexcept;

// The displayed wall + feedback wrench within the caps (the direction kept, as HapticDevice does), and the part of
// it that is the feedback: Capped(wall + feedback) − Capped(wall).
struct CappedWrench {
  Vector6d displayed = Vector6d::Zero();  // [f; tau] in O
  Vector6d feedback = Vector6d::Zero();
};
CappedWrench CapWrench(const Vector6d& wall_O, const Vector6d& feedback_O, double max_force_n,
                       double max_torque_nm) noexcept;

struct FeedbackPortEnergies {
  double in_j = 0;   // the hand gave (P < 0)
  double out_j = 0;  // the port gave the hand (P > 0)
};

class FeedbackPassivity {
 public:
  explicit FeedbackPassivity(const FeedbackPassivityConfig& config);

  // One sample of dt: the wall wrench and the wanted feedback wrench (in O) at the hand's twist (in O);
  // remote_in_j is the energy that entered the network at the follower port, as last received, already multiplied
  // by the feedback gain (kNetwork only). Returns the displayed wrench (walls + controlled feedback, within the caps)
  // and books the energy of its feedback part.
  CappedWrench Apply(const Vector6d& wall_O, const Vector6d& feedback_O, const Vector6d& twist_O, double dt,
                     double max_force_n, double max_torque_nm, double remote_in_j) noexcept;
  // Starts the books over (the hand left, the follower stopped following: nothing crosses the port).
  void Reset() noexcept;

  const FeedbackPortEnergies& energies() const noexcept { return energies_; }
  // The observer: the scheme's budget minus the output energy (>= 0 while the port is passive in the scheme's
  // sense; for kOff the one-port observer E_in − E_out, which goes negative when the delayed feedback is active).
  double observed_j() const noexcept { return observed_j_; }
  bool active() const noexcept { return active_; }      // the controller changed the feedback this sample
  double damping() const noexcept { return damping_; }  // alpha of this sample (linear, N·s/m)

 private:
  double Budget(double remote_in_j) const noexcept;
  void Book(double power, double dt, double remote_in_j) noexcept;
  FeedbackPassivityConfig config_;
  FeedbackPortEnergies energies_;
  double observed_j_ = 0;
  bool active_ = false;
  double damping_ = 0;
  // The last sample's action (the smoothed controller starts from it).
  double alpha_held_ = 0;
  double beta_held_ = 0;
  double lambda_held_ = 1;
};

}  // namespace robossis::teleop
