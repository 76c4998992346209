#include "src/apps/rsr_json.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "src/core/units.h"

namespace robossis::apps {

using json = nlohmann::ordered_json;
using robot::kNumArms;
using robot::RsrJointKind;

namespace {
json Vec(const Eigen::Vector3d& v, double scale = 1.0) { return json::array({v.x() * scale, v.y() * scale, v.z() * scale}); }

// Edge units of one limit kind: mm for strokes, degrees for angles.
double EdgeValue(RsrJointKind kind, double si) { return kind == RsrJointKind::kStroke ? MToMm(si) : RadToDeg(si); }
const char* EdgeUnit(RsrJointKind kind) { return kind == RsrJointKind::kStroke ? "mm" : "deg"; }
}  // namespace

json RsrInfoJson(const robot::RsrModel& model) {
  const robot::RsrGeometry& g = model.geometry();
  json fixed = json::array(), moving = json::array(), angles = json::array();
  for (int i = 0; i < kNumArms; ++i) {
    fixed.push_back(Vec(g.p_FA[i]));
    moving.push_back(Vec(g.p_MB[i]));
    angles.push_back(RadToDeg(g.arm_angles_rad[i]));
  }
  const Vector6d home = MmDegFromPose(g.X_FM_home);
  const robot::RsrIkResult home_ik = robot::CalcInverseKinematics(model, g.X_FM_home);
  return {
      {"fixed_ring_joints_m", fixed},
      {"moving_ring_joints_m", moving},
      {"moving_ring_joints_frame", "moving ring (M)"},
      {"arm_angles_deg", angles},
      {"home_pose", {{"position_mm", Vec(home.head<3>())}, {"rpy_deg", Vec(home.tail<3>())}}},
      {"home_joints", {{"theta_deg", Vec(home_ik.joints.theta_rad, kRadToDeg)},
                       {"d_mm", Vec(home_ik.joints.d_m, kMToMm)},
                       {"psi_deg", Vec(home_ik.joints.psi_rad, kRadToDeg)}}},
      {"limits",
       {{"stroke_min_mm", MToMm(g.limits.stroke_min_m)},
        {"stroke_max_mm", MToMm(g.limits.stroke_max_m)},
        {"spherical_cone_max_deg", RadToDeg(g.limits.spherical_cone_max_rad)},
        {"rotary_max_deg", RadToDeg(g.limits.rotary_max_rad)}}},
      {"orientation_convention", "R = Rz(yaw) * Ry(pitch) * Rx(roll)"},
  };
}

std::string ViolationText(const robot::RsrLimitCheck& c) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "arm %d %s = %.3f %s, limit %.3f %s, margin %.3f %s", c.arm + 1,
                robot::ToString(c.joint), EdgeValue(c.joint, c.value), EdgeUnit(c.joint),
                EdgeValue(c.joint, c.limit), EdgeUnit(c.joint), EdgeValue(c.joint, c.margin), EdgeUnit(c.joint));
  return buf;
}

json RsrFeasibilityJson(const robot::RsrIkResult& ik) {
  json violations = json::array();
  for (const robot::RsrLimitCheck& c : ik.checks) {
    if (c.margin < 0) violations.push_back(ViolationText(c));
  }
  return {{"feasible", ik.feasible}, {"violations", violations}};
}

json RsrIkJson(const robot::RsrIkResult& ik) {
  json violations = json::array(), limits = json::array();
  for (const robot::RsrLimitCheck& c : ik.checks) {
    json entry = {{"arm", c.arm + 1},
                  {"joint", robot::ToString(c.joint)},
                  {"unit", EdgeUnit(c.joint)},
                  {"value", EdgeValue(c.joint, c.value)},
                  {"limit", EdgeValue(c.joint, c.limit)},
                  {"margin", EdgeValue(c.joint, c.margin)}};
    if (c.margin < 0) violations.push_back(entry);
    limits.push_back(std::move(entry));
  }
  return {{"feasible", ik.feasible},
          {"theta_deg", Vec(ik.joints.theta_rad, kRadToDeg)},
          {"d_mm", Vec(ik.joints.d_m, kMToMm)},
          {"psi_deg", Vec(ik.joints.psi_rad, kRadToDeg)},
          {"cone_deg", Vec(ik.joints.cone_rad, kRadToDeg)},
          {"violations", violations},
          {"limits", limits}};
}

json RsrFkJson(const robot::RsrFkResult& fk) {
  const Vector6d pose = MmDegFromPose(fk.X_FM);
  return {{"converged", fk.converged()},
          {"status", robot::ToString(fk.status)},
          {"position_mm", Vec(pose.head<3>())},
          {"rpy_deg", Vec(pose.tail<3>())},
          {"iterations", fk.iterations},
          {"residual", fk.residual}};
}

json RsrJacobianJson(const Matrix6d& J) {
  json rows = json::array();
  for (int r = 0; r < 6; ++r) {
    json row = json::array();
    for (int c = 0; c < 6; ++c) row.push_back(J(r, c));
    rows.push_back(row);
  }
  return {{"jacobian", rows},
          {"rows", {"theta_1 (rad/s)", "theta_2 (rad/s)", "theta_3 (rad/s)", "d_1 (m/s)", "d_2 (m/s)", "d_3 (m/s)"}},
          {"columns", {"v_x (m/s)", "v_y (m/s)", "v_z (m/s)", "omega_x (rad/s)", "omega_y (rad/s)", "omega_z (rad/s)"}},
          {"frame", "fixed ring (F); v is the velocity of the moving-ring centre P"}};
}

json RsrStaticsJson(const robot::RsrStaticsResult& s) {
  return {{"linear_force_n", Vec(s.linear_force_n)},
          {"rotary_torque_nm", Vec(s.rotary_torque_nm)},
          {"convention", "efforts holding the ring against the external wrench, Q = -J^-T W; "
                         "linear force > 0 pushes the rings apart"}};
}

void PrintKeyValues(const json& document) {
  for (const auto& [key, value] : document.items()) std::cout << key << ": " << value.dump() << "\n";
}

namespace {
// The path of the first non-finite number in `node`, or "" if every number is finite.
std::string FirstNonFinite(const nlohmann::ordered_json& node, const std::string& path) {
  if (node.is_number_float()) return std::isfinite(node.get<double>()) ? "" : path;
  if (node.is_object()) {
    for (const auto& [key, value] : node.items()) {
      if (std::string p = FirstNonFinite(value, path.empty() ? key : path + "." + key); !p.empty()) return p;
    }
  } else if (node.is_array()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      if (std::string p = FirstNonFinite(node[i], path + "[" + std::to_string(i) + "]"); !p.empty()) return p;
    }
  }
  return "";
}
}  // namespace

void RequireFiniteResult(const nlohmann::ordered_json& document, const std::string& what) {
  const std::string bad = FirstNonFinite(document, "");
  if (!bad.empty()) {
    throw std::runtime_error(what + ": not finite at this pose ('" + bad +
                             "' is NaN or infinite): a singular or degenerate pose; expected a pose where the "
                             "kinematics are defined");
  }
}

}  // namespace robossis::apps
