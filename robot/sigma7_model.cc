#include "robot/sigma7_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "src/core/config.h"
#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::robot {

Sigma7Model::Sigma7Model(const Sigma7Geometry& g) : geometry_(g) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("sigma.7 geometry: " + what);
  };
  require(g.a_m > 0 && g.b_m > 0 && g.r_m >= 0 && g.c_m >= 0 && g.f_m >= 0, "link lengths must be positive");
  require(std::isfinite(g.s_m) && std::isfinite(g.tilt_rad), "s and tilt must be finite");
  require(g.theta1_min_rad < g.theta1_max_rad, "theta1_min must be below theta1_max");
  require(g.theta3_min_rad > 0 && g.theta3_min_rad < g.theta3_max_rad && g.theta3_max_rad < kPi,
          "theta3 range must lie inside (0, 180) deg");
  require((g.wrist_half_range_rad.array() > 0).all(), "wrist ranges must be positive");
  require(g.wrist_half_range_rad.y() < kPi / 2, "the wrist pitch range must be below 180 deg");
  const double ct = std::cos(g.tilt_rad), st = std::sin(g.tilt_rad);
  Eigen::Matrix3d R_tilt;
  R_tilt << ct, 0, st, 0, 1, 0, -st, 0, ct;  // eq. 1, second matrix
  for (int i = 0; i < kNumDeltaChains; ++i) {
    const double cp = std::cos(g.chain_angles_rad[i]), sp = std::sin(g.chain_angles_rad[i]);
    Eigen::Matrix3d R_phi;
    R_phi << cp, sp, 0, -sp, cp, 0, 0, 0, 1;  // eq. 1, first matrix
    R_chain_base_[i] = R_phi * R_tilt;
  }
  const double mid = 0.5 * (g.theta1_min_rad + g.theta1_max_rad);
  const DeltaFkResult center = CalcDeltaForwardKinematics(*this, Eigen::Vector3d::Constant(mid));
  require(center.ok, "the mid-range actuated angles do not assemble; check the dimensions");
  p_center_O_ = center.p_O;
}

Sigma7Model Sigma7Model::FromYaml(const std::filesystem::path& file) {
  return FromConfig(ConfigNode::Load(file));
}

Sigma7Model Sigma7Model::FromConfig(const ConfigNode& root) {
  const ConfigNode delta = root.Child("delta");
  const ConfigNode wrist = root.Child("wrist");
  const ConfigNode device = root.Child("device");
  Sigma7Geometry g;
  g.a_m = MmToM(delta.PositiveNumber("a_mm"));
  g.b_m = MmToM(delta.PositiveNumber("b_mm"));
  g.r_m = MmToM(delta.NumberInRange("r_mm", 0, 1e4));
  g.c_m = MmToM(delta.NumberInRange("c_mm", 0, 1e4));
  g.f_m = MmToM(delta.NumberInRange("f_mm", 0, 1e4));
  g.s_m = MmToM(delta.Number("s_mm"));
  g.tilt_rad = DegToRad(delta.NumberInRange("tilt_deg", -90, 90));
  const std::vector<double> phi = delta.Numbers("chain_angles_deg", kNumDeltaChains);
  for (int i = 0; i < kNumDeltaChains; ++i) g.chain_angles_rad[i] = DegToRad(phi[i]);
  g.theta1_min_rad = DegToRad(delta.NumberInRange("theta1_min_deg", -180, 180));
  g.theta1_max_rad = DegToRad(delta.NumberInRange("theta1_max_deg", -180, 180));
  if (g.theta1_max_rad <= g.theta1_min_rad) delta.Fail("theta1_max_deg", "must be greater than theta1_min_deg");
  g.theta3_min_rad = DegToRad(delta.NumberInRange("theta3_min_deg", 1e-6, 179.999));
  g.theta3_max_rad = DegToRad(delta.NumberInRange("theta3_max_deg", 1e-6, 179.999));
  if (g.theta3_max_rad <= g.theta3_min_rad) delta.Fail("theta3_max_deg", "must be greater than theta3_min_deg");
  g.wrist_half_range_rad = 0.5 * Eigen::Vector3d(DegToRad(wrist.NumberInRange("roll_range_deg", 1e-6, 360)),
                                                 DegToRad(wrist.NumberInRange("pitch_range_deg", 1e-6, 179.999)),
                                                 DegToRad(wrist.NumberInRange("yaw_range_deg", 1e-6, 360)));
  g.max_force_n = device.PositiveNumber("max_force_n");
  g.max_torque_nm = device.PositiveNumber("max_torque_nm");
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  try {
    return Sigma7Model(g);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(root.file() + ": " + e.what());
  }
}

Sigma7Model Sigma7Model::Default() { return FromYaml(DefaultDataDir() / "config" / "sigma7.yaml"); }

Eigen::Vector3d ChainCoordinates(const Sigma7Model& model, int chain, const Eigen::Vector3d& p_O) noexcept {
  const Sigma7Geometry& g = model.geometry();
  return model.R_chain_base(chain) * p_O - Eigen::Vector3d(g.r_m, g.s_m, 0.0);  // eq. 1
}

