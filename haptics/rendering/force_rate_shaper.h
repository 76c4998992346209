#pragma once
// A passive limit on how fast a coupling force may change (haptics/README.md, "Mesh walls fit to drive hardware",
// the force-rate shaper).
//
// A virtual coupling F = k·(q − p_HC) to a target attachment q* (the proxy) changes by k·|Δp_HC| per tick when the
// hand moves, and by k·|Δq*| when the proxy jumps: 1.7 N per 1 kHz tick for a hand entering at 830 mm/s, 15 N when
// the proxy is released at once. The shaper displays the spring of an attachment q that follows q* only as fast as
// the displayed force may change, and moves q so that it never puts energy into the hand that the coupling has not
// dissipated first:
//   * moving q toward the hand unloads the spring (the energy goes into a tank: a slider in series with the spring);
//   * moving q away from the hand loads it, paid from the tank, never beyond it;
//   * the damper's strength is chosen in [0, max_damping_ns_per_m] so that its force stays continuous too;
//   * a hand about to be back inside the true region finds the force unloaded by then, and inside the force is at
//     most free_space_force_n (no phantom wall).
// The stored energy of the saturated spring is Φ(r) = ½·k·r² up to the saturation offset r_s = F_max/k and
// F_max·(r − r_s) + ½·k·r_s² beyond, so a saturated attachment deeper than r_s stores (and may return) only the
// work its plateau takes from the hand.
//
// Real-time: no allocation, no lock, no exception.

#include <Eigen/Core>

namespace robossis::haptics {

struct ForceRateShaperParams {
  // [assumed] The largest change of the displayed force (the damper included) per second; 0: the shaper is off.
  // 500 N/s is 0.5 N per 1 kHz tick (the hardware goal of haptics/README.md for the mesh walls).
  double max_rate_n_per_s = 0;
  // [assumed] The largest force (spring and damper) displayed while the HC pose is inside the true region: under the
  // no-phantom-wall goal of 1 N, so that a hand let in at once (its orientation, not its position, came back inside)
  // finds the force cut by as little as the goal allows.
  double free_space_force_n = 0.9;
  // [assumed] How much sooner than its first-order entry time a leaving hand is assumed to be inside when the shaper
  // plans the unloading before the boundary (the simulated hand accelerates when the wall lets go).
  double exit_speed_margin = 2.0;
  // [assumed] The strongest damper the shaper may use to keep the force from dropping faster than the rate when
  // the hand stops short (the handle meeting the sigma.7's own stop): a damper only dissipates; 100 N·s/m is half
  // the passivity controller's cap and keeps b·T/m far below the discrete damper's stability bound of 2.
  double max_damping_ns_per_m = 100;
};

class ForceRateShaper {
 public:
  // k: the coupling stiffness (N/m); max_force_n: the saturation of the spring; dt_s: the tick.
  // Throws std::invalid_argument on a non-positive stiffness, cap or tick, or negative parameters.
  ForceRateShaper(double k_n_per_m, double max_force_n, double dt_s, const ForceRateShaperParams& params);

  bool enabled() const noexcept { return params_.max_rate_n_per_s > 0; }
  // Forgets the attachment and the tank: the next Shape starts from the target with no force history.
  void Reset() noexcept { started_ = false; }

  // An entry time for a hand that is not approaching the region.
  static constexpr double kNever = 1e300;

  // One tick. p_HC, v_HC: the hand's position and velocity; q_target: the target attachment (the proxy position);
  // damping_ns_per_m: the damper of the wall law this tick (c_f times its weight); inside: the HC pose is inside the
  // true region; entry_s: when it will be, at its current rate of approach (first order; kNever: not approaching).
  // Returns the force to display, spring and damper (eq. 18 with the shaped attachment); with the shaper off,
  // eq. 18 itself: k·(q_target − p_HC) − c·v_HC.
  Eigen::Vector3d Shape(const Eigen::Vector3d& p_HC, const Eigen::Vector3d& v_HC, const Eigen::Vector3d& q_target,
                        double damping_ns_per_m, bool inside, double entry_s) noexcept;

  // The damping the last Shape applied (N·s/m): the wall law's, or more where a stronger damper kept the force
  // from dropping faster than the rate (a damper of any strength only dissipates).
  double applied_damping_ns_per_m() const noexcept { return applied_damping_; }
  // The energy the coupling has dissipated and not yet returned in this contact (J).
  double tank_j() const noexcept { return tank_j_; }
  const Eigen::Vector3d& attachment() const noexcept { return q_; }

 private:
  double Potential(double offset_m) const noexcept;  // Φ above
  // The offset on the segment from → to farthest toward `to` whose potential exceeds that at `from` by at most
  // budget_j (budget_j >= 0).
  Eigen::Vector3d Toward(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double budget_j) const noexcept;
  // The damper strength in [0, max_damping] nearest to `nominal` whose force −b·v is within max_change_n of last
  // tick's damper force (or nearest to it when none is).
  double DamperStrength(const Eigen::Vector3d& v, double nominal, double max_damping,
                        double max_change_n) const noexcept;
  Eigen::Vector3d SpringForce(const Eigen::Vector3d& offset_m) const noexcept;  // sat(k·offset)

  double k_;
  double max_force_n_;
  double dt_s_;
  ForceRateShaperParams params_;
  bool started_ = false;
  Eigen::Vector3d q_ = Eigen::Vector3d::Zero();        // the displayed attachment
  Eigen::Vector3d f_previous_ = Eigen::Vector3d::Zero();  // the force displayed at the last tick (damper included)
  Eigen::Vector3d damper_previous_ = Eigen::Vector3d::Zero();  // its damper part
  double tank_j_ = 0;
  double applied_damping_ = 0;
};

}  // namespace robossis::haptics
