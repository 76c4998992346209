// Demo report, section 8: teleoperation on one machine. The project's fast hand trajectory (data/teleop/) drives the
// simulated sigma.7 through the walls (proxy-safe) into the Bullet follower, both units on their own loops in real
// time, every tick in a session log; then a recorded human hand's delay through the motion transfer, and the
// follower's load at the hand (bilateral feedback), with and without delay, beside the walls alone.

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "src/apps/demo_teleop_section.h"
#include "src/core/child_process.h"
#include "src/core/files.h"
#include "src/core/json_finite.h"
#include "src/core/units.h"
#include "src/teleop/run_verdict.h"
#include "src/teleop/teleop_session.h"

namespace robossis::apps {

namespace {

// A summary's hand-to-set-point delay as the report prints it: the figure (or none) and, in parentheses, its status
// and the share of the set-points judged.
std::string DelayText(const nlohmann::ordered_json& s) {
  const std::string figure = s["hand_to_setpoint_delay_ms"].is_number()
                                 ? FormatNumber(s["hand_to_setpoint_delay_ms"].get<double>(), "%.3g") + " ms"
                                 : std::string("none");
  return figure + " (" + s["hand_to_setpoint_delay_status"].get<std::string>() + ", " +
         FormatFixed(100 * s["hand_to_setpoint_delay_judged_fraction"].get<double>(), 0) +
         " % of the set-points judged";
}

// The load felt at the hand: the simulated sigma.7's loop hand into the Bullet follower with the paper's muscle
// traction (517 N, 74 N·m), simulated clock, 3 s per run (about a second of wall time each): the walls alone, the
// load at no delay, the load behind a 100 ms one-way delay.
void WriteBilateralPart(DemoContext& demo) {
  demo.Progress("teleop: the follower's load at the hand (bilateral feedback, 0 and 100 ms delay)");
  const robot::RsrModel rsr = demo.app.LoadRsr();
  const robot::Sigma7Model sigma7 = demo.app.LoadSigma7();
  teleop::TeleopSetup setup = teleop::TeleopSetup::Load(demo.app.data_dir, rsr, sigma7);
  setup.transfer.caps.max_linear_speed_m_s = MmToM(100);  // the caps of the command the report quotes
  setup.transfer.caps.max_angular_speed_rad_s = DegToRad(20);
  setup.follower.setpoint.caps = setup.transfer.caps;
  struct Run {
    const char* name;
    const char* feedback;
    double delay_ms;
  };
  demo.report << "### The follower's load at the hand (bilateral feedback)\n\n"
              << "`robossis teleop --device sim --follower sim --clock simulated --duration-s 3 --max-speed-mm-s 100 "
                 "--max-angular-speed-deg-s 20 --sim-load-n 517 --sim-load-nm 74 --feedback F --link-delay-ms D`: the "
                 "simulated hand's loop into the Bullet follower pulled by the paper's muscle traction; the load "
                 "shown at gain 0.025 through the classic passivity controller (README, \"Bilateral feedback\").\n\n"
              << "| run | max load force on the hand (N) | max force on the hand (N) | port energy, end / max (J) | "
                 "load error rms (N) | controller active | drift (mm) |\n|---|---|---|---|---|---|---|\n";
  for (const Run& run : {Run{"walls alone", "walls", 0}, Run{"bilateral, no delay", "bilateral", 0},
                         Run{"bilateral, 100 ms each way", "bilateral", 100}}) {
    teleop::TeleopRequest request;
    request.device = "sim";
    request.method = "proxy-safe";
    request.follower = "sim";
    request.duration_s = 3;
    request.feedback = run.feedback;
    request.link_delay_s = 1e-3 * run.delay_ms;
    request.sim_load_n = 517;
    request.sim_load_nm = 74;
    const std::string name = std::string("teleop/bilateral_") + run.feedback + "_" +
                             std::to_string(static_cast<int>(run.delay_ms)) + "ms";
    const teleop::TeleopOutputs o = teleop::RunTeleop(request, setup, demo.out.Path(name + ".rlog"));
    demo.out.Write(name + ".json", o.summary.dump(2) + "\n");
    const auto& s = o.summary;
    // A figure the run has no value for (null: the load error of the walls-alone run, which shows no load) is "—".
    auto num = [&](const char* key) {
      return s[key].is_number() ? FormatNumber(s[key].get<double>(), "%.3g") : std::string("—");
    };
    demo.report << "| " << run.name << " | " << num("max_feedback_force_n") << " | " << num("max_force_n") << " | "
                << num("feedback_energy_j") << " / " << num("feedback_energy_max_j") << " | "
                << num("feedback_force_error_n_rms") << " | "
                << FormatFixed(100 * s["tdpa_active_fraction"].get<double>(), 1) << " % | "
                << (s["position_drift_mm"].is_number() ? num("position_drift_mm") : std::string("n/a")) << " |\n";
  }
  demo.report << "\n";
}

// The delay on a real hand: a recorded person's hand (data/teleop/recorded_hand.csv, scaled 1:50) at the shipped
// caps, which it stays below, into the pulse recorder on the simulated clock (the transfer's delay does not depend on
// the follower), so that nothing but the motion transfer's filters stands between the hand and the set-point.
void WriteRecordedHandPart(DemoContext& demo) {
  demo.Progress("teleop: a recorded human hand at the shipped caps (the hand-to-set-point delay)");
  const robot::RsrModel rsr = demo.app.LoadRsr();  // the setup refers to both: they outlive the run
  const robot::Sigma7Model sigma7 = demo.app.LoadSigma7();
  const teleop::TeleopSetup setup = teleop::TeleopSetup::Load(demo.app.data_dir, rsr, sigma7);
  teleop::TeleopRequest request;
  request.device = "replay:" + (demo.app.data_dir / "teleop" / "recorded_hand.csv").string();
  request.method = "proxy-safe";
  request.follower = "recorder";
  request.duration_s = demo.fast ? 10 : 60;
  const teleop::TeleopOutputs o = teleop::RunTeleop(request, setup, demo.out.Path("teleop/recorded_hand.rlog"));
  demo.out.Write("teleop/recorded_hand.json", o.summary.dump(2) + "\n");
  const auto& s = o.summary;
  const auto mm_s = [&](const char* key) { return FormatNumber(s[key].get<double>(), "%.3g") + " mm/s"; };
  demo.report << "### The delay on a recorded human hand\n\n"
              << "`robossis teleop --device replay:data/teleop/recorded_hand.csv --method proxy-safe --follower "
                 "recorder --clock simulated --duration-s "
              << FormatFixed(request.duration_s, 0)
              << "`: a person's hand from a motion-capture take, scaled 1:50 (data/teleop/README.md), at the shipped "
                 "caps (10 mm/s, 1°/s), which its motion stays below. Hand-to-set-point delay: "
              << DelayText(s) << "; the goal is 25 ms). The hand at up to " << mm_s("max_hand_speed_mm_s")
              << ", the follower at up to " << mm_s("max_follower_speed_mm_s")
              << "; set-points stopped at the boundary: " << s["setpoints_stopped_at_boundary"] << ".\n\n";
}

}  // namespace

void ReportRunVerdict(DemoContext& demo, const nlohmann::ordered_json& follower_summary, const std::string& section) {
  const teleop::RunVerdict v = teleop::ReadRunVerdict(follower_summary);
  if (v.clean) {
    demo.report << "The follower followed to the end of the leader's run: no fault";
    if (v.holds == 0) {
      demo.report << ", no hold while the leader sent.\n\n";
    } else {
      demo.report << "; the watchdog held the robot " << v.holds << " time(s) for a late set-point ("
                  << FormatFixed(1e3 * v.hold_s, 1) << " ms in all) and following resumed each time.\n\n";
    }
    return;
  }
  const std::string what = v.judged ? v.description : std::string("the follower's run was not judged (no records)");
  demo.report << "**FAULT**: " << what << ".\n\n";
  demo.faults.push_back(section + ": " + what);
}

std::string OverrunsByCause(const nlohmann::ordered_json& summary, const std::string& loop) {
  const auto count = [&](const std::string& key) { return std::to_string(summary[loop + key].get<std::uint64_t>()); };
  return count("_overruns") + " of " + count("_ticks") + " ticks (late wake-up " + count("_overruns_late_wake") +
         ", long tick " + count("_overruns_long_tick") + ")";
}

void WriteTeleopSection(DemoContext& demo) {
  demo.Progress("teleop: fast hand -> leader (proxy-safe walls) -> Bullet follower, real time");
  // The command the report quotes, as its own process: a real-time run locks its memory (mlockall), and locked in
  // this process that would be every page the earlier sections left mapped (about 930 MB, the demo's peak), not the
  // session's own.
  // Caps raised to 100 mm/s and 20 deg/s (10x and 20x the paper's demonstration caps) so that within the recording
  // the set-point reaches the walls; the hand itself moves at up to 250 mm/s and 60 deg/s.
  const double duration_s = demo.fast ? 3.0 : 17.0;
  const std::filesystem::path dir = demo.out.Path("teleop");
  const std::filesystem::path log = demo.out.Path("teleop.log");
  ChildProcess teleop(SelfExecutable(),
                      {"--data-dir", demo.app.data_dir.string(), "teleop", "--device",
                       "replay:" + (demo.app.data_dir / "teleop" / "fast_hand.csv").string(), "--method", "proxy-safe",
                       "--follower", "sim", "--clock", "real", "--max-speed-mm-s", "100", "--max-angular-speed-deg-s",
                       "20", "--duration-s", FormatFixed(duration_s, 0), "--no-plots", "--out", dir.string()},
                      log);
  const ChildExit exit = teleop.Wait();
  const std::string output = ReadTextFile(log);
  std::filesystem::remove(log);
  if (!exit.exited || exit.code != 0) {
    std::string last = output;
    while (!last.empty() && last.back() == '\n') last.pop_back();
    throw std::runtime_error("demo teleop: robossis teleop: " + exit.Describe() + ": " +
                             last.substr(last.rfind('\n') + 1));
  }
  const std::string text = ReadTextFile(dir / "summary.json");
  const nlohmann::ordered_json summary = ParseJsonInput<nlohmann::ordered_json>(text.begin(), text.end(), "summary");
  std::vector<std::string> warnings;
  const std::string warning = "robossis: warning: ";
  for (std::size_t at = output.find(warning); at != std::string::npos; at = output.find(warning, at + 1)) {
    const std::size_t from = at + warning.size();
    warnings.push_back(output.substr(from, output.find('\n', from) - from));
  }
  const auto& s = summary;
  auto num = [&](const char* key, const char* format = "%.3g") { return FormatNumber(s[key].get<double>(), format); };
  demo.report << "## 8. Teleoperation: the leader and follower units in real time (src/teleop)\n\n"
              << "`robossis teleop --device replay:data/teleop/fast_hand.csv --method proxy-safe --follower sim "
                 "--clock real --max-speed-mm-s 100 --max-angular-speed-deg-s 20` for "
              << FormatFixed(duration_s, 0)
              << " s: the synthetic fast hand (250 mm/s, ±60°, far outside the workspace) through the walls into the "
                 "Bullet follower. Caps raised to 100 mm/s and 20°/s so that the set-point reaches the walls within "
                 "the recording. Measured on a shared, loaded machine. An overrun is a missed deadline, counted "
                 "under its cause: a late wake-up (the loop's thread was not run at its deadline: scheduling) or a "
                 "long tick (the tick's own work, with any preemption inside it, passed its period).\n\n"
              << "| quantity | value |\n|---|---|\n"
              << "| leader / follower ticks | " << s["leader_ticks"] << " / " << s["follower_ticks"] << " |\n"
              << "| overruns of the leader's loop | " << OverrunsByCause(s, "leader") << " |\n"
              << "| overruns of the follower's loop | " << OverrunsByCause(s, "follower") << " |\n"
              << "| overruns of the simulated robot's own loop | " << OverrunsByCause(s, "plant") << " |\n"
              << "| period jitter p99 leader / follower (µs) | " << num("leader_period_jitter_us_p99") << " / "
              << num("follower_period_jitter_us_p99") << " |\n"
              << "| follower limit violations (measured joints, cones included) | " << s["follower_limit_violations"]
              << " |\n"
              << "| set-points stopped at the boundary | " << s["setpoints_stopped_at_boundary"] << " |\n"
              << "| max force / torque on the hand | " << num("max_force_n") << " N / " << num("max_torque_nm")
              << " N·m |\n"
              << "| max follower speed | " << num("max_follower_speed_mm_s") << " mm/s, "
              << num("max_follower_angular_speed_deg_s") << " °/s |\n"
              << "| hand-to-set-point delay (the transfer's filters, where the set-point follows a hand below the "
                 "caps) | "
              << DelayText(s) << ") |\n"
              << "| watchdog holds | " << s["watchdog_holds"] << " |\n\n";
  demo.report << "Follower state transitions:";
  for (const auto& t : s["follower_transitions"]) {
    demo.report << " " << FormatFixed(t["t_s"].get<double>(), 3) << " s " << t["from"].get<std::string>() << " → "
                << t["to"].get<std::string>() << " (" << t["reason"].get<std::string>() << ");";
  }
  demo.report << " set-points accepted / rejected by the follower: " << s["setpoints_accepted"] << " / "
              << s["setpoints_rejected"] << ".\n\n";
  ReportRunVerdict(demo, s, "section 8 (teleop)");
  for (const std::string& w : warnings) demo.report << "Warning: " << w << "\n\n";
  demo.Figure("teleop_session.py", {"--dir", demo.out.Path("teleop").string()}, "teleop/teleop.png",
              "Hand vs follower, the wrench on the hand, the follower's tightest joint-limit margin, the loop periods");
  WriteRecordedHandPart(demo);
  WriteBilateralPart(demo);
}

}  // namespace robossis::apps
