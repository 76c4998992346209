#pragma once
// Kinematics and statics of the RSR (paper §III-B and §V-A): inverse kinematics (eq. 5–8), a trigonometry-free
// feasibility test for the haptic loop, forward kinematics by Newton iteration, the Jacobian of eq. 15 by
// reciprocal screws, and actuator efforts for a wrench on the moving ring.
//
// Every function here is allocation-free and noexcept: they run inside real-time ticks.

#include <array>
#include <string>

#include "robot/rsr_model.h"
#include "src/core/pose.h"

namespace robossis::robot {

// Actuated joints in the order of eq. 13: [theta_1 theta_2 theta_3 d_1 d_2 d_3] (rad, m).
using RsrJointVector = Vector6d;
constexpr int ThetaIndex(int arm) { return arm; }
constexpr int StrokeIndex(int arm) { return kNumArms + arm; }

// All joint values of one pose.
struct RsrJoints {
  Eigen::Vector3d theta_rad = Eigen::Vector3d::Zero();  // active rotary joints, eq. 7
  Eigen::Vector3d d_m = Eigen::Vector3d::Zero();        // linear actuator lengths, eq. 6
  Eigen::Vector3d psi_rad = Eigen::Vector3d::Zero();    // passive joints, eq. 8
  Eigen::Vector3d cone_rad = Eigen::Vector3d::Zero();   // spherical joint: angle between leg and ring normal
  Eigen::Matrix3d leg_direction_F = Eigen::Matrix3d::Zero();  // column i: unit leg vector n_i in F

  RsrJointVector actuated() const {
    RsrJointVector q;
    q << theta_rad, d_m;
    return q;
  }
};

enum class RsrJointKind { kStroke, kRotary, kSphericalCone };
const char* ToString(RsrJointKind kind);

// One limit of one arm: the nearest bound, the value, and the margin (>= 0 inside, < 0 violated; m or rad).
struct RsrLimitCheck {
  int arm = 0;
  RsrJointKind joint = RsrJointKind::kStroke;
  double value = 0;
  double limit = 0;
  double margin = 0;
};

struct RsrIkResult {
  RsrJoints joints;
  // 3 arms x {stroke, rotary, spherical cone}, in that order per arm.
  std::array<RsrLimitCheck, 3 * kNumArms> checks{};
  bool feasible = false;  // every margin >= 0

  // The smallest margin over all limits, and which one.
  const RsrLimitCheck& tightest() const;
};

// Inverse kinematics (eq. 5–8) with the per-limit verdict. X_FM: pose of the moving ring in the fixed-ring frame.
RsrIkResult CalcInverseKinematics(const RsrModel& model, const Eigen::Isometry3d& X_FM) noexcept;

// True if the pose is within every joint limit. Same verdict as CalcInverseKinematics(...).feasible, without
// trigonometry (one square root per arm): this is the test the haptic point clouds call thousands of times a tick.
bool IsPoseFeasible(const RsrModel& model, const Eigen::Isometry3d& X_FM) noexcept;

// IsPoseFeasible for the poses a haptic point cloud visits around one pose: that pose translated (one orientation,
// many positions), or turned about its own position (one position, many orientations). The parts of each leg that
// do not change across the cloud are computed once, at construction. Keeps a reference to the model.
class PoseFeasibilityAround {
 public:
  PoseFeasibilityAround(const RsrModel& model, const Eigen::Isometry3d& X_FM) noexcept;
  // X_FM translated by offset_F (in F).
  bool Translated(const Eigen::Vector3d& offset_F) const noexcept;
  // X_FM turned by R_step at its position: orientation R_step · R_FM.
  bool Rotated(const Eigen::Matrix3d& R_step) const noexcept;

 private:
  const RsrModel& model_;
  Eigen::Vector3d z_M_;
  std::array<Eigen::Vector3d, kNumArms> e_;  // R_FM · b_i
  std::array<Eigen::Vector3d, kNumArms> c_;  // p_FM − a_i
};

// The Jacobian of eq. 15, q_dot = J · [v; omega], by reciprocal screws: rows in eq. 13 order, columns the linear
// and angular velocity of the moving ring (at P, in F). Singular when some cos(psi_i) = 0.
Matrix6d CalcJacobian(const RsrModel& model, const Eigen::Isometry3d& X_FM) noexcept;

struct RsrFkOptions {
  int max_iterations = 30;
  double tolerance = 1e-13;  // on the joint residual, in m and rad
};

enum class RsrFkStatus { kConverged, kMaxIterations, kSingular };
const char* ToString(RsrFkStatus status);

struct RsrFkResult {
  RsrFkStatus status = RsrFkStatus::kMaxIterations;
  Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();
  int iterations = 0;
  double residual = 0;  // max |q(X_FM) - q| over the six actuated joints
  bool converged() const { return status == RsrFkStatus::kConverged; }
};

// Forward kinematics: the pose whose actuated joints are q, by Newton iteration with the analytic Jacobian,
// warm-started at X_FM_guess (the previous pose in a loop; the home pose otherwise). The mechanism has several
// assembly modes; Newton converges to the one nearest the guess.
RsrFkResult CalcForwardKinematics(const RsrModel& model, const RsrJointVector& q, const Eigen::Isometry3d& X_FM_guess,
                                  const RsrFkOptions& options = {}) noexcept;

// Actuator efforts holding the moving ring in equilibrium against an external wrench W = [F; M] applied to it
// (force at P and moment about P, both in F): the actuators exert J^T Q = -W on the ring, so Q = -J^-T W.
// Q is in eq. 13 order: rotary torques (N·m) then linear forces (N, positive = pushing the rings apart).
struct RsrStaticsResult {
  bool singular = false;
  Eigen::Vector3d rotary_torque_nm = Eigen::Vector3d::Zero();
  Eigen::Vector3d linear_force_n = Eigen::Vector3d::Zero();
};
RsrStaticsResult CalcActuatorEfforts(const RsrModel& model, const Eigen::Isometry3d& X_FM,
                                     const Vector6d& wrench_ext_F) noexcept;

// The largest external wrench component the statics accept (assumptions, not in the paper): 1e6 N and 1e5 N·m are
// three to four orders of magnitude above any load on a femur (muscle traction is ~0.5 kN; the paper's test 517 N),
// and far enough below DBL_MAX that Q = -J^-T W stays finite at any pose the Jacobian is invertible at.
inline constexpr double kMaxWrenchForceN = 1e6;
inline constexpr double kMaxWrenchTorqueNm = 1e5;
// Throws std::invalid_argument "WHERE: FZ_N is 1e+308; expected a finite force within +/-1e+06 N" unless every
// component of W = [F; M] is finite and within the bounds above.
void RequireBoundedWrench(const Vector6d& wrench_ext_F, const std::string& where);

}  // namespace robossis::robot
