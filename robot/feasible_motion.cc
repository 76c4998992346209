#include "robot/feasible_motion.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace robossis::robot {

const char* ToString(FeasibleMotionStatus status) {
  switch (status) {
    case FeasibleMotionStatus::kTracked: return "tracked";
    case FeasibleMotionStatus::kConstrained: return "constrained";
    case FeasibleMotionStatus::kHeld: return "held";
    case FeasibleMotionStatus::kInvalidInput: return "invalid_input";
    case FeasibleMotionStatus::kStartInfeasible: return "start_infeasible";
  }
  return "unknown";
}

void FeasibleMotionConfig::Validate() const {
  const auto require = [](bool ok, const char* field, double value, const char* expected) {
    if (!ok) {
      throw std::invalid_argument(std::string("feasible-motion guard: ") + field + " is " + std::to_string(value) +
                                  "; expected " + expected);
    }
  };
  require(std::isfinite(rotation_length_m) && rotation_length_m > 0, "rotation_length_m", rotation_length_m,
          "a finite length > 0");
  require(std::isfinite(stroke_buffer_m) && stroke_buffer_m >= 0 && stroke_buffer_m < 1e-3, "stroke_buffer_m",
          stroke_buffer_m, "0 <= buffer < 1 mm");
  require(std::isfinite(angle_buffer_rad) && angle_buffer_rad >= 0 && angle_buffer_rad < 1e-2, "angle_buffer_rad",
          angle_buffer_rad, "0 <= buffer < 0.01 rad");
  require(std::isfinite(approach_gain) && approach_gain > 0 && approach_gain <= 1, "approach_gain", approach_gain,
          "0 < eta <= 1");
  require(max_relinearizations >= 1 && max_relinearizations <= 16, "max_relinearizations", max_relinearizations,
          "1..16");
  require(max_halvings >= 0 && max_halvings <= 40, "max_halvings", max_halvings, "0..40");
}

Eigen::Isometry3d ApplyTwistStep(const Eigen::Isometry3d& X_FM, const Vector6d& step) noexcept {
  Eigen::Isometry3d X = X_FM;
  X.translation() += step.head<3>();
  X.linear() = RotationFromVector(step.tail<3>()) * X_FM.linear();  // the rotation vector is expressed in F
  return X;
}

Vector6d TwistStepBetween(const Eigen::Isometry3d& X_a, const Eigen::Isometry3d& X_b) noexcept {
  Vector6d step;
  step.head<3>() = X_b.translation() - X_a.translation();
  const Eigen::Matrix3d R_ab_F = X_b.linear() * X_a.linear().transpose();
  step.tail<3>() = RotationVector(R_ab_F);
  return step;
}

LinearizedLimits CalcLinearizedLimits(const RsrModel& model, const Eigen::Isometry3d& X_FM,
                                      const FeasibleMotionConfig& config) noexcept {
  const RsrLimits& lim = model.limits();
  const Matrix6d J = CalcJacobian(model, X_FM);  // eq. 15
  const Eigen::Vector3d z_M = X_FM.linear().col(2);
  const double cone_buffer = std::cos(lim.spherical_cone_max_rad - config.angle_buffer_rad) -
                             std::cos(lim.spherical_cone_max_rad);
  LinearizedLimits out;
  for (int i = 0; i < kNumArms; ++i) {
    const Eigen::Vector3d e = X_FM.linear() * model.p_MB(i);  // e_i = R b_i
    const Eigen::Vector3d leg = X_FM.translation() + e - model.p_FA(i);  // eq. 5
    const double d = leg.norm();                                         // eq. 6
    const Eigen::Vector3d n = leg / d;
    const double theta = std::atan2(-model.tangent_axis_F(i).dot(leg), leg.z());  // eq. 7 (continued by atan2)
    const int r = 5 * i;
    // Strokes: rows of J (d_dot_i = n_i·v + (e_i × n_i)·omega, eq. 15).
    out.gradient.row(r + 0) = J.row(StrokeIndex(i));
    out.margin[r + 0] = d - lim.stroke_min_m;
    out.gradient.row(r + 1) = -J.row(StrokeIndex(i));
    out.margin[r + 1] = lim.stroke_max_m - d;
    out.buffer[r + 0] = out.buffer[r + 1] = config.stroke_buffer_m;
    // Rotary joints: rows of J (eq. 15).
    out.gradient.row(r + 2) = J.row(ThetaIndex(i));
    out.margin[r + 2] = theta + lim.rotary_max_rad;
    out.gradient.row(r + 3) = -J.row(ThetaIndex(i));
    out.margin[r + 3] = lim.rotary_max_rad - theta;
    out.buffer[r + 2] = out.buffer[r + 3] = config.angle_buffer_rad;
    // Spherical cone: g = n_i · z_M - cos(cone_max). With leg_dot = v + omega × e_i and z_M_dot = omega × z_M,
    // d(n·z)/dt = w·v / d + ((e_i × w) / d + z_M × n)·omega, where w = z_M - (n·z_M) n.
    const double cos_cone = n.dot(z_M);
    const Eigen::Vector3d w = z_M - cos_cone * n;
    out.gradient.block<1, 3>(r + 4, 0) = (w / d).transpose();
    out.gradient.block<1, 3>(r + 4, 3) = (e.cross(w) / d + z_M.cross(n)).transpose();
    out.margin[r + 4] = cos_cone - std::cos(lim.spherical_cone_max_rad);
    out.buffer[r + 4] = cone_buffer;
  }
  return out;
}

