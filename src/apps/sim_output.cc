#include "src/apps/sim_output.h"

#include <nlohmann/json.hpp>

#include "src/core/units.h"

namespace robossis::apps {

using json = nlohmann::ordered_json;

json SimSummaryJson(const sim::ScenarioSummary& s) {
  json j;
  j["max_translation_error_mm"] = s.max_translation_error_mm;
  j["mean_translation_error_mm"] = s.mean_translation_error_mm;
  j["max_rotation_error_deg"] = s.max_rotation_error_deg;
  j["mean_rotation_error_deg"] = s.mean_rotation_error_deg;
  j["max_actuator_force_n"] = s.max_actuator_force_n;
  j["max_actuator_torque_nm"] = s.max_actuator_torque_nm;
  j["realtime_factor"] = s.realtime_factor;
  return j;
}

json SimDetailsJson(const sim::ScenarioResult& r, const sim::SimConfig& config) {
  const sim::ScenarioSummary& s = r.summary;
  json j;
  j["scenario"] = sim::ToString(r.params.kind);
  j["load_n"] = r.params.load_n;
  j["load_nm"] = r.params.load_nm;
  j["duration_s"] = r.params.duration_s;
  j["gravity"] = r.params.gravity;
  j["step_hz"] = config.physics.step_hz;
  j["solver"] = config.physics.solver == sim::ConstraintSolverKind::kDantzig ? "dantzig" : "pgs";
  j["steps"] = s.steps;
  j["simulated_s"] = s.simulated_s;
  j["wall_s"] = s.wall_s;
  j["cpu_s"] = s.cpu_s;
  j["realtime_factor_wall"] = s.realtime_factor_wall;
  j["actuator_limit_reached"] = s.actuator_limit_reached;
  j["actuator_limit_steps"] = s.actuator_limit_steps;
  j["actuator_limit_message"] = s.actuator_limit_message;
  j["linear_force_limit_n"] = config.actuators.linear_force_max_n;
  j["rotary_torque_limit_nm"] = config.actuators.rotary_torque_max_nm;
  j["joint_end_stop_reached"] = s.joint_limit_reached;
  j["max_spherical_cone_deg"] = s.max_spherical_cone_deg;
  j["spherical_limit_exceeded"] = s.spherical_limit_exceeded;
  j["statics_linear_relative_error"] = s.statics_linear_rel_error;
  j["statics_rotary_relative_error"] = s.statics_rotary_rel_error;
  j["statics_steps"] = s.statics_steps;
  j["statics_within_5_percent"] = s.statics_linear_rel_error <= 0.05 && s.statics_rotary_rel_error <= 0.05;
  j["max_penetration_mm"] = s.max_penetration_mm;
  j["penetration_tolerance_mm"] = s.penetration_tolerance_mm;
  j["contact_steps"] = s.contact_steps;
  j["peak_traction_n"] = s.peak_traction_n;
  j["peak_traction_torque_nm"] = s.peak_traction_torque_nm;
  j["max_loop_closure_error_mm"] = MToMm(s.max_loop_error_m);
  j["ring_and_fragment_mass_kg"] = s.ring_mass_kg;
  j["unstable"] = s.unstable;
  return j;
}

PlotResult WriteSimOutputs(const StagedOutputDir& out, const std::string& prefix, const sim::ScenarioResult& result,
                           const sim::SimConfig& config) {
  out.Write(prefix + "trajectory.csv", sim::TrajectoryCsv(result));
  out.Write(prefix + "summary.json", SimSummaryJson(result.summary).dump(2) + "\n");
  out.Write(prefix + "details.json", SimDetailsJson(result, config).dump(2) + "\n");
  const std::string title = std::string(sim::ToString(result.params.kind)) + ", load " +
                            std::to_string(static_cast<int>(result.params.load_n)) + " N / " +
                            std::to_string(static_cast<int>(result.params.load_nm)) + " N·m";
  return RunPlotScript("sim_fig7.py", {"--csv", out.Path(prefix + "trajectory.csv").string(), "--title", title,
                                       "--out", out.Path(prefix + "fig7_sim.png").string()});
}

void WriteFragments(const StagedOutputDir& out, const std::string& prefix, const sim::BoneFragments& fragments,
                    const sim::SimConfig& config) {
  const std::string mark = "ALTERED from FemurR.stl (BMFToolkit, zlib licence): cut at mid-shaft and capped by Robossis";
  out.Write(prefix + "fragment_proximal.stl", sim::StlAscii(fragments.proximal_F, mark + " - proximal, frame F"));
  out.Write(prefix + "fragment_distal.stl", sim::StlAscii(fragments.distal_M, mark + " - distal, frame M"));
  out.Write(prefix + "NOTICE_femur.txt", sim::FragmentNotice(config));
}

}  // namespace robossis::apps
