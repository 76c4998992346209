#include "haptics/rendering/force_rate_shaper.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace robossis::haptics {

namespace {

void LimitNorm(Eigen::Vector3d& v, double max_norm) noexcept {
  const double n = v.norm();
  if (n > max_norm) v *= max_norm / n;
}

}  // namespace

ForceRateShaper::ForceRateShaper(double k_n_per_m, double max_force_n, double dt_s,
                                 const ForceRateShaperParams& params)
    : k_(k_n_per_m), max_force_n_(max_force_n), dt_s_(dt_s), params_(params) {
  if (!(k_n_per_m > 0) || !(max_force_n > 0) || !(dt_s > 0) || !(params.max_rate_n_per_s >= 0) ||
      !(params.free_space_force_n >= 0) || !(params.exit_speed_margin >= 1)) {
    throw std::invalid_argument(
        "force-rate shaper: expected a positive stiffness, force cap and tick, a rate and a free-space force >= 0 and "
        "an exit speed margin >= 1");
  }
}

double ForceRateShaper::Potential(double offset_m) const noexcept {
  const double r_s = max_force_n_ / k_;
  if (offset_m <= r_s) return 0.5 * k_ * offset_m * offset_m;
  return max_force_n_ * (offset_m - r_s) + 0.5 * k_ * r_s * r_s;
}

Eigen::Vector3d ForceRateShaper::SpringForce(const Eigen::Vector3d& offset_m) const noexcept {
  Eigen::Vector3d f = k_ * offset_m;
  LimitNorm(f, max_force_n_);
  return f;
}

double ForceRateShaper::DamperStrength(const Eigen::Vector3d& v, double nominal, double max_damping,
                                      double max_change_n) const noexcept {
  const double v2 = v.squaredNorm();
  if (v2 < 1e-12) return nominal;
  // |−b·v − D_prev| <= max_change: b between the roots of v²·b² + 2·(D_prev·v)·b + |D_prev|² − max_change².
  const double half_b = damper_previous_.dot(v) / v2;
  const double discriminant = half_b * half_b - (damper_previous_.squaredNorm() - max_change_n * max_change_n) / v2;
  if (discriminant < 0) return std::clamp(-half_b, 0.0, max_damping);  // out of reach: the nearest force
  const double lo = std::max(0.0, -half_b - std::sqrt(discriminant));
  const double hi = std::min(max_damping, -half_b + std::sqrt(discriminant));
  if (lo > hi) return std::clamp(-half_b, 0.0, max_damping);
  return std::clamp(nominal, lo, hi);
}

Eigen::Vector3d ForceRateShaper::Toward(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                                        double budget_j) const noexcept {
  const double phi_from = Potential(from.norm());
  if (Potential(to.norm()) - phi_from <= budget_j) return to;
  // The potential along the segment is convex and within the budget at `from`: bisection on the fraction.
  double lo = 0, hi = 1;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (Potential((from + mid * (to - from)).norm()) - phi_from <= budget_j ? lo : hi) = mid;
  }
  return from + lo * (to - from);
}

