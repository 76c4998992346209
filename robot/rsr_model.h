#pragma once
// The Robossis Surgical Robot (RSR): an immutable model of its geometry and joint limits.
//
// Arm i (README.md, "The RSR model"): an active rotary joint theta_i whose axis u_i is radial in the fixed-ring plane, a passive
// revolute joint psi_i, the linear actuator d_i, and a spherical joint on the moving ring. In the arm frame
// Rz(gamma_i) the leg direction is Rx(theta_i) · Ry(psi_i) · z, which reproduces the paper's eq. 7–8.

#include <array>
#include <filesystem>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::robot {

inline constexpr int kNumArms = 3;

// Geometry the model refuses as degenerate (assumptions, not in the paper). Arms closer than 30 deg on the rings
// (the paper's are 120 deg apart) leave the moving ring nearly unconstrained about some axis: the Jacobian is
// (near-)singular and IK, FK and statics give NaN or huge values. A home-pose Jacobian condition number above 1000
// (2-norm, rows in rad/s and m/s, columns in m/s and rad/s; the shipped geometry passes) means the same: an
// effort or velocity error is amplified a thousandfold there.
inline constexpr double kMinArmSeparationRad = 30.0 * kDegToRad;
inline constexpr double kMaxHomeJacobianCondition = 1000.0;

// Joint limits, SI. All are inequalities that a feasible pose satisfies with a non-negative margin.
struct RsrLimits {
  double stroke_min_m = 0.214;       // paper §III-B
  double stroke_max_m = 0.354;       // paper §III-B
  double spherical_cone_max_rad = 0; // paper: spherical joints +/-25 deg
  double rotary_max_rad = 0;         // assumed: +/-30 deg
};

struct RsrGeometry {
  std::array<double, kNumArms> arm_angles_rad{};           // gamma_i, paper §III-B
  std::array<Eigen::Vector3d, kNumArms> p_FA{};            // fixed-ring joints A_i in F (a_i of eq. 5)
  std::array<Eigen::Vector3d, kNumArms> p_MB{};            // moving-ring joints B_i in M (b_i of eq. 5)
  Eigen::Isometry3d X_FM_home = Eigen::Isometry3d::Identity();
  RsrLimits limits;
};

class RsrModel {
 public:
  // Validates the geometry (finite values, ordered limits, a home pose inside the limits); throws
  // std::invalid_argument naming the field otherwise.
  explicit RsrModel(const RsrGeometry& geometry);

  // Loads `rsr.yaml` (see data/config/rsr.yaml); throws std::runtime_error naming the file and key.
  static RsrModel FromYaml(const std::filesystem::path& file);
  // The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
  static RsrModel FromConfig(const ConfigNode& root);
  // The default configuration: <data dir>/config/rsr.yaml.
  static RsrModel Default();

  const RsrGeometry& geometry() const { return geometry_; }
  const RsrLimits& limits() const { return geometry_.limits; }
  const Eigen::Vector3d& p_FA(int i) const { return geometry_.p_FA[i]; }
  const Eigen::Vector3d& p_MB(int i) const { return geometry_.p_MB[i]; }
  // Radial axis u_i of the rotary joint theta_i, in F.
  const Eigen::Vector3d& rotary_axis_F(int i) const { return rotary_axis_F_[i]; }
  // Tangential axis of arm i (z × u_i), in F.
  const Eigen::Vector3d& tangent_axis_F(int i) const { return tangent_axis_F_[i]; }

  // Limit thresholds precomputed for the trigonometry-free feasibility test.
  double stroke_min_sq() const { return stroke_min_sq_; }
  double stroke_max_sq() const { return stroke_max_sq_; }
  double cos_cone_max() const { return cos_cone_max_; }
  double tan_rotary_max() const { return tan_rotary_max_; }

 private:
  RsrGeometry geometry_;
  std::array<Eigen::Vector3d, kNumArms> rotary_axis_F_{};
  std::array<Eigen::Vector3d, kNumArms> tangent_axis_F_{};
  double stroke_min_sq_ = 0;
  double stroke_max_sq_ = 0;
  double cos_cone_max_ = 0;
  double tan_rotary_max_ = 0;
};

}  // namespace robossis::robot
