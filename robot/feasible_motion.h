#pragma once
// The feasible-motion guard: the last word on every pose the follower is sent. Given the current feasible RSR pose
// and the pose wanted one tick later, it returns the next pose that tracks the wanted one as closely as possible
// while no joint limit is crossed: the three strokes, the three rotary ranges and the three spherical-joint cones.
//
// Method (the constrained least-squares step of JHU's sawConstraintController and of the vector-field inequalities
// of Marinho et al., ICRA 2019): with the twist step x = [dp; dtheta] (position of P and rotation vector, in F),
//
//     minimise |W (x - x_wanted)|^2   subject to   grad g_k(X) · x >= -eta * (g_k(X) - buffer_k)   for every limit k,
//
// where g_k is the margin of limit k, linearised through the Jacobian of eq. 15 (strokes and rotary joints are rows
// of J; the cone uses the gradient of n_i · z_M). Since J is invertible inside the workspace, a step on the twist
// is a step on the joint velocities q_dot = J x (eq. 15). W weighs rotation by a length so that millimetres and
// radians compare. The final check is the exact IK (CalcInverseKinematics): a pose that fails it is never returned;
// the step is re-linearised, then halved, and if nothing passes the guard holds the current pose.
//
// Real time: allocation-free and noexcept (a fixed-size active-set QP, robot/projection_qp.h).

#include <cstdint>

#include <Eigen/Geometry>

#include "robot/projection_qp.h"
#include "robot/rsr_kinematics.h"
#include "robot/rsr_model.h"

namespace robossis::robot {

// Tuning of the guard. Every value is an assumption (the paper gives none); the follower's YAML
// (data/config/follower.yaml, `guard:`) names them and says why.
struct FeasibleMotionConfig {
  double rotation_length_m = 0.2;      // W: 1 rad of rotation weighs as much as this length (the ring radius)
  double stroke_buffer_m = 1e-6;       // the guard keeps this far inside each stroke limit
  double angle_buffer_rad = 1e-5;      // ... and this far inside each rotary range and cone
  double approach_gain = 1.0;          // eta in (0, 1]: the share of the remaining margin one step may use
  int max_relinearizations = 3;        // QP solves per call, each linearised at the previous result
  int max_halvings = 12;               // step halvings when the exact IK rejects a QP result
  // Throws std::invalid_argument naming the field.
  void Validate() const;
};

enum class FeasibleMotionStatus : std::uint8_t {
  kTracked,          // the wanted pose itself (feasible)
  kConstrained,      // a limit was active: the nearest feasible pose, sliding along it
  kHeld,             // no feasible step found: the current pose
  kInvalidInput,     // a non-finite input: the current pose (or home if the current pose is not finite)
  kStartInfeasible,  // the current pose itself breaks a limit: held, never moved further
};
const char* ToString(FeasibleMotionStatus status);

struct FeasibleMotionResult {
  Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();  // the next pose; always passes the exact IK unless
                                                           // status is kStartInfeasible/kInvalidInput
  FeasibleMotionStatus status = FeasibleMotionStatus::kHeld;
  int active_limits = 0;    // linearised limits active in the last QP
  int qp_iterations = 0;    // total over the re-linearisations
  int halvings = 0;
  RsrLimitCheck tightest{};  // the tightest limit of the returned pose (exact IK)
  bool moved_as_wanted() const noexcept { return status == FeasibleMotionStatus::kTracked; }
};

// The linearised limits at one pose: row k of `gradient` is d g_k / d x for the twist step x = [dp; dtheta] (in F),
// `margin[k]` is g_k (m for strokes, rad for rotary joints, cosine difference for cones, >= 0 inside).
// Order: per arm {stroke above min, stroke below max, rotary above -max, rotary below +max, cone}.
inline constexpr int kNumLinearizedLimits = 5 * kNumArms;
struct LinearizedLimits {
  Eigen::Matrix<double, kNumLinearizedLimits, 6> gradient = decltype(gradient)::Zero();
  Eigen::Matrix<double, kNumLinearizedLimits, 1> margin = decltype(margin)::Zero();
  Eigen::Matrix<double, kNumLinearizedLimits, 1> buffer = decltype(buffer)::Zero();
};
LinearizedLimits CalcLinearizedLimits(const RsrModel& model, const Eigen::Isometry3d& X_FM,
                                      const FeasibleMotionConfig& config) noexcept;

// The pose reached from X_FM by the twist step x = [dp; dtheta] (in F): p + dp, Exp(dtheta) R.
Eigen::Isometry3d ApplyTwistStep(const Eigen::Isometry3d& X_FM, const Vector6d& step) noexcept;
// The twist step from X_a to X_b (inverse of ApplyTwistStep).
Vector6d TwistStepBetween(const Eigen::Isometry3d& X_a, const Eigen::Isometry3d& X_b) noexcept;

class FeasibleMotionGuard {
 public:
  // Validates the config (throws std::invalid_argument). Keeps a reference to the model: it must outlive the guard.
  explicit FeasibleMotionGuard(const RsrModel& model, const FeasibleMotionConfig& config = {});

  // The next pose from X_FM_current towards X_FM_wanted (one tick).
  FeasibleMotionResult Step(const Eigen::Isometry3d& X_FM_current,
                            const Eigen::Isometry3d& X_FM_wanted) const noexcept;
  // The same with the wanted motion as a twist [v; omega] (in F) held for dt_s.
  FeasibleMotionResult StepTwist(const Eigen::Isometry3d& X_FM_current, const Vector6d& twist_F,
                                 double dt_s) const noexcept;

  const FeasibleMotionConfig& config() const noexcept { return config_; }
  const RsrModel& model() const noexcept { return model_; }

 private:
  const RsrModel& model_;
  FeasibleMotionConfig config_;
};

}  // namespace robossis::robot
