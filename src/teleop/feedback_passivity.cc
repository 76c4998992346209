#include "src/teleop/feedback_passivity.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace robossis::teleop {

const char* ToString(FeedbackPassivityScheme scheme) {
  switch (scheme) {
    case FeedbackPassivityScheme::kOff: return "off";
    case FeedbackPassivityScheme::kClassic: return "classic";
    case FeedbackPassivityScheme::kNetwork: return "network";
  }
  return "unknown";
}

FeedbackPassivityScheme ParseFeedbackPassivityScheme(const char* where, const std::string& value) {
  for (const FeedbackPassivityScheme s :
       {FeedbackPassivityScheme::kOff, FeedbackPassivityScheme::kClassic, FeedbackPassivityScheme::kNetwork}) {
    if (value == ToString(s)) return s;
  }
  throw std::invalid_argument(std::string(where) + " is '" + value + "'; expected off, classic or network");
}

void FeedbackPassivityConfig::Validate() const {
  if (!(std::isfinite(max_damping_n_s_per_m) && max_damping_n_s_per_m >= 0)) {
    throw std::invalid_argument("feedback passivity: max_damping_n_s_per_m must be finite and >= 0");
  }
  if (!(std::isfinite(max_damping_nm_s_per_rad) && max_damping_nm_s_per_rad >= 0)) {
    throw std::invalid_argument("feedback passivity: max_damping_nm_s_per_rad must be finite and >= 0");
  }
  auto check = [](double v, const char* field, bool zero_allowed) {
    if (!(std::isfinite(v) && (v > 0 || (zero_allowed && v == 0)))) {
      throw std::invalid_argument(std::string("feedback passivity: ") + field + " must be finite and " +
                                  (zero_allowed ? ">= 0" : "> 0"));
    }
  };
  check(release_s, "release_s", true);
  check(reserve_j, "reserve_j", true);
  check(rise_s, "rise_s", true);
  check(rest_damping_n_s_per_m, "rest_damping_n_s_per_m", true);
  check(rest_hold_s, "rest_hold_s", true);
  check(still_m_s, "still_m_s", false);
  check(still_rad_s, "still_rad_s", false);
  check(active_tolerance_n, "active_tolerance_n", false);
  check(active_tolerance_nm, "active_tolerance_nm", false);
}

Eigen::Vector3d CapNorm(const Eigen::Vector3d& v, double max) noexcept {
  const double n = v.norm();
  return n > max ? Eigen::Vector3d(v * (max / n)) : v;
}

CappedWrench CapWrench(const Vector6d& wall_O, const Vector6d& feedback_O, double max_force_n,
                       double max_torque_nm) noexcept {
  CappedWrench c;
  c.displayed.head<3>() = CapNorm(wall_O.head<3>() + feedback_O.head<3>(), max_force_n);
  c.displayed.tail<3>() = CapNorm(wall_O.tail<3>() + feedback_O.tail<3>(), max_torque_nm);
  c.feedback.head<3>() = c.displayed.head<3>() - CapNorm(wall_O.head<3>(), max_force_n);
  c.feedback.tail<3>() = c.displayed.tail<3>() - CapNorm(wall_O.tail<3>(), max_torque_nm);
  return c;
}

namespace {

// What one sample of the port's power (W, > 0: the port gives the hand) over dt adds to the port's books.
FeedbackPortEnergies PortEnergiesOver(double power_w, double dt) {
  FeedbackPortEnergies e;
  (power_w > 0 ? e.out_j : e.in_j) = std::abs(power_w) * dt;
  return e;
}

Vector6d Damper(double alpha, double beta, const Vector6d& twist_O) {
  Vector6d d;
  d << alpha * twist_O.head<3>(), beta * twist_O.tail<3>();
  return d;
}

// f with `share` of its component along the motion u kept; below the speed `still` the component across the motion
// is faded too, wholly at rest, where the direction of the motion means nothing (a device let go and stopped would
// otherwise get the whole load back the sample its speed reaches zero).
Eigen::Vector3d Faded(const Eigen::Vector3d& f, const Eigen::Vector3d& u, double still, double share) {
  const double u2 = u.squaredNorm();
  const Eigen::Vector3d along = u2 > 0 ? Eigen::Vector3d((f.dot(u) / u2) * u) : Eigen::Vector3d::Zero();
  const double across_kept = u2 < still * still ? share + (1 - share) * u2 / (still * still) : 1.0;
  return share * along + across_kept * (f - along);
}

}  // namespace

