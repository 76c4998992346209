// Demo report, section 8: teleoperation on one machine. The project's fast hand trajectory (data/teleop/) drives the
// simulated sigma.7 through the walls (proxy-safe) into the Bullet follower, both units on their own loops in real
// time, every tick in a session log.

#include <stdexcept>
#include <string>

#include "src/apps/demo_teleop_section.h"
#include "src/core/units.h"
#include "src/teleop/teleop_session.h"

namespace robossis::apps {

std::string OverrunsByCause(const nlohmann::ordered_json& summary, const std::string& loop) {
  const auto count = [&](const std::string& key) { return std::to_string(summary[loop + key].get<std::uint64_t>()); };
  return count("_overruns") + " of " + count("_ticks") + " ticks (late wake-up " + count("_overruns_late_wake") +
         ", long tick " + count("_overruns_long_tick") + ")";
}

void WriteTeleopSection(DemoContext& demo) {
  demo.Progress("teleop: fast hand -> leader (proxy-safe walls) -> Bullet follower, real time");
  const robot::RsrModel rsr = demo.app.LoadRsr();
  const robot::Sigma7Model sigma7 = demo.app.LoadSigma7();
  teleop::TeleopSetup setup = teleop::TeleopSetup::Load(demo.app.data_dir, rsr, sigma7);
  // Caps raised to 100 mm/s and 20 deg/s (10x and 20x the paper's demonstration caps) so that within the recording
  // the set-point reaches the walls; the hand itself moves at up to 250 mm/s and 60 deg/s.
  setup.transfer.caps.max_linear_speed_m_s = MmToM(100);
  setup.transfer.caps.max_angular_speed_rad_s = DegToRad(20);
  setup.follower.setpoint.caps = setup.transfer.caps;
  teleop::TeleopRequest request;
  request.device = "replay:" + (demo.app.data_dir / "teleop" / "fast_hand.csv").string();
  request.method = "proxy-safe";
  request.follower = "sim";
  request.real_clock = true;
  request.duration_s = demo.fast ? 3.0 : 17.0;
  const teleop::TeleopOutputs o = teleop::RunTeleop(request, setup, demo.out.Path("teleop/session.rlog"));
  demo.out.Write("teleop/summary.json", o.summary.dump(2) + "\n");
  demo.out.Write("teleop/leader.csv", o.leader_csv);
  demo.out.Write("teleop/follower.csv", o.follower_csv);
  demo.out.Write("teleop/loop_periods.csv", o.periods_csv);
  if (!o.recorder_error.empty()) throw std::runtime_error("demo teleop: " + o.recorder_error);
  const auto& s = o.summary;
  auto num = [&](const char* key, const char* format = "%.3g") { return FormatNumber(s[key].get<double>(), format); };
  demo.report << "## 8. Teleoperation: the leader and follower units in real time (src/teleop)\n\n"
              << "`robossis teleop --device replay:data/teleop/fast_hand.csv --method proxy-safe --follower sim "
                 "--clock real --max-speed-mm-s 100 --max-angular-speed-deg-s 20` for "
              << FormatFixed(request.duration_s, 0)
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
  for (const std::string& w : o.warnings) demo.report << "Warning: " << w << "\n\n";
  demo.Figure("teleop_session.py", {"--dir", demo.out.Path("teleop").string()}, "teleop/teleop.png",
              "Hand vs follower, the wrench on the hand, the follower's tightest joint-limit margin, the loop periods");
}

}  // namespace robossis::apps
