#include "src/apps/teleop_options.h"

#include <cmath>
#include <iostream>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "geometry/boundary_atlas.h"
#include "haptics/rendering/method_names.h"
#include "src/apps/plotting.h"
#include "src/core/units.h"

namespace robossis::apps {

void AddTeleopOptions(CLI::App& cmd, TeleopCliOptions& o, TeleopUnits units) {
  if (units != TeleopUnits::kFollower) {
    cmd.add_option("--device", o.device,
                   "sim | replay:FILE.csv (t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg) | dhd[:lib=PATH,serial=N,"
                   "index=N,hold=1,window_ms=MS] (a sigma.7 through the Force Dimension SDK)")
        ->capture_default_str();
    cmd.add_option("--method", o.method,
                   "Rendering method: " + haptics::KnownMethodsText() +
                       " (default: haptics.yaml hardware_default_method)");
    cmd.add_option("--rate-hz", o.rate_hz, "Leader loop rate: 1000 or 4000 (a multiple of the 1 kHz transfer)")
        ->capture_default_str();
    cmd.add_option("--atlas", o.atlas, "Boundary atlas folder for mesh/mesh-live (default: build the coarse one)");
    cmd.add_option("--feedback", o.feedback,
                   "walls (the walls alone) | bilateral (the walls and the follower's load, passive under delay; "
                   "default: leader.yaml feedback.mode)");
    cmd.add_option("--feedback-gain", o.feedback_gain,
                   "Share of the follower's wrench felt at the hand, 0-1 (default: leader.yaml feedback.gain)")
        ->check(CLI::Range(0.0, 1.0));
    cmd.add_option("--feedback-passivity", o.feedback_passivity,
                   "The load's passivity controller: off | classic (one-port) | network (delay-aware; default: "
                   "leader.yaml feedback.passivity)");
    cmd.add_flag("--let-go-detector", o.let_go_detector,
                 "The leader drops the load and damps the device once it believes the operator let go "
                 "(src/teleop/let_go_detector.h; default: leader.yaml feedback.detect_let_go)");
  }
  if (units != TeleopUnits::kLeader) {
    cmd.add_option("--follower", o.follower,
                   "sim (Bullet) | recorder (pulse recorder) | hal (step/direction drives through LinuxCNC HAL, "
                   "hal.yaml)")
        ->capture_default_str();
    cmd.add_flag("--home", o.home,
                 "Home at start. For --follower hal this is the operator's declaration that the robot stands at its "
                 "home pose now: step/direction drives cannot measure where they are, so the HAL follower starts "
                 "unhomed after every start (a crash, a power cut, a moved robot) and refuses enable until homed. "
                 "sim and recorder measure their joints and are homed from their start");
    CLI::Option* enable = cmd.add_flag(
        "--enable", o.enable, "Enable at start, after --home (default for sim and recorder; refused while unhomed)");
    cmd.add_flag("--no-enable", o.no_enable, "Start disabled (default for --follower hal)")->excludes(enable);
    cmd.add_option("--sim-load-n", o.sim_load_n,
                   "--follower sim: the muscles' traction along the femur axis at the home pose, N (paper: 517)")
        ->check(CLI::Range(0.0, 1000.0));
    cmd.add_option("--sim-load-nm", o.sim_load_nm,
                   "--follower sim: the muscles' torque about the femur axis at the home pose, N·m (paper: 74)")
        ->check(CLI::Range(0.0, 100.0));
  }
  cmd.add_option("--duration-s", o.duration_s, "Run time (a replay ends 0.5 s after its last sample)")
      ->capture_default_str();
  cmd.add_option("--out", o.out, "Output folder (written atomically: complete or untouched)")->required();
  cmd.add_option("--max-speed-mm-s", o.max_speed_mm_s, LinearSpeedCapHelp());
  cmd.add_option("--max-angular-speed-deg-s", o.max_angular_speed_deg_s, AngularSpeedCapHelp());
  cmd.add_flag("--no-plots", o.no_plots, "Skip the figure");
  cmd.add_flag("--json", o.json, "Print summary.json to stdout");
}

TeleopInputs::TeleopInputs(const AppContext& context, const TeleopCliOptions& o, bool real_clock)
    : rsr(context.LoadRsr()),
      sigma7(context.LoadSigma7()),
      setup(teleop::TeleopSetup::Load(context.data_dir, rsr, sigma7)) {
  // The caps' one checker (transfer_config.h), as for transfer.yaml.
  if (o.max_speed_mm_s) {
    setup.transfer.caps.max_linear_speed_m_s = MmToM(*o.max_speed_mm_s);
    transfer::CheckLinearSpeedCap(setup.transfer.caps.max_linear_speed_m_s, "--max-speed-mm-s");
  }
  if (o.max_angular_speed_deg_s) {
    setup.transfer.caps.max_angular_speed_rad_s = DegToRad(*o.max_angular_speed_deg_s);
    transfer::CheckAngularSpeedCap(setup.transfer.caps.max_angular_speed_rad_s, "--max-angular-speed-deg-s");
  }
  setup.transfer.Validate();
  setup.follower.setpoint.caps = setup.transfer.caps;  // the follower checks the caps the leader applies
  request.device = o.device;
  // The one parser of method names: a given name is checked, an empty one refused (never "the default").
  request.method =
      o.method ? haptics::ParseMethodName(*o.method, "--method") : setup.haptics.hardware_default_method;
  request.follower = o.follower;
  request.home_at_start = o.home;
  request.enable_at_start = o.enable || (!o.no_enable && teleop::EnablesAtStartByDefault(o.follower));
  request.rate_hz = o.rate_hz;
  request.duration_s = o.duration_s;
  request.real_clock = real_clock;
  if (o.feedback) teleop::ParseFeedbackMode("--feedback", *o.feedback);  // checked before any work
  request.feedback = o.feedback.value_or("");
  request.feedback_gain = o.feedback_gain.value_or(-1.0);
  if (o.feedback_passivity) teleop::ParseFeedbackPassivityScheme("--feedback-passivity", *o.feedback_passivity);
  request.feedback_passivity = o.feedback_passivity.value_or("");
  request.let_go_detector = o.let_go_detector;
  if ((o.sim_load_n > 0 || o.sim_load_nm > 0) && o.follower != "sim") {
    throw std::invalid_argument("--sim-load-n/--sim-load-nm: only the Bullet follower (--follower sim) has muscles");
  }
  request.sim_load_n = o.sim_load_n;
  request.sim_load_nm = o.sim_load_nm;
}

std::vector<std::string> FeedbackArgs(const TeleopCliOptions& o) {
  std::vector<std::string> args;
  if (o.feedback) args.insert(args.end(), {"--feedback", *o.feedback});
  if (o.feedback_gain) args.insert(args.end(), {"--feedback-gain", std::to_string(*o.feedback_gain)});
  if (o.feedback_passivity) args.insert(args.end(), {"--feedback-passivity", *o.feedback_passivity});
  if (o.let_go_detector) args.push_back("--let-go-detector");
  return args;
}

std::vector<std::string> SimLoadArgs(const TeleopCliOptions& o) {
  return {"--sim-load-n", std::to_string(o.sim_load_n), "--sim-load-nm", std::to_string(o.sim_load_nm)};
}

void TeleopInputs::LoadAtlasIfNeeded(const TeleopCliOptions& o, const std::filesystem::path& scratch) {
  if (request.method.rfind("mesh", 0) != 0) return;
  request.atlas = std::make_shared<const geometry::BoundaryAtlas>(
      o.atlas.empty() ? geometry::BuildAtlas(rsr, sigma7, geometry::AtlasSpec::Coarse(rsr), scratch / "atlas")
                      : geometry::BoundaryAtlas::Load(o.atlas));
}

void CommitTeleopOutputs(StagedOutputDir& out, const teleop::TeleopOutputs& o, TeleopUnits units, bool plots) {
  out.Write("summary.json", o.summary.dump(2) + "\n");
  // An empty text (not even the header): the run streamed that CSV into the staging folder.
  if (units != TeleopUnits::kFollower && !o.leader_csv.empty()) out.Write("leader.csv", o.leader_csv);
  if (units != TeleopUnits::kLeader && !o.follower_csv.empty()) out.Write("follower.csv", o.follower_csv);
  out.Write("loop_periods.csv", o.periods_csv);
  if (plots && units == TeleopUnits::kBoth && o.recorder_error.empty()) {
    const PlotResult r = RunPlotScript("teleop_session.py", {"--dir", out.staging().string(), "--out",
                                                             out.Path("teleop.png").string()});
    if (!r.ok) std::cerr << "robossis: warning: teleop.png not rendered: " << r.message << "\n";
  }
  out.Commit();
  if (!o.recorder_error.empty()) throw std::runtime_error(o.recorder_error + " (what was recorded: " +
                                                          out.target().string() + ")");
}

}  // namespace robossis::apps
