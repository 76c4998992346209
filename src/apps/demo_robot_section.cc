// Demo report, section 1: the RSR and the sigma.7 as configured.

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "robot/rsr_kinematics.h"
#include "robot/sigma7_model.h"
#include "src/apps/demo.h"
#include "src/apps/rsr_json.h"
#include "src/core/units.h"

namespace robossis::apps {

namespace {

std::string Fmt(double v, int decimals = 1) { return FormatFixed(v, decimals); }

// Largest s in [0, s_max] with feasible(s) true for all of [0, s], by bisection (feasible(0) must hold).
double ReachAlong(const std::function<bool(double)>& feasible, double s_max) {
  double lo = 0.0, hi = s_max;
  if (feasible(hi)) return hi;
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    (feasible(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

void WriteRobotSection(DemoContext& demo) {
  demo.Progress("robot: geometry, limits, reach about home");
  const robot::RsrModel model = demo.app.LoadRsr();
  const robot::Sigma7Model hc = demo.app.LoadSigma7();
  const robot::RsrGeometry& g = model.geometry();
  const robot::RsrIkResult home = robot::CalcInverseKinematics(model, g.X_FM_home);
  demo.out.Write("robot/rsr_info.json", RsrInfoJson(model).dump(2) + "\n");

  std::ostringstream& r = demo.report;
  r << "## 1. The robots\n\n"
    << "### RSR geometry (follower)\n\n"
    << "Three arms at gamma_i = " << Fmt(RadToDeg(g.arm_angles_rad[0]), 0) << "°, "
    << Fmt(RadToDeg(g.arm_angles_rad[1]), 0) << "°, " << Fmt(RadToDeg(g.arm_angles_rad[2]), 0)
    << "° (paper §III-B). Each arm: active rotary joint theta_i about a radial axis in the fixed-ring plane, passive "
       "joint psi_i, linear actuator d_i, spherical joint on the moving ring.\n\n"
    << "| arm | fixed-ring joint A_i (mm, frame F) | moving-ring joint B_i (mm, frame M) |\n|---|---|---|\n";
  for (int i = 0; i < robot::kNumArms; ++i) {
    const Eigen::Vector3d a = g.p_FA[i] * kMToMm, b = g.p_MB[i] * kMToMm;
    r << "| " << i + 1 << " | (" << Fmt(a.x()) << ", " << Fmt(a.y()) << ", " << Fmt(a.z()) << ") | (" << Fmt(b.x())
      << ", " << Fmt(b.y()) << ", " << Fmt(b.z()) << ") |\n";
  }
  r << "\n**Assumptions** (the paper gives none of these; all are in `config/rsr.yaml`): ring joint radii "
    << Fmt(g.p_FA[0].head<2>().norm() * kMToMm, 0) << " mm (fixed) and " << Fmt(g.p_MB[0].head<2>().norm() * kMToMm, 0)
    << " mm (moving); joints in the ring planes; home pose with every arm at mid-stroke; rotary range ±"
    << Fmt(RadToDeg(g.limits.rotary_max_rad), 0)
    << "°; the spherical-joint limit read as the angle between the leg and the moving-ring normal.\n\n";

  r << "### Home pose\n\n| arm | theta (deg) | d (mm) | psi (deg) | cone (deg) |\n|---|---|---|---|---|\n";
  for (int i = 0; i < robot::kNumArms; ++i) {
    r << "| " << i + 1 << " | " << Fmt(RadToDeg(home.joints.theta_rad[i]), 3) << " | "
      << Fmt(MToMm(home.joints.d_m[i]), 3) << " | " << Fmt(RadToDeg(home.joints.psi_rad[i]), 3) << " | "
      << Fmt(RadToDeg(home.joints.cone_rad[i]), 3) << " |\n";
  }

  // Reach from home along each axis: where the first limit is met.
  const Eigen::Isometry3d X0 = g.X_FM_home;
  auto translate = [&](const Eigen::Vector3d& dir) {
    return ReachAlong([&](double s) {
      Eigen::Isometry3d X = X0;
      X.translation() += s * dir;
      return robot::IsPoseFeasible(model, X);
    }, 1.0);
  };
  auto rotate = [&](const Eigen::Vector3d& axis) {
    return ReachAlong([&](double s) {
      Eigen::Isometry3d X = X0;
      X.linear() = Eigen::AngleAxisd(s, axis).toRotationMatrix() * X0.linear();
      return robot::IsPoseFeasible(model, X);
    }, kPi);
  };
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Eigen::Vector3d::UnitY(), ez = Eigen::Vector3d::UnitZ();
  struct Reach {
    std::string name, unit, paper;
    double minus, plus;
  };
  const Reach reach[] = {
      {"x", "mm", "±130 (assumed geometry)", -MToMm(translate(-ex)), MToMm(translate(ex))},
      {"y", "mm", "±130 (assumed geometry)", -MToMm(translate(-ey)), MToMm(translate(ey))},
      {"z", "mm", "±70 (assumed geometry)", -MToMm(translate(-ez)), MToMm(translate(ez))},
      {"roll (tilt about x)", "deg", "±20 (assumed geometry)", -RadToDeg(rotate(-ex)), RadToDeg(rotate(ex))},
      {"pitch (tilt about y)", "deg", "±20 (assumed geometry)", -RadToDeg(rotate(-ey)), RadToDeg(rotate(ey))},
      {"yaw (twist about z)", "deg", "±39 (assumed geometry)", -RadToDeg(rotate(-ez)), RadToDeg(rotate(ez))},
  };
  std::string csv = "axis,unit,minus,plus\n";
  r << "\n### Limits and reach: paper vs this model\n\n| quantity | paper / design brief | this model |\n|---|---|---|\n"
    << "| linear actuator stroke | 0.284 ± 0.070 m (0.214–0.354 m), §III-B | "
    << Fmt(g.limits.stroke_min_m, 3) << "–" << Fmt(g.limits.stroke_max_m, 3) << " m |\n"
    << "| spherical joints | ±25°, §III-B | cone ≤ " << Fmt(RadToDeg(g.limits.spherical_cone_max_rad), 1) << "° |\n"
    << "| active rotary joint | not given | ±" << Fmt(RadToDeg(g.limits.rotary_max_rad), 1) << "° (assumed) |\n";
  for (const Reach& x : reach) {
    r << "| reach from home along " << x.name << " (" << x.unit << ") | " << x.paper << " | " << Fmt(x.minus)
      << " / +" << Fmt(x.plus) << " |\n";
    csv += x.name + "," + x.unit + "," + Fmt(x.minus, 4) + "," + Fmt(x.plus, 4) + "\n";
  }
  demo.out.Write("robot/reach_from_home.csv", csv);

  Vector6d axial_load = Vector6d::Zero();
  axial_load[2] = -517.0;  // paper §I: 517 N traction, here along the robot axis
  const robot::RsrStaticsResult statics = robot::CalcActuatorEfforts(model, X0, axial_load);
  r << "| linear actuator force for a 517 N axial load at home | ~172 N each (assumed geometry) | "
    << Fmt(statics.linear_force_n[0]) << ", " << Fmt(statics.linear_force_n[1]) << ", "
    << Fmt(statics.linear_force_n[2]) << " N |\n\n";

  const robot::Sigma7Geometry& h = hc.geometry();
  r << "### sigma.7 (leader)\n\n"
    << "Delta a = " << Fmt(MToMm(h.a_m), 0) << " mm, b = " << Fmt(MToMm(h.b_m), 0) << " mm, r = "
    << Fmt(MToMm(h.r_m), 0) << " mm, c = " << Fmt(MToMm(h.c_m), 0) << " mm, f = " << Fmt(MToMm(h.f_m), 0)
    << " mm, tilt " << Fmt(RadToDeg(h.tilt_rad), 0) << "° (paper §III-A); offset s = " << Fmt(MToMm(h.s_m), 0)
    << " mm (not given; assumed). Actuated range " << Fmt(RadToDeg(h.theta1_min_rad), 0) << "° to "
    << Fmt(RadToDeg(h.theta1_max_rad), 0) << "° (assumed). Wrist ranges "
    << Fmt(2 * RadToDeg(h.wrist_half_range_rad.z()), 0) << "° × " << Fmt(2 * RadToDeg(h.wrist_half_range_rad.y()), 0)
    << "° × " << Fmt(2 * RadToDeg(h.wrist_half_range_rad.x()), 0) << "° (paper: 235° × 140° × 200°). "
    << "Workspace centre (FK of mid-range angles): (" << Fmt(MToMm(hc.p_center_O().x())) << ", "
    << Fmt(MToMm(hc.p_center_O().y())) << ", " << Fmt(MToMm(hc.p_center_O().z())) << ") mm.\n\n";
}

}  // namespace robossis::apps
