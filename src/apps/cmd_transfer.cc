// `robossis transfer` and `robossis move`: the motion transfer and actuation chain from the command line.

#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "haptics/transfer/hc_trajectory.h"
#include "src/apps/app_context.h"
#include "src/apps/plotting.h"
#include "src/apps/transfer_run.h"
#include "src/core/parse.h"
#include "src/core/units.h"

namespace robossis::apps {

namespace {

// A number for a message, as printf formats it.
std::string Num(double v, const char* format = "%g") { return FormatNumber(v, format); }

// [assumed] The longest move the command line accepts: an hour (a 25 deg turn at the clinical 0.2 deg/s takes
// 3.5 min); checked before any work starts.
constexpr double kMaxMoveDurationS = 3600;

struct CommonOptions {
  std::string out;
  std::string start_pose;
  double max_speed_mm_s = 0;
  double max_angular_speed_deg_s = 0;
  CLI::Option* max_speed_opt = nullptr;
  CLI::Option* max_angular_speed_opt = nullptr;
  bool clinical = false;
  bool no_plots = false;
  bool json = false;

  void Add(CLI::App* cmd) {
    cmd->add_option("--out", out, "Output folder (written atomically: complete or untouched)")->required();
    cmd->add_option("--start-pose", start_pose, "Start pose X_MM,Y_MM,Z_MM,ROLL_DEG,PITCH_DEG,YAW_DEG (default: home)");
    max_speed_opt = cmd->add_option("--max-speed-mm-s", max_speed_mm_s, LinearSpeedCapHelp());
    max_angular_speed_opt =
        cmd->add_option("--max-angular-speed-deg-s", max_angular_speed_deg_s, AngularSpeedCapHelp());
    CLI::Option* clinical_opt =
        cmd->add_flag("--clinical", clinical, "Clinical caps of the paper: 2 mm/s and 0.2 deg/s");
    clinical_opt->excludes(max_speed_opt)->excludes(max_angular_speed_opt);
    cmd->add_flag("--no-plots", no_plots, "Skip the PNG figures (CSV and JSON only)");
    cmd->add_flag("--json", json, "Print summary.json to stdout");
  }

