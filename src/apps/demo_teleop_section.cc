// Demo report, section 8: teleoperation on one machine. The project's fast hand trajectory (data/teleop/) drives the
// simulated sigma.7 through the walls (proxy-safe) into the Bullet follower, both units on their own loops in real
// time, every tick in a session log.

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "src/apps/demo_teleop_section.h"
#include "src/core/child_process.h"
#include "src/core/files.h"
#include "src/core/json_finite.h"

namespace robossis::apps {

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
              << "| hand-to-set-point delay (the transfer's filters, where the hand is below the cap) | "
              << (s["hand_to_setpoint_delay_ms"].is_number() ? num("hand_to_setpoint_delay_ms") + " ms"
                                                              : std::string("none"))
              << " (" << s["hand_to_setpoint_delay_status"].get<std::string>() << ", "
              << FormatFixed(100 * s["hand_to_setpoint_delay_judged_fraction"].get<double>(), 0)
              << " % of the set-points judged) |\n"
              << "| watchdog holds | " << s["watchdog_holds"] << " |\n\n";
  demo.report << "Follower state transitions:";
  for (const auto& t : s["follower_transitions"]) {
    demo.report << " " << FormatFixed(t["t_s"].get<double>(), 3) << " s " << t["from"].get<std::string>() << " → "
                << t["to"].get<std::string>() << " (" << t["reason"].get<std::string>() << ");";
  }
  demo.report << " set-points accepted / rejected by the follower: " << s["setpoints_accepted"] << " / "
              << s["setpoints_rejected"] << ".\n\n";
  for (const std::string& w : warnings) demo.report << "Warning: " << w << "\n\n";
  demo.Figure("teleop_session.py", {"--dir", demo.out.Path("teleop").string()}, "teleop/teleop.png",
              "Hand vs follower, the wrench on the hand, the follower's tightest joint-limit margin, the loop periods");
}

}  // namespace robossis::apps