FeedbackPassivity::FeedbackPassivity(const FeedbackPassivityConfig& config) : config_(config) { config.Validate(); }

void FeedbackPassivity::Reset() noexcept {
  energies_ = {};
  observed_j_ = 0;
  active_ = taper_active_ = false;
  damping_ = 0;
  alpha_held_ = beta_held_ = 0;
  lambda_held_ = 1;
  taper_share_ = 1;
  uncredited_j_ = 0;
  taper_alpha_ = 0;
}

double FeedbackPassivity::Budget(double remote_in_j) const noexcept {
  const double credited = energies_.in_j - uncredited_j_;
  switch (config_.scheme) {
    case FeedbackPassivityScheme::kNetwork: return std::min(remote_in_j, credited);
    case FeedbackPassivityScheme::kClassic:
    case FeedbackPassivityScheme::kOff: break;
  }
  return credited;
}

Vector6d FeedbackPassivity::Taper(const Vector6d& feedback_O, const Vector6d& twist_O, double allowed, double dt,
                                  double& alpha) noexcept {
  // Only the load's component along the motion (linear and angular apart) is faded: the component across it does
  // no work and is shown whole, as the classic controller's damper leaves it. The share falls while that component
  // would give the hand energy, and comes back while the hand pushes against it (paying for it); it applies in both
  // cases, so the force does not step when the motion reverses.
  const Eigen::Vector3d v = twist_O.head<3>(), w = twist_O.tail<3>();
  const double p_lin = feedback_O.head<3>().dot(v), p_ang = feedback_O.tail<3>().dot(w);
  const double target = p_lin > 0 || p_ang > 0 ? std::sqrt(std::min(1.0, allowed / config_.reserve_j)) : 1.0;
  const double rise = config_.rise_s > 0 ? 1 - std::exp(-dt / config_.rise_s) : 1.0;
  taper_share_ = target < taper_share_ ? target : taper_share_ + (target - taper_share_) * rise;
  Vector6d load;
  load << Faded(feedback_O.head<3>(), v, config_.still_m_s, taper_share_),
      Faded(feedback_O.tail<3>(), w, config_.still_rad_s, taper_share_);
  // The damper fades over rest_hold_s rather than vanishing with the load (a load gone slack leaves the device let go
  // coasting on its own friction).
  const double hold = config_.rest_hold_s > 0 ? std::exp(-dt / config_.rest_hold_s) : 0.0;
  alpha = std::max(p_lin > 0 ? config_.rest_damping_n_s_per_m * (1 - taper_share_) : 0.0, hold * alpha_held_);
  return load;
}

