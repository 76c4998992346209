#include "robot/rsr_kinematics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <Eigen/LU>

namespace robossis::robot {

const char* ToString(RsrJointKind kind) {
  switch (kind) {
    case RsrJointKind::kStroke: return "stroke";
    case RsrJointKind::kRotary: return "rotary";
    case RsrJointKind::kSphericalCone: return "spherical_cone";
  }
  return "unknown";
}

const char* ToString(RsrFkStatus status) {
  switch (status) {
    case RsrFkStatus::kConverged: return "converged";
    case RsrFkStatus::kMaxIterations: return "max_iterations";
    case RsrFkStatus::kSingular: return "singular";
  }
  return "unknown";
}

const RsrLimitCheck& RsrIkResult::tightest() const {
  return *std::min_element(checks.begin(), checks.end(),
                           [](const RsrLimitCheck& a, const RsrLimitCheck& b) { return a.margin < b.margin; });
}

RsrIkResult CalcInverseKinematics(const RsrModel& model, const Eigen::Isometry3d& X_FM) noexcept {
  const RsrLimits& lim = model.limits();
  const Eigen::Vector3d z_M = X_FM.linear().col(2);  // moving-ring normal in F
  RsrIkResult out;
  out.feasible = true;
  for (int i = 0; i < kNumArms; ++i) {
    // eq. 5: leg vector d_i = p + R b_i - a_i.
    const Eigen::Vector3d leg = X_FM * model.p_MB(i) - model.p_FA(i);
    const double d = leg.norm();  // eq. 6
    const Eigen::Vector3d n = leg / d;
    // Leg components in the arm frame Rz(gamma_i): radial (u_i), tangential (z × u_i), axial (z).
    const double radial = model.rotary_axis_F(i).dot(leg);
    const double tangential = model.tangent_axis_F(i).dot(leg);
    // eq. 8: psi_i = asin(radial / d_i).
    const double psi = std::asin(std::clamp(radial / d, -1.0, 1.0));
    // eq. 7: theta_i = asin(-tangential / (d_i cos psi_i)), with d_i cos psi_i = hypot(tangential, axial). eq. 7 is
    // the physical branch (leg above the fixed-ring plane, axial > 0); below it, atan2 keeps theta continuous.
    const double d_cos_psi = std::sqrt(tangential * tangential + leg.z() * leg.z());
    const double theta = leg.z() > 0.0 ? std::asin(std::clamp(-tangential / d_cos_psi, -1.0, 1.0))
                                       : std::atan2(-tangential, leg.z());
    // Cone angle between the leg and the ring normal: asin of the cross product is exact near 0 where acos is not.
    const double cos_cone = n.dot(z_M);
    const double cone = cos_cone > 0.7 ? std::asin(std::min(n.cross(z_M).norm(), 1.0))
                                       : std::acos(std::clamp(cos_cone, -1.0, 1.0));

    out.joints.theta_rad[i] = theta;
    out.joints.d_m[i] = d;
    out.joints.psi_rad[i] = psi;
    out.joints.cone_rad[i] = cone;
    out.joints.leg_direction_F.col(i) = n;

    const double margin_low = d - lim.stroke_min_m;
    const double margin_high = lim.stroke_max_m - d;
    out.checks[3 * i + 0] = {i, RsrJointKind::kStroke, d,
                             margin_low < margin_high ? lim.stroke_min_m : lim.stroke_max_m,
                             std::min(margin_low, margin_high)};
    out.checks[3 * i + 1] = {i, RsrJointKind::kRotary, theta, std::copysign(lim.rotary_max_rad, theta),
                             lim.rotary_max_rad - std::abs(theta)};
    out.checks[3 * i + 2] = {i, RsrJointKind::kSphericalCone, cone, lim.spherical_cone_max_rad,
                             lim.spherical_cone_max_rad - cone};
  }
  for (const RsrLimitCheck& c : out.checks) out.feasible = out.feasible && c.margin >= 0.0;
  return out;
}

namespace {

// One arm's limits, given its leg (A_i to B_i, in F) and the moving ring's axis z_M (in F).
inline bool IsLegFeasible(const RsrModel& model, int i, const Eigen::Vector3d& leg, const Eigen::Vector3d& z_M) noexcept {
  const double d_sq = leg.squaredNorm();
  if (!(d_sq >= model.stroke_min_sq() && d_sq <= model.stroke_max_sq())) return false;  // also rejects NaN
  // Spherical cone: n · z_M >= cos(cone_max).
  if (leg.dot(z_M) < model.cos_cone_max() * std::sqrt(d_sq)) return false;
  // Rotary: |theta| = |atan2(-tangential, axial)| <= theta_max.
  const double axial = leg.z();
  const double tangential = model.tangent_axis_F(i).dot(leg);
  return axial > 0.0 && std::abs(tangential) <= model.tan_rotary_max() * axial;
}

}  // namespace

bool IsPoseFeasible(const RsrModel& model, const Eigen::Isometry3d& X_FM) noexcept {
  const Eigen::Vector3d z_M = X_FM.linear().col(2);
  for (int i = 0; i < kNumArms; ++i) {
    if (!IsLegFeasible(model, i, X_FM * model.p_MB(i) - model.p_FA(i), z_M)) return false;
  }
  return true;
}

PoseFeasibilityAround::PoseFeasibilityAround(const RsrModel& model, const Eigen::Isometry3d& X_FM) noexcept
    : model_(model), z_M_(X_FM.linear().col(2)) {
  for (int i = 0; i < kNumArms; ++i) {
    e_[i] = X_FM.linear() * model.p_MB(i);
    c_[i] = X_FM.translation() - model.p_FA(i);
  }
}

bool PoseFeasibilityAround::Translated(const Eigen::Vector3d& offset_F) const noexcept {
  for (int i = 0; i < kNumArms; ++i) {
    if (!IsLegFeasible(model_, i, c_[i] + e_[i] + offset_F, z_M_)) return false;
  }
  return true;
}

bool PoseFeasibilityAround::Rotated(const Eigen::Matrix3d& R_step) const noexcept {
  const Eigen::Vector3d z_M = R_step * z_M_;
  for (int i = 0; i < kNumArms; ++i) {
    if (!IsLegFeasible(model_, i, c_[i] + R_step * e_[i], z_M)) return false;
  }
  return true;
}

Matrix6d CalcJacobian(const RsrModel& model, const Eigen::Isometry3d& X_FM) noexcept {
  Matrix6d J;
  for (int i = 0; i < kNumArms; ++i) {
    const Eigen::Vector3d e = X_FM.linear() * model.p_MB(i);  // e_i = R b_i
    const Eigen::Vector3d leg = X_FM.translation() + e - model.p_FA(i);
    const double d = leg.norm();
    const Eigen::Vector3d n = leg / d;
    // t_i: the unit direction the leg sweeps when theta_i turns, u_i × n_i / |u_i × n_i|, with |u_i × n_i| = cos psi_i.
    const Eigen::Vector3d u_cross_n = model.rotary_axis_F(i).cross(n);
    const double cos_psi = u_cross_n.norm();
    const Eigen::Vector3d t = u_cross_n / cos_psi;
    // eq. 15 by reciprocal screws: d_dot_i = n_i·v + (e_i × n_i)·omega;
    // theta_dot_i = (t_i·v + (e_i × t_i)·omega) / (d_i cos psi_i).
    J.block<1, 3>(ThetaIndex(i), 0) = t.transpose() / (d * cos_psi);
    J.block<1, 3>(ThetaIndex(i), 3) = e.cross(t).transpose() / (d * cos_psi);
    J.block<1, 3>(StrokeIndex(i), 0) = n.transpose();
    J.block<1, 3>(StrokeIndex(i), 3) = e.cross(n).transpose();
  }
  return J;
}

namespace {
RsrJointVector ActuatedJoints(const RsrModel& model, const Eigen::Isometry3d& X_FM) noexcept {
  RsrJointVector q;
  for (int i = 0; i < kNumArms; ++i) {
    const Eigen::Vector3d leg = X_FM * model.p_MB(i) - model.p_FA(i);
    q[ThetaIndex(i)] = std::atan2(-model.tangent_axis_F(i).dot(leg), leg.z());  // eq. 7 (see CalcInverseKinematics)
    q[StrokeIndex(i)] = leg.norm();                                             // eq. 6
  }
  return q;
}
}  // namespace

RsrFkResult CalcForwardKinematics(const RsrModel& model, const RsrJointVector& q, const Eigen::Isometry3d& X_FM_guess,
                                  const RsrFkOptions& options) noexcept {
  RsrFkResult out;
  out.X_FM = X_FM_guess;
  if (!q.allFinite() || !X_FM_guess.matrix().allFinite()) {
    out.status = RsrFkStatus::kSingular;
    out.residual = std::numeric_limits<double>::infinity();
    return out;
  }
  for (out.iterations = 0; out.iterations <= options.max_iterations; ++out.iterations) {
    const RsrJointVector r = ActuatedJoints(model, out.X_FM) - q;
    out.residual = r.cwiseAbs().maxCoeff();
    if (out.residual <= options.tolerance) {
      out.status = RsrFkStatus::kConverged;
      return out;
    }
    if (out.iterations == options.max_iterations) break;
    const Eigen::PartialPivLU<Matrix6d> lu(CalcJacobian(model, out.X_FM));
    if (!std::isfinite(lu.rcond()) || lu.rcond() < 1e-12) {
      out.status = RsrFkStatus::kSingular;
      return out;
    }
    // Newton step on the twist: J [dp; dw] = -r; the rotation is updated on the left (w is expressed in F).
    const Vector6d step = lu.solve(-r);
    out.X_FM.translation() += step.head<3>();
    out.X_FM.linear() = RotationFromVector(step.tail<3>()) * out.X_FM.linear();
  }
  out.status = RsrFkStatus::kMaxIterations;
  return out;
}

RsrStaticsResult CalcActuatorEfforts(const RsrModel& model, const Eigen::Isometry3d& X_FM,
                                     const Vector6d& wrench_ext_F) noexcept {
  RsrStaticsResult out;
  const Eigen::PartialPivLU<Matrix6d> lu(CalcJacobian(model, X_FM).transpose());
  if (!std::isfinite(lu.rcond()) || lu.rcond() < 1e-12) {
    out.singular = true;
    return out;
  }
  const Vector6d Q = lu.solve(-wrench_ext_F);  // J^T Q = -W
  out.rotary_torque_nm = Q.head<3>();
  out.linear_force_n = Q.tail<3>();
  return out;
}

void RequireBoundedWrench(const Vector6d& w, const std::string& where) {
  static const char* const kNames[6] = {"FX_N", "FY_N", "FZ_N", "TX_NM", "TY_NM", "TZ_NM"};
  for (int k = 0; k < 6; ++k) {
    const bool force = k < 3;
    const double bound = force ? kMaxWrenchForceN : kMaxWrenchTorqueNm;
    if (!(std::abs(w[k]) <= bound)) {
      char text[160];
      std::snprintf(text, sizeof text, "%s is %g; expected a finite %s within +/-%g %s", kNames[k], w[k],
                    force ? "force" : "moment", bound, force ? "N" : "N m");
      throw std::invalid_argument(where + ": " + text);
    }
  }
}

}  // namespace robossis::robot
