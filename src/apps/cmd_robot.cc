// `robossis robot ...`: the RSR model, its inverse and forward kinematics, Jacobian and statics.

#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "robot/rsr_kinematics.h"
#include "src/apps/app_context.h"
#include "src/apps/rsr_json.h"
#include "src/core/parse.h"
#include "src/core/units.h"

namespace robossis::apps {

namespace {

using json = nlohmann::ordered_json;
using robot::kNumArms;

void PrintIkText(const robot::RsrIkResult& ik) {
  std::cout << std::fixed << std::setprecision(4) << (ik.feasible ? "feasible" : "NOT feasible") << "\n";
  for (int i = 0; i < kNumArms; ++i) {
    std::cout << "arm " << i + 1 << ": theta " << RadToDeg(ik.joints.theta_rad[i]) << " deg, d "
              << MToMm(ik.joints.d_m[i]) << " mm, psi " << RadToDeg(ik.joints.psi_rad[i]) << " deg, cone "
              << RadToDeg(ik.joints.cone_rad[i]) << " deg\n";
  }
  for (const auto& c : ik.checks) {
    if (c.margin < 0) std::cout << "violation: " << ViolationText(c) << "\n";
  }
}

// "feasible: false (outside the joint limits)" and one line per violated limit: a result computed at a pose the
// robot cannot reach is printed, and said to be so.
void PrintFeasibility(const json& feasibility) {
  const bool feasible = feasibility.at("feasible").get<bool>();
  std::cout << "feasible: " << (feasible ? "true" : "false (outside the joint limits; the result is the model's, "
                                                    "not a pose the robot reaches)")
            << "\n";
  for (const auto& v : feasibility.at("violations")) std::cout << "violation: " << v.get<std::string>() << "\n";
}

struct PoseOption {
  std::string text;
  CLI::Option* Add(CLI::App* cmd) {
    return cmd->add_option("--pose", text, "Moving-ring pose in the fixed-ring frame: X_MM,Y_MM,Z_MM,ROLL_DEG,PITCH_DEG,YAW_DEG")
        ->required();
  }
  Eigen::Isometry3d Parse() const { return ParsePoseMmDeg(text, "--pose"); }
};

}  // namespace

void RegisterRobotCommands(CLI::App& app, const AppContext& context) {
  CLI::App* robot = app.add_subcommand("robot", "RSR kinematics: info, ik, fk, jacobian, statics");
  robot->require_subcommand(1);

  CLI::App* info = robot->add_subcommand("info", "Geometry, home pose and joint limits of the RSR\n"
                                                 "Example: robossis robot info --json");
  auto info_json = std::make_shared<bool>(false);
  info->add_flag("--json", *info_json, "Machine-readable output");
  info->callback([&context, info_json] {
    const robot::RsrModel model = context.LoadRsr();
    const json doc = RsrInfoJson(model);
    if (*info_json) {
      PrintJson(doc);
    } else {
      PrintKeyValues(doc);
    }
  });

  CLI::App* ik = robot->add_subcommand("ik", "Inverse kinematics (eq. 5-8) with a per-limit feasibility verdict\n"
                                             "Example: robossis robot ik --pose 20,0,290,0,5,10 --json");
  auto ik_pose = std::make_shared<PoseOption>();
  auto ik_json = std::make_shared<bool>(false);
  ik_pose->Add(ik);
  ik->add_flag("--json", *ik_json, "Machine-readable output");
  ik->callback([&context, ik_pose, ik_json] {
    const Eigen::Isometry3d X_FM = ik_pose->Parse();
    const robot::RsrModel model = context.LoadRsr();
    const robot::RsrIkResult result = robot::CalcInverseKinematics(model, X_FM);
    RequireFiniteResult(RsrIkJson(result), "robot ik --pose " + ik_pose->text);
    if (*ik_json) {
      PrintJson(RsrIkJson(result));
    } else {
      PrintIkText(result);
    }
  });

  CLI::App* fk = robot->add_subcommand(
      "fk", "Forward kinematics by Newton iteration, warm-started at the home pose (or --guess)\n"
            "Example: robossis robot fk --joints 0,0,0,284,290,300 --json");
  auto fk_joints = std::make_shared<std::string>();
  auto fk_guess = std::make_shared<std::string>();
  auto fk_json = std::make_shared<bool>(false);
  fk->add_option("--joints", *fk_joints, "Actuated joints TH1_DEG,TH2_DEG,TH3_DEG,D1_MM,D2_MM,D3_MM")->required();
  fk->add_option("--guess", *fk_guess, "Start pose X_MM,Y_MM,Z_MM,ROLL_DEG,PITCH_DEG,YAW_DEG (default: home)");
  fk->add_flag("--json", *fk_json, "Machine-readable output");
  fk->callback([&context, fk_joints, fk_guess, fk_json] {
    const std::vector<double> v =
        ParseNumberList(*fk_joints, 6, "--joints", "TH1_DEG,TH2_DEG,TH3_DEG,D1_MM,D2_MM,D3_MM",
                        FieldBounds::kWorkspace);
    robot::RsrJointVector q;
    for (int i = 0; i < kNumArms; ++i) {
      q[robot::ThetaIndex(i)] = DegToRad(v[i]);
      q[robot::StrokeIndex(i)] = MmToM(v[3 + i]);
      if (!(v[3 + i] > 0)) {
        throw std::invalid_argument("--joints: D" + std::to_string(i + 1) + "_MM must be positive, got " +
                                    std::to_string(v[3 + i]));
      }
    }
    const robot::RsrModel model = context.LoadRsr();
    const Eigen::Isometry3d guess =
        fk_guess->empty() ? model.geometry().X_FM_home : ParsePoseMmDeg(*fk_guess, "--guess");
    const robot::RsrFkResult result = robot::CalcForwardKinematics(model, q, guess);
    json doc = RsrFkJson(result);
    if (result.converged()) doc.update(RsrFeasibilityJson(robot::CalcInverseKinematics(model, result.X_FM)));
    if (*fk_json) {
      PrintJson(doc);
    } else {
      PrintKeyValues(RsrFkJson(result));
      if (result.converged()) PrintFeasibility(doc);
    }
    if (!result.converged()) throw std::runtime_error("forward kinematics did not converge (" +
                                                      std::string(robot::ToString(result.status)) + ")");
  });

  CLI::App* jac = robot->add_subcommand("jacobian", "Jacobian of eq. 15 (q_dot = J [v; omega]) at a pose\n"
                                                    "Example: robossis robot jacobian --pose 0,0,284,0,0,0 --json");
  auto jac_pose = std::make_shared<PoseOption>();
  auto jac_json = std::make_shared<bool>(false);
  jac_pose->Add(jac);
  jac->add_flag("--json", *jac_json, "Machine-readable output");
  jac->callback([&context, jac_pose, jac_json] {
    const robot::RsrModel model = context.LoadRsr();
    const Eigen::Isometry3d X_FM = jac_pose->Parse();
    const Matrix6d J = robot::CalcJacobian(model, X_FM);
    json doc = RsrJacobianJson(J);
    RequireFiniteResult(doc, "robot jacobian --pose " + jac_pose->text);
    const json feasibility = RsrFeasibilityJson(robot::CalcInverseKinematics(model, X_FM));
    doc.update(feasibility);
    if (*jac_json) {
      PrintJson(doc);
    } else {
      std::cout << "rows: theta_1..3 (rad/s), d_1..3 (m/s); columns: v (m/s), omega (rad/s), in the fixed frame\n"
                << J << "\n";
      PrintFeasibility(feasibility);
    }
  });

  CLI::App* statics = robot->add_subcommand(
      "statics", "Actuator forces/torques holding the ring against an external wrench (Q = -J^-T W)\n"
                 "Example: robossis robot statics --pose 0,0,284,0,0,0 --wrench 0,0,-517,0,0,0 --json");
  auto st_pose = std::make_shared<PoseOption>();
  auto st_wrench = std::make_shared<std::string>();
  auto st_json = std::make_shared<bool>(false);
  st_pose->Add(statics);
  statics->add_option("--wrench", *st_wrench, "External wrench on the moving ring at P, in the fixed frame: "
                                              "FX_N,FY_N,FZ_N,TX_NM,TY_NM,TZ_NM; forces within +/-1e6 N, moments "
                                              "within +/-1e5 N m")
      ->required();
  statics->add_flag("--json", *st_json, "Machine-readable output");
  statics->callback([&context, st_pose, st_wrench, st_json] {
    const Eigen::Isometry3d X_FM = st_pose->Parse();
    const std::vector<double> w = ParseNumberList(*st_wrench, 6, "--wrench", "FX_N,FY_N,FZ_N,TX_NM,TY_NM,TZ_NM");
    const Vector6d wrench = Eigen::Map<const Vector6d>(w.data());
    robot::RequireBoundedWrench(wrench, "--wrench");
    const robot::RsrModel model = context.LoadRsr();
    const robot::RsrStaticsResult result = robot::CalcActuatorEfforts(model, X_FM, wrench);
    if (result.singular) throw std::runtime_error("--pose: the Jacobian is singular there; no static solution");
    json doc = RsrStaticsJson(result);
    RequireFiniteResult(doc, "robot statics --pose " + st_pose->text);
    const json feasibility = RsrFeasibilityJson(robot::CalcInverseKinematics(model, X_FM));
    doc.update(feasibility);
    if (*st_json) {
      PrintJson(doc);
    } else {
      PrintKeyValues(RsrStaticsJson(result));
      PrintFeasibility(feasibility);
    }
  });
}

}  // namespace robossis::apps