  ChainSetup Setup(const AppContext& context, const robot::RsrModel& model) const {
    ChainSetup s = DefaultChainSetup(context, model);
    if (clinical) s.transfer.caps = transfer::ClinicalSpeedCaps();
    // A given value is used as given: 0 is a value (and refused), never "the default".
    // The caps' one checker (transfer_config.h), as for transfer.yaml.
    if (max_speed_opt->count() > 0) {
      s.transfer.caps.max_linear_speed_m_s = MmToM(max_speed_mm_s);
      transfer::CheckLinearSpeedCap(s.transfer.caps.max_linear_speed_m_s, "--max-speed-mm-s");
    }
    if (max_angular_speed_opt->count() > 0) {
      s.transfer.caps.max_angular_speed_rad_s = DegToRad(max_angular_speed_deg_s);
      transfer::CheckAngularSpeedCap(s.transfer.caps.max_angular_speed_rad_s, "--max-angular-speed-deg-s");
    }
    s.transfer.Validate();
    if (!start_pose.empty()) s.X_FM_start = ParsePoseMmDeg(start_pose, "--start-pose");
    if (!robot::CalcInverseKinematics(model, s.X_FM_start).feasible) {
      throw std::invalid_argument("--start-pose: the pose is outside the RSR's joint limits");
    }
    return s;
  }
};

// Says so when the run met a joint limit (the guard held or slid the set-point, or the validator refused some).
void ReportLimits(const TransferSummary& s, const char* command) {
  if (s.guard_limited_ticks == 0 && s.setpoints_rejected == 0 && s.limit_ticks == 0) return;
  std::cerr << "robossis: warning: " << command << ": the follower was stopped at a joint limit for "
            << s.guard_limited_ticks << " of " << s.ticks << " ticks (" << Num(s.guard_limited_ticks * 1e-4)
            << " s at 10 kHz), " << s.setpoints_rejected << " set-points refused; tightest: " << s.tightest_limit
            << " (margin " << Num(s.min_limit_margin) << "); see summary.json\n";
}

void Plot(const StagedOutputDir& out, const std::string& script, std::vector<std::string> args,
          const std::string& png) {
  args.push_back("--out");
  args.push_back(out.Path(png).string());
  const PlotResult r = RunPlotScript(script, args);
  if (!r.ok) std::cerr << "robossis: warning: " << png << " not rendered: " << r.message << "\n";
}

void WriteOutputs(const StagedOutputDir& out, const TransferTrace& trace, const CommonOptions& options,
                  bool with_fig8) {
  out.Write("setpoints.csv", SetPointsCsv(trace));
  out.Write("joints.csv", JointsCsv(trace));
  out.Write("pulses.csv", PulsesCsv(trace));
  if (with_fig8) out.Write("transfer_1khz.csv", SlowTraceCsv(trace));
  const nlohmann::ordered_json summary = SummaryJson(trace.summary);
  out.Write("summary.json", summary.dump(2) + "\n");
  if (!options.no_plots) {
    const std::string dir = out.staging().string();
    if (with_fig8) Plot(out, "transfer_fig8.py", {"--dir", dir}, "fig8_transfer.png");
    Plot(out, "transfer_fig9.py", {"--dir", dir}, "fig9_actuation.png");
  }
  if (options.json) PrintJson(summary);
}

void PrintSummaryText(const TransferSummary& s, const std::string& out_dir) {
  std::cout << "max speed " << s.max_speed_mm_s << " mm/s, max angular speed " << s.max_angular_speed_deg_s
            << " deg/s, max accel " << s.max_accel_mm_s2 << " mm/s^2, max jerk " << s.max_jerk_mm_s3
            << " mm/s^3, delay " << s.delay_ms << " ms, steps error max " << s.steps_error_max << " steps\n"
            << "written to " << out_dir << "\n";
}

}  // namespace

void RegisterTransferCommands(CLI::App& app, const AppContext& context) {
  // robossis transfer
  CLI::App* tr = app.add_subcommand(
      "transfer", "HC trajectory → incremental mapping, scaling, 10 kHz filtering → joint velocities and pulses\n"
                  "Example: robossis transfer --scenario fig8 --out transfer-out");
  auto hc_file = std::make_shared<std::string>();
  auto scenario = std::make_shared<std::string>();
  auto tr_options = std::make_shared<CommonOptions>();
  CLI::Option* hc_opt = tr->add_option("--hc", *hc_file,
                                       "HC trajectory CSV: time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg"
                                       "[,clutch][,arrival_s]");
  std::string names;
  for (const std::string& n : transfer::ScenarioNames()) names += (names.empty() ? "" : ", ") + n;
  CLI::Option* sc_opt = tr->add_option("--scenario", *scenario, "Built-in HC trajectory: " + names);
  hc_opt->excludes(sc_opt);
  tr_options->Add(tr);
  tr->callback([&context, hc_file, scenario, tr_options] {
    if (hc_file->empty() == scenario->empty()) {
      throw std::invalid_argument("transfer: give exactly one of --hc FILE.csv or --scenario NAME");
    }
    const OutputPolicy output = context.Output({{"--hc", *hc_file}});
    output.CheckFolder("--out", tr_options->out);
    const transfer::HcTrajectory hc =
        hc_file->empty() ? transfer::MakeScenario(*scenario) : transfer::ReadHcCsv(*hc_file);
    const robot::RsrModel model = context.LoadRsr();
    const ChainSetup setup = tr_options->Setup(context, model);
    StagedOutputDir out(tr_options->out, output);
    std::cerr << "[transfer] " << hc.description << ": " << hc.records.size() << " samples\n";
    const TransferTrace trace = RunTransferChain(hc, setup);
    out.Write("hc.csv", HcRecordsCsv(hc));
    WriteOutputs(out, trace, *tr_options, true);
    out.Commit();
    if (!tr_options->json) PrintSummaryText(trace.summary, tr_options->out);
    ReportLimits(trace.summary, "transfer");
    if (trace.summary.follower_limit_violations > 0) {
      throw std::runtime_error("transfer: the commanded joints broke a joint limit at " +
                               std::to_string(trace.summary.follower_limit_violations) + " ticks");
    }
  });

  // robossis move
  CLI::App* mv = app.add_subcommand(
      "move", "Time-controlled move (eq. 9) from the start pose → joint velocities and pulses\n"
              "Example: robossis move --delta-mm 0,0,10 --delta-deg 0,0,2 --duration-s 5 --out move-out");
  auto delta_mm = std::make_shared<std::string>("0,0,0");
  auto delta_deg = std::make_shared<std::string>("0,0,0");
  auto duration = std::make_shared<double>(0);
  auto speed_mm = std::make_shared<double>(0);
  auto speed_deg = std::make_shared<double>(0);
  auto mv_options = std::make_shared<CommonOptions>();
  mv->add_option("--delta-mm", *delta_mm, "Change of position DX_MM,DY_MM,DZ_MM (fixed frame)")->capture_default_str();
  mv->add_option("--delta-deg", *delta_deg, "Change of orientation RX_DEG,RY_DEG,RZ_DEG (rotation vector, fixed axes)")
      ->capture_default_str();
  CLI::Option* dur_opt = mv->add_option("--duration-s", *duration, "Duration of the move (s)");
  CLI::Option* spd_opt = mv->add_option("--speed-mm-s", *speed_mm, "Peak linear speed instead of a duration");
  CLI::Option* spd_deg_opt = mv->add_option("--speed-deg-s", *speed_deg, "Peak angular speed instead of a duration");
  dur_opt->excludes(spd_opt)->excludes(spd_deg_opt);
  mv_options->Add(mv);
  mv->callback([&context, delta_mm, delta_deg, duration, speed_mm, speed_deg, mv_options, dur_opt, spd_opt,
                spd_deg_opt] {
    const OutputPolicy output = context.Output();
    output.CheckFolder("--out", mv_options->out);
    const std::vector<double> dp = ParseNumberList(*delta_mm, 3, "--delta-mm", "DX_MM,DY_MM,DZ_MM", FieldBounds::kWorkspace);
    const std::vector<double> dr = ParseNumberList(*delta_deg, 3, "--delta-deg", "RX_DEG,RY_DEG,RZ_DEG", FieldBounds::kWorkspace);
    transfer::TimedMoveRequest req;
    req.delta_p_F = MmToM(1.0) * Eigen::Vector3d(dp[0], dp[1], dp[2]);
    req.delta_rot_F = DegToRad(1.0) * Eigen::Vector3d(dr[0], dr[1], dr[2]);
    if (req.delta_rot_F.norm() >= kPi) throw std::invalid_argument("--delta-deg: the rotation must be below 180 deg");
    double duration_s = *duration;
    if (dur_opt->count() == 0) {  // 0 is a value: "not given" is the option's absence
      if (spd_opt->count() == 0 && spd_deg_opt->count() == 0) {
        throw std::invalid_argument("move: give --duration-s, or --speed-mm-s / --speed-deg-s");
      }
      for (const auto& [opt, value] : {std::pair{spd_opt, *speed_mm}, std::pair{spd_deg_opt, *speed_deg}}) {
        if (opt->count() > 0 && !(std::isfinite(value) && value > 0)) {
          throw std::invalid_argument(opt->get_name() + ": expected a finite speed > 0, got " + Num(value));
        }
      }
      if ((req.delta_p_F.norm() > 0 && spd_opt->count() == 0) ||
          (req.delta_rot_F.norm() > 0 && spd_deg_opt->count() == 0)) {
        throw std::invalid_argument("move: give a speed for every part that moves (--speed-mm-s, --speed-deg-s)");
      }
      const double inf = std::numeric_limits<double>::infinity();
      duration_s = transfer::TimedMove::DurationForPeakSpeeds(req, spd_opt->count() > 0 ? MmToM(*speed_mm) : inf,
                                                              spd_deg_opt->count() > 0 ? DegToRad(*speed_deg) : inf);
      if (duration_s == 0) throw std::invalid_argument("move: --delta-mm and --delta-deg are both zero: nothing to move");
    } else if (!(std::isfinite(duration_s) && duration_s > 0)) {
      throw std::invalid_argument("--duration-s: expected a finite duration in (0, " + Num(kMaxMoveDurationS) +
                                  "] s, got " + Num(duration_s));
    }
    if (!(duration_s <= kMaxMoveDurationS)) {
      throw std::invalid_argument("move: the move lasts " + Num(duration_s) + " s; at most " +
                                  Num(kMaxMoveDurationS) + " s");
    }
    const robot::RsrModel model = context.LoadRsr();
    ChainSetup setup = mv_options->Setup(context, model);
    setup.settle_s = 0.2;
    // The one validated path: every pose of the move at the actuation rate by the exact IK, then the caps.
    const transfer::TimedMove probe(setup.X_FM_start, req, duration_s);
    const teleop::PathVerdict verdict = teleop::ValidateMove(probe, setup);
    if (verdict.verdict == teleop::SetPointVerdict::kInfeasible) {
      throw std::invalid_argument("move: the move leaves the RSR's workspace (joint limits) at " +
                                  Num(100.0 * verdict.time_s / duration_s, "%.2f") + " % of its path: arm " +
                                  std::to_string(verdict.tightest.arm + 1) + " " + robot::ToString(verdict.tightest.joint));
    }
    if (!verdict.ok()) {
      const transfer::SpeedCaps& caps = setup.transfer.caps;
      // Rounded up to the millisecond, so that the duration printed is one the check accepts.
      const double shortest_s = std::ceil(teleop::MinimumMoveDuration(req, setup) * 1e3) * 1e-3;
      const std::string given = dur_opt->count() > 0 ? "--duration-s" : "the duration of --speed-mm-s/--speed-deg-s";
      const std::string why =
          verdict.shorter_than_a_tick
              ? given + " " + Num(duration_s) + " s is shorter than one actuation tick (" +
                    Num(1.0 / setup.transfer.rates.actuation_rate_hz) + " s at " +
                    Num(setup.transfer.rates.actuation_rate_hz) + " Hz, transfer.yaml)"
              : "the move breaks the speed caps";
      throw std::invalid_argument(
          "move: " + why + " (caps " + Num(MToMm(caps.max_linear_speed_m_s)) + " mm/s, " +
          Num(RadToDeg(caps.max_angular_speed_rad_s)) + " deg/s): its peak speeds are " +
          Num(MToMm(probe.peak_linear_speed_m_s())) + " mm/s and " +
          Num(RadToDeg(probe.peak_angular_speed_rad_s())) + " deg/s (" + teleop::ToString(verdict.verdict) +
          "); the shortest --duration-s within the caps is " + Num(shortest_s, "%.3f") + " s");
    }
    StagedOutputDir out(mv_options->out, output);
    const TransferTrace trace = RunMoveChain({req}, {duration_s}, setup);
    if (trace.summary.follower_limit_violations > 0 || trace.summary.setpoints_rejected > 0 ||
        trace.summary.limit_ticks > 0) {
      throw std::runtime_error("move: the validated move still met a joint limit (" +
                               std::to_string(trace.summary.limit_ticks) + " ticks); nothing written");
    }
    WriteOutputs(out, trace, *mv_options, false);
    out.Commit();
    if (!mv_options->json) PrintSummaryText(trace.summary, mv_options->out);
  });
}

}  // namespace robossis::apps