DeltaIkResult CalcDeltaInverseKinematics(const Sigma7Model& model, const Eigen::Vector3d& p_O) noexcept {
  const Sigma7Geometry& g = model.geometry();
  DeltaIkResult out;
  out.reachable = p_O.allFinite();
  out.within_limits = out.reachable;
  for (int i = 0; i < kNumDeltaChains && out.reachable; ++i) {
    const Eigen::Vector3d P = ChainCoordinates(model, i, p_O);
    // eq. 3: Pv = b cos(theta3) - f, positive branch theta3 in (0, pi).
    const double cos3 = (P.y() + g.f_m) / g.b_m;
    if (std::abs(cos3) >= 1.0) {
      out.reachable = false;
      break;
    }
    const double theta3 = std::acos(cos3);
    const double k = g.b_m * std::sin(theta3);
    // eq. 2 and 4 without theta2: (Pu + c - a cos t1)^2 + (Pw - a sin t1)^2 = k^2, i.e.
    // (Pu + c) cos t1 + Pw sin t1 = ((Pu + c)^2 + Pw^2 + a^2 - k^2) / (2a) = rho cos(t1 - delta).
    const double u = P.x() + g.c_m;
    const double w = P.z();
    const double rho = std::hypot(u, w);
    const double cos_arg = (u * u + w * w + g.a_m * g.a_m - k * k) / (2.0 * g.a_m * rho);
    if (!(rho > 0.0) || std::abs(cos_arg) > 1.0) {
      out.reachable = false;
      break;
    }
    const double theta1 = std::atan2(w, u) + std::acos(cos_arg);
    // eq. 2 and 4 again for theta2.
    const double theta2 = std::atan2(w - g.a_m * std::sin(theta1), u - g.a_m * std::cos(theta1));
    out.joints.theta1[i] = theta1;
    out.joints.theta2[i] = theta2;
    out.joints.theta3[i] = theta3;
    out.within_limits = out.within_limits && theta1 >= g.theta1_min_rad && theta1 <= g.theta1_max_rad &&
                        theta3 >= g.theta3_min_rad && theta3 <= g.theta3_max_rad;
  }
  out.within_limits = out.within_limits && out.reachable;
  return out;
}

DeltaFkResult CalcDeltaForwardKinematics(const Sigma7Model& model, const Eigen::Vector3d& theta1) noexcept {
  const Sigma7Geometry& g = model.geometry();
  DeltaFkResult out;
  if (!theta1.allFinite()) return out;
  // Sphere centre of chain i: P_uvw = (a cos t1 - c, -f, a sin t1) + (b sin t3 cos t2, b cos t3, b sin t3 sin t2),
  // so P lies on the sphere of radius b about the elbow (a cos t1 - c, -f, a sin t1) in chain coordinates.
  std::array<Eigen::Vector3d, kNumDeltaChains> c;
  for (int i = 0; i < kNumDeltaChains; ++i) {
    const Eigen::Vector3d elbow_chain(g.a_m * std::cos(theta1[i]) - g.c_m, -g.f_m, g.a_m * std::sin(theta1[i]));
    c[i] = model.R_chain_base(i).transpose() * (elbow_chain + Eigen::Vector3d(g.r_m, g.s_m, 0.0));
  }
  // Three equal spheres: |P - c_i| = b. Subtracting pairs gives two planes; their line meets the sphere twice.
  const Eigen::Vector3d n1 = c[1] - c[0];
  const Eigen::Vector3d n2 = c[2] - c[0];
  const double h1 = 0.5 * (c[1].squaredNorm() - c[0].squaredNorm());
  const double h2 = 0.5 * (c[2].squaredNorm() - c[0].squaredNorm());
  const Eigen::Vector3d dir = n1.cross(n2);
  const double dir_sq = dir.squaredNorm();
  if (!(dir_sq > 1e-18)) return out;
  // A point on the line: p0 = (h1 (n2 × dir) + h2 (dir × n1)) / |dir|^2 satisfies n1·p0 = h1, n2·p0 = h2.
  const Eigen::Vector3d p0 = (h1 * n2.cross(dir) + h2 * dir.cross(n1)) / dir_sq;
  const Eigen::Vector3d unit = dir / std::sqrt(dir_sq);
  const Eigen::Vector3d m = p0 - c[0];
  const double half_b = unit.dot(m);
  const double disc = half_b * half_b - (m.squaredNorm() - g.b_m * g.b_m);
  if (disc < 0.0) return out;
  const double root = std::sqrt(disc);
  for (const double t : {-half_b + root, -half_b - root}) {
    const Eigen::Vector3d p = p0 + t * unit;
    const DeltaIkResult ik = CalcDeltaInverseKinematics(model, p);
    if (ik.reachable && (ik.joints.theta1 - theta1).cwiseAbs().maxCoeff() < 1e-7) {
      out.ok = true;
      out.p_O = p;
      return out;
    }
  }
  return out;
}

Eigen::Vector3d WristJointsFromRotation(const Eigen::Matrix3d& R) noexcept { return RpyFromRotation(R); }

bool WristWithinRange(const Sigma7Model& model, const Eigen::Vector3d& wrist_rpy) noexcept {
  return (wrist_rpy.cwiseAbs().array() <= model.geometry().wrist_half_range_rad.array()).all();
}

bool IsInSigma7Workspace(const Sigma7Model& model, const Eigen::Vector3d& p_O, const Eigen::Matrix3d& R) noexcept {
  return CalcDeltaInverseKinematics(model, p_O).within_limits && WristWithinRange(model, WristJointsFromRotation(R));
}

}  // namespace robossis::robot
