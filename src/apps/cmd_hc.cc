// `robossis hc ...`: the sigma.7 haptic controller's delta IK/FK and workspace test.

#include <iostream>
#include <memory>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "robot/sigma7_model.h"
#include "src/apps/app_context.h"
#include "src/apps/rsr_json.h"
#include "src/core/parse.h"
#include "src/core/units.h"

namespace robossis::apps {

namespace {
using json = nlohmann::ordered_json;

json Deg(const Eigen::Vector3d& v) { return json::array({RadToDeg(v.x()), RadToDeg(v.y()), RadToDeg(v.z())}); }
json Mm(const Eigen::Vector3d& v) { return json::array({MToMm(v.x()), MToMm(v.y()), MToMm(v.z())}); }

void Print(const json& doc, bool as_json) {
  if (as_json) {
    PrintJson(doc);
  } else {
    PrintKeyValues(doc);
  }
}
}  // namespace

void RegisterHcCommands(CLI::App& app, const AppContext& context) {
  CLI::App* hc = app.add_subcommand("hc", "sigma.7 haptic controller kinematics (eq. 1-4): ik, fk");
  hc->require_subcommand(1);

  CLI::App* ik = hc->add_subcommand(
      "ik", "Delta inverse kinematics of the handle position, and the wrist-range test of an orientation\n"
            "Example: robossis hc ik --position 61,0,-61 --rpy-deg 0,30,0 --json");
  auto position = std::make_shared<std::string>();
  auto rpy = std::make_shared<std::string>();
  auto ik_json = std::make_shared<bool>(false);
  ik->add_option("--position", *position, "Handle centre P in the base frame: X_MM,Y_MM,Z_MM")->required();
  ik->add_option("--rpy-deg", *rpy, "Handle orientation ROLL_DEG,PITCH_DEG,YAW_DEG (default 0,0,0)");
  ik->add_flag("--json", *ik_json, "Machine-readable output");
  ik->callback([&context, position, rpy, ik_json] {
    const std::vector<double> p = ParseNumberList(*position, 3, "--position", "X_MM,Y_MM,Z_MM", FieldBounds::kWorkspace);
    std::vector<double> r = {0, 0, 0};
    if (!rpy->empty()) r = ParseNumberList(*rpy, 3, "--rpy-deg", "ROLL_DEG,PITCH_DEG,YAW_DEG", FieldBounds::kWorkspace);
    const robot::Sigma7Model model = context.LoadSigma7();
    const Eigen::Vector3d p_O = Eigen::Vector3d(p[0], p[1], p[2]) * kMmToM;
    // The range is a property of the orientation, not of the numbers given for it: 0,300,0 and 0,-60,0 are one
    // rotation, tested as the wrist's joint angles of that rotation.
    const Eigen::Vector3d wrist =
        robot::WristJointsFromRotation(RotationFromRpy(Eigen::Vector3d(r[0], r[1], r[2]) * kDegToRad));
    const robot::DeltaIkResult result = robot::CalcDeltaInverseKinematics(model, p_O);
    const bool wrist_ok = robot::WristWithinRange(model, wrist);
    Print({{"reachable", result.reachable},
           {"within_limits", result.within_limits},
           {"theta1_deg", result.reachable ? Deg(result.joints.theta1) : json(nullptr)},
           {"theta2_deg", result.reachable ? Deg(result.joints.theta2) : json(nullptr)},
           {"theta3_deg", result.reachable ? Deg(result.joints.theta3) : json(nullptr)},
           {"wrist_rpy_deg", Deg(wrist)},
           {"wrist_within_range", wrist_ok},
           {"in_workspace", result.within_limits && wrist_ok}},
          *ik_json);
  });

  CLI::App* fk = hc->add_subcommand("fk", "Delta forward kinematics from the three actuated angles\n"
                                          "Example: robossis hc fk --joints 25,25,25 --json");
  auto joints = std::make_shared<std::string>();
  auto fk_json = std::make_shared<bool>(false);
  fk->add_option("--joints", *joints, "Actuated angles TH11_DEG,TH12_DEG,TH13_DEG")->required();
  fk->add_flag("--json", *fk_json, "Machine-readable output");
  fk->callback([&context, joints, fk_json] {
    const std::vector<double> t = ParseNumberList(*joints, 3, "--joints", "TH11_DEG,TH12_DEG,TH13_DEG", FieldBounds::kWorkspace);
    const robot::Sigma7Model model = context.LoadSigma7();
    const robot::DeltaFkResult result =
        robot::CalcDeltaForwardKinematics(model, Eigen::Vector3d(t[0], t[1], t[2]) * kDegToRad);
    if (!result.ok) throw std::runtime_error("--joints: the delta does not assemble at these angles");
    const robot::DeltaIkResult check = robot::CalcDeltaInverseKinematics(model, result.p_O);
    Print({{"ok", result.ok}, {"position_mm", Mm(result.p_O)}, {"within_limits", check.within_limits}}, *fk_json);
  });
}

}  // namespace robossis::apps
