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
// Chatter, and where it comes from: without a controller the displayed force has <= 5 % of its power above 25 Hz in
// every cell of `robossis bilateral-matrix` (the 1 kHz set-points seen through delay, jitter and loss, and the hand's
// grasp stiffness, add little); the tick-by-tick controller puts 7-52 % there at >= 25 ms: at the budget's edge it
// cuts the load for a sample as the sign of the power flips, and switches its damper on and off tick by tick.
// Two smoothings, each only ever taking energy from the port, so the bound still holds at every sample:
//   - the energy-reserve taper (reserve_j, the default): the load's component along the hand's motion, while it would
//     give the hand energy, is scaled by the square root of the energy the port may still give over a reserve, so the
//     output energy approaches the budget smoothly instead of running into it; the load's share comes back with a time
//     constant once the hand pays again, and the share it cuts is shown as a damper (rest_damping_n_s_per_m) that is
//     not credited to the budget, so that a device the operator let go is brought to rest. A passivity-preserving
//     smoothing of the controller's action in the spirit of Ryu and Preusche's reference energy following (ICRA 2007:
//     the observed energy is made to follow a smooth reference rather than being reset to zero sample by sample) and of
//     Chawda and O'Malley's gradient-limited TDPA (the controller's force limited in its rate of change). Share above
//     25 Hz <= 2.7 %.
//   - the released action (release_s, when reserve_j is 0): the damper decays exponentially from its last value and
//     the load's share recovers at a bounded rate (<= 7.6 %, but the load is held down).
//
// Real time: Apply() and Observe() are noexcept, allocation-free.

#include <cmath>
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
  // [assumed] With reserve_j 0: the controller's action released over this time constant (0: sample by sample, the
  // classic TDPA controller, which chatters); 0.25 s brings the force's share above 25 Hz from up to 52 % to <= 7.6 %
  // (classic) and <= 5.5 % (network) in `robossis bilateral-matrix --reserve-j 0 --release-s 0.25`, at a price in
  // force tracking (README).
  double release_s = 0;
  // The energy-reserve taper (reserve_j > 0; release_s then unused). While the load's component along the hand's motion
  // would give the hand energy, its share falls to sqrt(min(1, E_left/reserve_j)), E_left what the port may still give:
  // the force fades as the budget empties instead of being cut at zero. Continuous in the (continuous) remaining
  // energy, it puts no step into the force, and the output energy only approaches the budget, so the tick-by-tick
  // controller underneath seldom acts. The square root ends the fade in finite time (a linear share leaves a device let
  // go creeping at the speed where the load and the damper below cancel, the remaining energy decaying only
  // hyperbolically). [assumed] 0.01 J, a fifth of what the hand pays pressing 15 mm into the 20 kN/m wall at gain 0.025
  // (`robossis bilateral-matrix`: 0.01, 0.03 and 0.1 J keep the share above 25 Hz at <= 2.7, 3.3 and 5.7 %; the
  // smallest fades the least load).
  double reserve_j = 0.01;
  // [assumed] With the taper, the load's share comes back toward 1 with this time constant once the hand gives
  // energy again (a step back to the full load would chatter): 20 ms puts the step's power below 8 Hz.
  double rise_s = 0.02;
  // With the taper, the share of the load it cuts is shown as a damper up to this much (N·s/m): the hand moving
  // with an exhausted load is slowed, so a device let go comes to rest rather than coasting on its own friction.
  // A damper only takes energy; what it takes is not credited to the budget (a device let go would otherwise spend
  // it on the load again and creep). [assumed] 10 N·s/m: the 0.2 kg device settles in ~0.02 s, below the walls'
  // 15 N·s/m that the hand already feels.
  double rest_damping_n_s_per_m = 10;
  // [assumed] The taper's damper fades with this time constant once the load stops pushing the hand along its motion
  // (0.1 s: a device let go stops in the first ~0.05 s; a held hand feels it fade within a tenth of a second).
  double rest_hold_s = 0.1;
  // [assumed] Below these speeds (the harness's "at rest", 1 mm/s, and 0.01 rad/s) the taper fades the load's
  // component across the motion too, wholly at standstill: there the direction of the motion means nothing.
  double still_m_s = 0.001;
  double still_rad_s = 0.01;
  // [assumed] The controller counts as acting on a sample (active(), summary.json tdpa_active_fraction) when it
  // changed the displayed force or torque by more than these: a hundredth of the let-go detector's 1 N, and the same
  // share of the device's 0.3 N·m torque cap (the taper's share below 1 on a load across the motion changes nothing).
  double active_tolerance_n = 0.01;
  double active_tolerance_nm = 0.0002;
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

