#pragma once
// Kinematics of the Force Dimension sigma.7 (paper §III-A): the delta mechanism of eq. 1–4 for translation and a
// serial wrist for rotation.
//
// Reading of eq. 1 (the paper leaves it open; see README "sigma.7 model"): the chain frame (u_i, v_i, w_i) sits at
// the chain's lowest joint A_i, so the offset (r, s) is applied in the chain frame, after the rotations, as in the
// Falcon kinematics the paper builds on:  P_uvw = Rz'(phi_i) · Ry'(theta) · P - [r, s, 0]^T.  Taken literally
// (offset added before rotating) every A_i would sit at the same point (r, s, 0), which is not a delta mechanism.

#include <array>
#include <filesystem>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::robot {

inline constexpr int kNumDeltaChains = 3;

struct Sigma7Geometry {
  double a_m = 0.084, b_m = 0.175, r_m = 0.079, c_m = 0.042, f_m = 0.037;  // paper §III-A
  double s_m = 0.0;                                                        // eq. 1 offset, assumed 0
  double tilt_rad = 0;                                                     // theta of eq. 1 (45 deg)
  std::array<double, kNumDeltaChains> chain_angles_rad{};                  // phi_i
  double theta1_min_rad = 0, theta1_max_rad = 0;                           // assumed actuated-joint range
  double theta3_min_rad = 0, theta3_max_rad = 0;                           // assumed parallelogram range
  Eigen::Vector3d wrist_half_range_rad = Eigen::Vector3d::Zero();          // (roll, pitch, yaw) half ranges
  double max_force_n = 20, max_torque_nm = 0.4;                            // device peak output
};

// Joint angles of the three delta chains (rad). theta1 is actuated; theta2, theta3 are passive.
struct DeltaJoints {
  Eigen::Vector3d theta1 = Eigen::Vector3d::Zero();
  Eigen::Vector3d theta2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d theta3 = Eigen::Vector3d::Zero();
};

struct DeltaIkResult {
  bool reachable = false;  // a real solution exists for every chain
  bool within_limits = false;
  DeltaJoints joints;
};

struct DeltaFkResult {
  bool ok = false;
  Eigen::Vector3d p_O = Eigen::Vector3d::Zero();  // platform centre P in the base frame O (m)
};

class Sigma7Model {
 public:
  explicit Sigma7Model(const Sigma7Geometry& geometry);  // validates; throws std::invalid_argument
  static Sigma7Model FromYaml(const std::filesystem::path& file);
  // The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
  static Sigma7Model FromConfig(const ConfigNode& root);
  static Sigma7Model Default();  // <data dir>/config/sigma7.yaml

  const Sigma7Geometry& geometry() const { return geometry_; }
  // Rotation taking base coordinates to chain i's (u, v, w) axes: the two matrices of eq. 1.
  const Eigen::Matrix3d& R_chain_base(int i) const { return R_chain_base_[i]; }
  // A platform position well inside the workspace (the FK of the mid-range actuated angles).
  const Eigen::Vector3d& p_center_O() const { return p_center_O_; }

 private:
  Sigma7Geometry geometry_;
  std::array<Eigen::Matrix3d, kNumDeltaChains> R_chain_base_{};
  Eigen::Vector3d p_center_O_ = Eigen::Vector3d::Zero();
};

// P in chain i's frame (eq. 1, with the reading above).
Eigen::Vector3d ChainCoordinates(const Sigma7Model& model, int chain, const Eigen::Vector3d& p_O) noexcept;

// Delta IK (eq. 2–4): theta3 from eq. 3 on its positive branch (paper: theta_3i > 0), then theta1 on the branch in
// the first quadrant side (the larger of the two solutions; paper: "theta_1i is always in the first [quadrant]"),
// then theta2.
DeltaIkResult CalcDeltaInverseKinematics(const Sigma7Model& model, const Eigen::Vector3d& p_O) noexcept;

// Delta FK: each chain constrains P to a sphere of radius b about the elbow; the two intersections of the three
// spheres are tried and the one whose IK reproduces theta1 (the physical branch) is returned.
DeltaFkResult CalcDeltaForwardKinematics(const Sigma7Model& model, const Eigen::Vector3d& theta1) noexcept;

// Wrist joints (roll, pitch, yaw) of a handle orientation R = Rz(yaw) Ry(pitch) Rx(roll), and the range test.
Eigen::Vector3d WristJointsFromRotation(const Eigen::Matrix3d& R) noexcept;
bool WristWithinRange(const Sigma7Model& model, const Eigen::Vector3d& wrist_rpy) noexcept;

// Workspace membership: the position is reachable within the delta joint ranges and the orientation within the
// wrist ranges.
bool IsInSigma7Workspace(const Sigma7Model& model, const Eigen::Vector3d& p_O, const Eigen::Matrix3d& R) noexcept;

}  // namespace robossis::robot