FeasibleMotionGuard::FeasibleMotionGuard(const RsrModel& model, const FeasibleMotionConfig& config)
    : model_(model), config_(config) {
  config_.Validate();
}

namespace {
bool IsFinitePose(const Eigen::Isometry3d& X) noexcept { return X.matrix().allFinite(); }
}  // namespace

FeasibleMotionResult FeasibleMotionGuard::Step(const Eigen::Isometry3d& X_FM_current,
                                               const Eigen::Isometry3d& X_FM_wanted) const noexcept {
  FeasibleMotionResult out;
  out.X_FM = X_FM_current;
  if (!IsFinitePose(X_FM_current)) {
    out.status = FeasibleMotionStatus::kInvalidInput;
    return out;
  }
  const RsrIkResult ik_current = CalcInverseKinematics(model_, X_FM_current);
  out.tightest = ik_current.tightest();
  if (!ik_current.feasible) {
    out.status = FeasibleMotionStatus::kStartInfeasible;
    return out;
  }
  if (!IsFinitePose(X_FM_wanted)) {
    out.status = FeasibleMotionStatus::kInvalidInput;
    return out;
  }

  // Scaled variables y = S x, S = diag(1, 1, 1, L, L, L): |y - y_wanted| is the weighted tracking error.
  const double L = config_.rotation_length_m;
  Vector6d scale;
  scale << 1, 1, 1, L, L, L;

  Eigen::Isometry3d X = X_FM_current;
  bool reached_wanted = false;
  bool constrained = false;
  for (int pass = 0; pass < config_.max_relinearizations; ++pass) {
    const LinearizedLimits lin = CalcLinearizedLimits(model_, X, config_);
    ProjectionQp qp;
    qp.num_constraints = kNumLinearizedLimits;
    for (int k = 0; k < kNumLinearizedLimits; ++k) {
      qp.A.row(k) = lin.gradient.row(k).cwiseQuotient(scale.transpose());
      // Vector-field inequality: grad g · x >= -eta (g - buffer). Inside the buffer (g < buffer) the limit may not
      // be approached further, but is not required to recede: x = 0 always stays feasible.
      qp.b[k] = -config_.approach_gain * std::max(lin.margin[k] - lin.buffer[k], 0.0);
    }
    const Vector6d x_wanted = TwistStepBetween(X, X_FM_wanted);
    const QpVector y_wanted = x_wanted.cwiseProduct(scale);
    const QpResult qp_result = SolveProjectionQp(qp, y_wanted, QpVector::Zero());
    out.qp_iterations += qp_result.iterations;
    out.active_limits = qp_result.active;
    if (qp_result.status == QpStatus::kStartInfeasible) break;
    const bool unconstrained = qp_result.status == QpStatus::kOptimal && qp_result.active == 0;
    constrained = constrained || !unconstrained;

    // The exact IK decides: the QP's step, then halves of it, until one passes.
    Vector6d x = qp_result.y.cwiseQuotient(scale);
    Eigen::Isometry3d candidate = unconstrained ? X_FM_wanted : ApplyTwistStep(X, x);
    bool accepted = false;
    for (int h = 0; h <= config_.max_halvings; ++h) {
      if (h > 0) {
        x *= 0.5;
        candidate = ApplyTwistStep(X, x);
        ++out.halvings;
        constrained = true;
      }
      const RsrIkResult ik = CalcInverseKinematics(model_, candidate);
      if (ik.feasible) {
        accepted = true;
        out.tightest = ik.tightest();
        break;
      }
    }
    if (!accepted) break;
    X = candidate;
    if (unconstrained && out.halvings == 0) {
      reached_wanted = true;
      break;
    }
    // Nothing left worth another linearisation (well below a nanometre / nanoradian).
    if (TwistStepBetween(X, X_FM_wanted).cwiseProduct(scale).norm() < 1e-10 || x.cwiseProduct(scale).norm() < 1e-13) {
      break;
    }
  }
  out.X_FM = X;
  if (reached_wanted && !constrained) {
    out.status = FeasibleMotionStatus::kTracked;
  } else if (X.matrix() == X_FM_current.matrix()) {
    out.status = FeasibleMotionStatus::kHeld;
  } else {
    out.status = FeasibleMotionStatus::kConstrained;
  }
  return out;
}

FeasibleMotionResult FeasibleMotionGuard::StepTwist(const Eigen::Isometry3d& X_FM_current, const Vector6d& twist_F,
                                                    double dt_s) const noexcept {
  if (!twist_F.allFinite() || !std::isfinite(dt_s)) {
    FeasibleMotionResult out;
    out.X_FM = X_FM_current;
    out.status = FeasibleMotionStatus::kInvalidInput;
    return out;
  }
  return Step(X_FM_current, ApplyTwistStep(X_FM_current, twist_F * dt_s));
}

}  // namespace robossis::robot