CappedWrench FeedbackPassivity::Apply(const Vector6d& wall_O, const Vector6d& feedback_O, const Vector6d& twist_O,
                                      double dt, double max_force_n, double max_torque_nm,
                                      double remote_in_j) noexcept {
  active_ = taper_active_ = false;
  damping_ = 0;
  taper_alpha_ = 0;
  if (config_.scheme == FeedbackPassivityScheme::kOff) return CapWrench(wall_O, feedback_O, max_force_n, max_torque_nm);
  // What the port may still give this sample: the budget less what it gave (never below zero: a budget that
  // shrank, e.g. a network bound received late, gives nothing now rather than taking back what was given).
  const double allowed = std::max(0.0, Budget(remote_in_j) - energies_.out_j);
  // The taper (reserve_j > 0) fades the load before the tick-by-tick controller below, which then seldom acts.
  const bool taper = config_.reserve_j > 0;
  double taper_alpha = 0;
  const Vector6d load = taper ? Taper(feedback_O, twist_O, allowed, dt, taper_alpha) : feedback_O;
  const CappedWrench uncontrolled = CapWrench(wall_O, feedback_O, max_force_n, max_torque_nm);
  CappedWrench c = taper ? CapWrench(wall_O, load, max_force_n, max_torque_nm) : uncontrolled;
  taper_active_ = Changed(c.feedback, uncontrolled.feedback);
  const double power = c.feedback.dot(twist_O);
  // The smoothed action (release_s > 0, no taper): the damper decays from its last value and the load's share
  // recovers at 1/release_s instead of both snapping back the next sample. Holding a damper longer, or the load
  // lower, only takes energy out of the port, so the bound below still holds at every sample.
  const bool smooth = !taper && config_.release_s > 0;
  const double decay = smooth ? std::exp(-dt / config_.release_s) : 0.0;
  double alpha = taper ? taper_alpha : decay * alpha_held_, beta = decay * beta_held_;
  double lambda = smooth ? std::min(1.0, lambda_held_ + dt / config_.release_s) : 1.0;
  const double v2 = twist_O.head<3>().squaredNorm(), w2 = twist_O.tail<3>().squaredNorm();
  // The power with dampers a, b and the load's share l: the capped load's power, less what the dampers and the
  // share take (the caps' turn is checked on the result).
  const double p0 = load.dot(twist_O);
  auto power_with = [&](double a, double b, double l) { return power - (1 - l) * p0 - a * v2 - b * w2; };
  double excess = power_with(alpha, beta, lambda) * dt - allowed;
  if (excess > 0) {
    // The damper, linear part first, then angular, each capped; alpha·|v|²·dt removes the excess energy.
    if (v2 > 0) {
      const double more = std::max(0.0, std::min(excess / (v2 * dt), config_.max_damping_n_s_per_m - alpha));
      alpha += more;
      excess -= more * v2 * dt;
    }
    if (w2 > 0 && excess > 0) {
      const double more = std::max(0.0, std::min(excess / (w2 * dt), config_.max_damping_nm_s_per_rad - beta));
      beta += more;
      excess -= more * w2 * dt;
    }
    // Beyond the dampers' caps, the load itself is scaled down just enough (lambda in [0, 1]): the force shrinks
    // continuously where the cap binds instead of dropping to zero, which would chatter.
    if (excess > 0 && p0 > 0) {
      lambda = std::clamp((allowed / dt + Damper(alpha, beta, twist_O).dot(twist_O)) / p0, 0.0, lambda);
    }
  }
  if (alpha > 0 || beta > 0 || lambda < 1 || (taper && taper_share_ < 1)) {
    c = CapWrench(wall_O, lambda * load - Damper(alpha, beta, twist_O), max_force_n, max_torque_nm);
    if (c.feedback.dot(twist_O) * dt > allowed) {
      // The caps turned it: no feedback this sample.
      c = CapWrench(wall_O, Vector6d::Zero(), max_force_n, max_torque_nm);
      lambda = 0;
    }
  }
  // A damper decayed below a thousandth of its cap is gone (the controller idle again).
  alpha_held_ = taper ? (taper_alpha > 1e-3 * config_.rest_damping_n_s_per_m ? taper_alpha : 0.0)
                      : alpha > 1e-3 * config_.max_damping_n_s_per_m ? alpha : 0.0;
  beta_held_ = beta > 1e-3 * config_.max_damping_nm_s_per_rad ? beta : 0.0;
  lambda_held_ = lambda;
  damping_ = alpha;
  taper_alpha_ = taper_alpha;
  active_ = Changed(c.feedback, uncontrolled.feedback);
  return c;
}

FeedbackPortEnergies FeedbackPassivity::Observe(const Vector6d& displayed_feedback_O, const Vector6d& twist_O,
                                                double dt, double remote_in_j) noexcept {
  const FeedbackPortEnergies tick = PortEnergiesOver(displayed_feedback_O.dot(twist_O), dt);
  energies_.in_j += tick.in_j;
  energies_.out_j += tick.out_j;
  // The taper's damper is a separate element: what it takes is not credited, so the budget pays for the load's own
  // power (a device let go would otherwise spend the damper's take on the load again and creep at the speed where
  // the two cancel). Never more than is left, so the observer stays >= 0.
  if (taper_alpha_ > 0) {
    uncredited_j_ += std::min(taper_alpha_ * twist_O.head<3>().squaredNorm() * dt,
                              std::max(0.0, Budget(remote_in_j) - energies_.out_j));
  }
  observed_j_ = Budget(remote_in_j) - energies_.out_j;
  return tick;
}

bool FeedbackPassivity::Changed(const Vector6d& shown, const Vector6d& uncontrolled) const noexcept {
  return (shown.head<3>() - uncontrolled.head<3>()).norm() > config_.active_tolerance_n ||
         (shown.tail<3>() - uncontrolled.tail<3>()).norm() > config_.active_tolerance_nm;
}

}  // namespace robossis::teleop
