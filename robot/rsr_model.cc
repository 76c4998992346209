#include "robot/rsr_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/SVD>

#include "robot/rsr_kinematics.h"
#include "src/core/config.h"
#include "src/core/parse.h"
#include "src/core/units.h"

namespace robossis::robot {

namespace {
std::string Num(double v) { return FormatNumber(v, "%.4g"); }
void Require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument("RSR geometry: " + message);
}
}  // namespace

RsrModel::RsrModel(const RsrGeometry& geometry) : geometry_(geometry) {
  const RsrLimits& lim = geometry_.limits;
  for (int i = 0; i < kNumArms; ++i) {
    Require(std::isfinite(geometry_.arm_angles_rad[i]), "arm angle " + std::to_string(i + 1) + " is not finite");
    Require(geometry_.p_FA[i].allFinite() && geometry_.p_MB[i].allFinite(),
            "joint position of arm " + std::to_string(i + 1) + " is not finite");
    const double g = geometry_.arm_angles_rad[i];
    rotary_axis_F_[i] = Eigen::Vector3d(std::cos(g), std::sin(g), 0.0);
    tangent_axis_F_[i] = Eigen::Vector3d(-std::sin(g), std::cos(g), 0.0);
  }
  for (int i = 0; i < kNumArms; ++i) {
    for (int j = i + 1; j < kNumArms; ++j) {
      const double d = std::fmod(std::abs(geometry_.arm_angles_rad[i] - geometry_.arm_angles_rad[j]), 2 * kPi);
      const double separation = std::min(d, 2 * kPi - d);
      Require(separation >= kMinArmSeparationRad - 1e-12,
              "geometry.arm_angles_deg: arms " + std::to_string(i + 1) + " and " + std::to_string(j + 1) + " are " +
                  Num(RadToDeg(separation)) + " deg apart; expected at least " +
                  Num(RadToDeg(kMinArmSeparationRad)) + " deg (closer arms make the ring's pose degenerate)");
    }
  }
  Require(lim.stroke_min_m > 0 && lim.stroke_min_m < lim.stroke_max_m,
          "limits.stroke_min_m must be positive and below limits.stroke_max_m");
  Require(lim.spherical_cone_max_rad > 0 && lim.spherical_cone_max_rad < kPi / 2,
          "limits.spherical_cone_max_deg must be in (0, 90)");
  Require(lim.rotary_max_rad > 0 && lim.rotary_max_rad < kPi / 2, "limits.rotary_max_deg must be in (0, 90)");
  stroke_min_sq_ = lim.stroke_min_m * lim.stroke_min_m;
  stroke_max_sq_ = lim.stroke_max_m * lim.stroke_max_m;
  cos_cone_max_ = std::cos(lim.spherical_cone_max_rad);
  tan_rotary_max_ = std::tan(lim.rotary_max_rad);
  const RsrIkResult home = CalcInverseKinematics(*this, geometry_.X_FM_home);
  if (!home.feasible) {
    const RsrLimitCheck& worst = home.tightest();
    throw std::invalid_argument("RSR geometry: the home pose violates the " + std::string(ToString(worst.joint)) +
                                " limit of arm " + std::to_string(worst.arm + 1));
  }
  const Matrix6d J = CalcJacobian(*this, geometry_.X_FM_home);
  double condition = std::numeric_limits<double>::infinity();
  if (J.allFinite()) {
    const Eigen::JacobiSVD<Matrix6d> svd(J);
    const auto& sv = svd.singularValues();
    if (sv(5) > 0) condition = sv(0) / sv(5);
  }
  Require(condition <= kMaxHomeJacobianCondition,
          "home_pose: the Jacobian's condition number there is " + Num(condition) + "; expected at most " +
              Num(kMaxHomeJacobianCondition) + " (a near-singular home pose)");
}

RsrModel RsrModel::FromYaml(const std::filesystem::path& file) {
  return FromConfig(ConfigNode::Load(file));
}

RsrModel RsrModel::FromConfig(const ConfigNode& root) {
  const ConfigNode geo = root.Child("geometry");
  const ConfigNode home = root.Child("home_pose");
  const ConfigNode lim = root.Child("limits");

  RsrGeometry g;
  const std::vector<double> angles_deg = geo.Numbers("arm_angles_deg", kNumArms);
  const double r_a = geo.PositiveNumber("fixed_ring_radius_m");
  const double r_b = geo.PositiveNumber("moving_ring_radius_m");
  const double h_a = geo.Number("fixed_ring_joint_height_m");
  const double h_b = geo.Number("moving_ring_joint_height_m");
  for (int i = 0; i < kNumArms; ++i) {
    const double gamma = DegToRad(angles_deg[i]);
    g.arm_angles_rad[i] = gamma;
    g.p_FA[i] = Eigen::Vector3d(r_a * std::cos(gamma), r_a * std::sin(gamma), h_a);
    g.p_MB[i] = Eigen::Vector3d(r_b * std::cos(gamma), r_b * std::sin(gamma), h_b);
  }
  const std::vector<double> p_mm = home.Numbers("position_mm", 3);
  const std::vector<double> rpy_deg = home.Numbers("rpy_deg", 3);
  Vector6d pose;
  pose << p_mm[0], p_mm[1], p_mm[2], rpy_deg[0], rpy_deg[1], rpy_deg[2];
  g.X_FM_home = PoseFromMmDeg(pose);

  g.limits.stroke_min_m = lim.PositiveNumber("stroke_min_m");
  g.limits.stroke_max_m = lim.PositiveNumber("stroke_max_m");
  if (g.limits.stroke_max_m <= g.limits.stroke_min_m) {
    lim.Fail("stroke_max_m", "must be greater than stroke_min_m");
  }
  g.limits.spherical_cone_max_rad = DegToRad(lim.NumberInRange("spherical_cone_max_deg", 1e-6, 89.999));
  g.limits.rotary_max_rad = DegToRad(lim.NumberInRange("rotary_max_deg", 1e-6, 89.999));
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  try {
    return RsrModel(g);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(root.file() + ": " + e.what());
  }
}

RsrModel RsrModel::Default() { return FromYaml(DefaultDataDir() / "config" / "rsr.yaml"); }

}  // namespace robossis::robot
