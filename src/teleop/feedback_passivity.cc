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
  if (!(std::isfinite(release_s) && release_s >= 0)) {
    throw std::invalid_argument("feedback passivity: release_s must be finite and >= 0");
  }
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

Vector6d Damper(double alpha, double beta, const Vector6d& twist_O) {
  Vector6d d;
  d << alpha * twist_O.head<3>(), beta * twist_O.tail<3>();
  return d;
}

}  // namespace

FeedbackPassivity::FeedbackPassivity(const FeedbackPassivityConfig& config) : config_(config) { config.Validate(); }

void FeedbackPassivity::Reset() noexcept {
  energies_ = {};
  observed_j_ = 0;
  active_ = false;
  damping_ = 0;
  alpha_held_ = beta_held_ = 0;
  lambda_held_ = 1;
}

double FeedbackPassivity::Budget(double remote_in_j) const noexcept {
  switch (config_.scheme) {
    case FeedbackPassivityScheme::kNetwork: return std::min(remote_in_j, energies_.in_j);
    case FeedbackPassivityScheme::kClassic:
    case FeedbackPassivityScheme::kOff: break;
  }
  return energies_.in_j;
}

CappedWrench FeedbackPassivity::Apply(const Vector6d& wall_O, const Vector6d& feedback_O, const Vector6d& twist_O,
                                      double dt, double max_force_n, double max_torque_nm,
                                      double remote_in_j) noexcept {
  active_ = false;
  damping_ = 0;
  CappedWrench c = CapWrench(wall_O, feedback_O, max_force_n, max_torque_nm);
  double power = c.feedback.dot(twist_O);
  if (config_.scheme == FeedbackPassivityScheme::kOff) {
    Book(power, dt, remote_in_j);
    return c;
  }
  // The smoothed action (release_s > 0): the damper decays from its last value and the load's share recovers at
  // 1/release_s instead of both snapping back the next sample. Holding a damper longer, or the load lower, only takes
  // energy out of the port, so the bound below still holds at every sample.
  const bool smooth = config_.release_s > 0;
  const double decay = smooth ? std::exp(-dt / config_.release_s) : 0.0;
  double alpha = decay * alpha_held_, beta = decay * beta_held_;
  double lambda = smooth ? std::min(1.0, lambda_held_ + dt / config_.release_s) : 1.0;
  // What the port may still give this sample: the budget less what it gave (never below zero: a budget that
  // shrank, e.g. a network bound received late, gives nothing now rather than taking back what was given).
  const double allowed = std::max(0.0, Budget(remote_in_j) - energies_.out_j);
  const double v2 = twist_O.head<3>().squaredNorm(), w2 = twist_O.tail<3>().squaredNorm();
  // The power with dampers a, b and the load's share l: the capped load's power, less what the dampers and the
  // share take (the caps' turn is checked on the result).
  const double p0 = feedback_O.dot(twist_O);
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
  if (alpha > 0 || beta > 0 || lambda < 1) {
    active_ = true;
    c = CapWrench(wall_O, lambda * feedback_O - Damper(alpha, beta, twist_O), max_force_n, max_torque_nm);
    power = c.feedback.dot(twist_O);
    if (power * dt > allowed) {
      // The caps turned it: no feedback this sample.
      c = CapWrench(wall_O, Vector6d::Zero(), max_force_n, max_torque_nm);
      power = 0;
      lambda = 0;
    }
  }
  // A damper decayed below a thousandth of its cap is gone (the controller idle again).
  alpha_held_ = alpha > 1e-3 * config_.max_damping_n_s_per_m ? alpha : 0.0;
  beta_held_ = beta > 1e-3 * config_.max_damping_nm_s_per_rad ? beta : 0.0;
  lambda_held_ = lambda;
  damping_ = alpha;
  Book(power, dt, remote_in_j);
  return c;
}

void FeedbackPassivity::Book(double power, double dt, double remote_in_j) noexcept {
  if (power > 0) energies_.out_j += power * dt;
  else energies_.in_j -= power * dt;
  observed_j_ = Budget(remote_in_j) - energies_.out_j;
}

}  // namespace robossis::teleop