// The controller and the observer are two calls, as the device sits between them: Apply() decides the wrench to
// write, Observe() books what the device then displayed (its own caps, or an output it zeroed, can show less than
// was asked), so the budget is spent on the force the hand actually felt.
class FeedbackPassivity {
 public:
  explicit FeedbackPassivity(const FeedbackPassivityConfig& config);

  // One sample of dt: the wall wrench and the wanted feedback wrench (in O) at the hand's twist (in O);
  // remote_in_j is the energy that entered the network at the follower port, as last received, already multiplied
  // by the feedback gain (kNetwork only). Returns the wrench to display (walls + controlled feedback, within the
  // caps) and its feedback part. Books nothing.
  CappedWrench Apply(const Vector6d& wall_O, const Vector6d& feedback_O, const Vector6d& twist_O, double dt,
                     double max_force_n, double max_torque_nm, double remote_in_j) noexcept;
  // The observer: books the feedback part of what the device displayed over the sample at the hand's twist (zero
  // where the device zeroed its output), with the same remote_in_j as Apply(). Returns the sample's energies.
  FeedbackPortEnergies Observe(const Vector6d& displayed_feedback_O, const Vector6d& twist_O, double dt,
                               double remote_in_j) noexcept;
  // Starts the books over (the hand left, the follower stopped following: nothing crosses the port).
  void Reset() noexcept;

  const FeedbackPortEnergies& energies() const noexcept { return energies_; }
  // The observer: the scheme's budget minus the output energy (>= 0 while the port is passive in the scheme's
  // sense; for kOff the one-port observer E_in − E_out, which goes negative when the delayed feedback is active).
  double observed_j() const noexcept { return observed_j_; }
  // The controller (taper, dampers, cut) changed the displayed wrench by more than the tolerances this sample.
  bool active() const noexcept { return active_; }
  // The taper alone changed the load by more than the tolerances this sample.
  bool taper_active() const noexcept { return taper_active_; }
  double damping() const noexcept { return damping_; }  // alpha of this sample (linear, N·s/m)

 private:
  double Budget(double remote_in_j) const noexcept;
  // The shown feedback differs from the uncontrolled one by more than the tolerances.
  bool Changed(const Vector6d& shown, const Vector6d& uncontrolled) const noexcept;
  // The load with the taper's share of its working part, and the taper's damper (reserve_j > 0).
  Vector6d Taper(const Vector6d& feedback_O, const Vector6d& twist_O, double allowed, double dt,
                 double& alpha) noexcept;
  FeedbackPassivityConfig config_;
  FeedbackPortEnergies energies_;
  double observed_j_ = 0;
  bool active_ = false;
  bool taper_active_ = false;
  double damping_ = 0;
  // The last sample's action (the smoothed controller starts from it).
  double alpha_held_ = 0;
  double beta_held_ = 0;
  double lambda_held_ = 1;
  // The taper's share of the load's working part, and what its damper took from the hand (in the books, in_j, but
  // not in the budget).
  double taper_share_ = 1;
  double uncredited_j_ = 0;
  double taper_alpha_ = 0;  // the taper's damper of the last Apply(), for Observe()
};

}  // namespace robossis::teleop