Eigen::Vector3d ForceRateShaper::Shape(const Eigen::Vector3d& p_HC, const Eigen::Vector3d& v_HC,
                                       const Eigen::Vector3d& q_target, double damping_ns_per_m, bool inside,
                                       double entry_s) noexcept {
  applied_damping_ = damping_ns_per_m;
  const Eigen::Vector3d target_offset = q_target - p_HC;
  if (!enabled()) return k_ * target_offset - damping_ns_per_m * v_HC;  // eq. 18
  const double v2 = v_HC.squaredNorm();
  const double max_damping = std::max(damping_ns_per_m, params_.max_damping_ns_per_m);
  if (!started_) {  // no history: the target itself
    started_ = true;
    q_ = q_target;
    tank_j_ = 0;
    damper_previous_ = -damping_ns_per_m * v_HC;
    f_previous_ = SpringForce(target_offset) + damper_previous_;
    LimitNorm(f_previous_, max_force_n_);
    return f_previous_;
  }
  const double step_n = params_.max_rate_n_per_s * dt_s_;

  // 0. The damper −b·v: the wall law's b, or in contact the b nearest to it that changes the damper's force by at
  //    most half a step (it steps with the velocity: when the hand stops short, and as it grows with the depth under
  //    a fast hand). A damper of any strength b >= 0 along the velocity only dissipates.
  applied_damping_ = inside ? damping_ns_per_m : DamperStrength(v_HC, damping_ns_per_m, max_damping, 0.5 * step_n);
  const Eigen::Vector3d damper = -applied_damping_ * v_HC;
  const Eigen::Vector3d hold = q_ - p_HC;  // the attachment where it was: the hand's motion alone loaded it
  const double depth = target_offset.norm();
  // The hand's speed toward the inside (along the target's pull): > 0 when it leaves the wall.
  const double v_out = depth > 0 ? v_HC.dot(target_offset / depth) : 0.0;

  // 1. The goal: the target's force. For a leaving hand, along the target's direction, no more than the part of
  //    the spring it holds along it: the target's plateau (a saturated target) is not kept up with energy the
  //    unloading will need, a sideways lag of the attachment is not kept as a drag, and a hand that passed the
  //    attachment is not pulled out.
  Eigen::Vector3d goal = SpringForce(target_offset);
  if (v_out > 0) goal *= std::clamp(SpringForce(hold).dot(target_offset / depth) / goal.norm(), 0.0, 1.0);
  // Toward the goal, within one step of the force displayed last tick (the damper's share included).
  const Eigen::Vector3d repeat = f_previous_ - damper;  // the spring force that repeats last tick's total
  Eigen::Vector3d f = goal;
  const Eigen::Vector3d change = f - repeat;
  if (change.norm() > step_n) f = repeat + (step_n / change.norm()) * change;
  LimitNorm(f, max_force_n_);

  // 2. The attachment that displays a spring force: at force/k below saturation; saturated, no deeper than it was
  //    or than the target (a deeper attachment would store energy the plateau did not take from the hand).
  const auto offset_for = [&](const Eigen::Vector3d& force) -> Eigen::Vector3d {
    const double n = force.norm();
    if (n < max_force_n_ * (1 - 1e-12)) return force / k_;
    return (force / n) * std::max(max_force_n_ / k_, std::min(hold.norm(), depth));
  };

  // 3. Energy: loading the spring beyond `hold` takes from the tank, never more than it holds. Two shares: what
  //    continuity needs (the spring nearest to the one the hand holds that keeps the force within the step) may
  //    use the whole tank; going on toward the goal (restoring a wall a fast hand pushed in) only what is left above
  //    a reserve: the energy for the spring to take up the whole damper force at once (a hand stopped short by the
  //    device's own stop takes the damper's force away in one tick).
  const Eigen::Vector3d hold_force = SpringForce(hold);
  Eigen::Vector3d f_continuity = hold_force;
  if (const Eigen::Vector3d away = hold_force - repeat; away.norm() > step_n) {
    f_continuity = repeat + (step_n / away.norm()) * away;
  }
  const double phi_hold = Potential(hold.norm());
  Eigen::Vector3d offset = Toward(hold, offset_for(f_continuity), tank_j_);
  double phi = Potential(offset.norm());
  const double reserve_j = Potential(offset.norm() + damper.norm() / k_) - phi;
  offset = Toward(offset, offset_for(f), std::max(0.0, tank_j_ - (phi - phi_hold) - reserve_j));
  phi = Potential(offset.norm());
  tank_j_ = std::max(0.0, tank_j_ - (phi - phi_hold));
  q_ = p_HC + offset;
  const Eigen::Vector3d spring = SpringForce(offset);

  // 4. Where the energy kept the spring from its share, the damper's strength that brings the whole force nearest
  //    to last tick's.
  Eigen::Vector3d total = spring + damper;
  if ((total - f_previous_).norm() > step_n && v2 > 1e-12 && !inside) {
    applied_damping_ = std::clamp(-(f_previous_ - spring).dot(v_HC) / v2, 0.0, max_damping);
    total = spring - applied_damping_ * v_HC;
  }
  // 5. No phantom wall: inside the region the force, spring and damper, is at most free_space_force_n; outside,
  //    at most what can unload before the hand may be inside (entry_s, sooner by the margin). Spring and damper
  //    shrink by one factor (each then only dissipates more); outside, never by more than the rate allows (where
  //    the entry came sooner than foreseen, the bound dropped at once).
  Eigen::Vector3d spring_shown = spring;
  double bound_n = max_force_n_;
  if (inside) {
    bound_n = params_.free_space_force_n;
  } else if (entry_s < kNever) {
    bound_n = params_.free_space_force_n + params_.max_rate_n_per_s * entry_s / params_.exit_speed_margin;
  }
  if (const double total_n = total.norm(); total_n > bound_n) {
    double scale = bound_n / total_n;
    if (!inside) {
      // |s·total − f_previous| <= step for s in [s_lo, s_hi] (a quadratic in s).
      const double a = total_n * total_n, half_b = total.dot(f_previous_);
      const double c = f_previous_.squaredNorm() - step_n * step_n;
      const double discriminant = half_b * half_b - a * c;
      if (discriminant < 0) {
        scale = std::max(scale, half_b / a);  // out of reach: no smaller than the nearest
      } else {
        scale = std::clamp(scale, (half_b - std::sqrt(discriminant)) / a, (half_b + std::sqrt(discriminant)) / a);
      }
      scale = std::clamp(scale, 0.0, 1.0);
    }
    spring_shown *= scale;
    applied_damping_ *= scale;
    total *= scale;
    if (spring_shown.norm() < max_force_n_) {
      q_ = p_HC + spring_shown / k_;  // the attachment of the smaller spring
      tank_j_ += phi - Potential((q_ - p_HC).norm());
    }
  }
  damper_previous_ = -applied_damping_ * v_HC;
  LimitNorm(total, max_force_n_);
  f_previous_ = total;
  // The damper's dissipation over the coming tick is energy the coupling takes from the hand: it may pay for
  // loading the spring later.
  tank_j_ += applied_damping_ * v2 * dt_s_;
  if (inside && spring_shown.squaredNorm() == 0) tank_j_ = 0;  // the contact is over: nothing dissipated carries over
  return total;
}

}  // namespace robossis::haptics
