// Demo report, section 9: the same teleoperation as two processes over the DDS link. `robossis follower` and
// `robossis leader` run on this machine over loopback with DDS Security on (credentials made for the run by
// `robossis keys init`), exactly as they would run on two machines.

#include <unistd.h>

#include <filesystem>
#include <string>

#include "src/apps/demo.h"
#include "src/apps/demo_teleop_section.h"
#include "src/core/child_process.h"
#include "src/core/units.h"
#include "src/link/keys.h"
#include "src/link/two_process_session.h"

namespace robossis::apps {

void WriteLinkSection(DemoContext& demo) {
  demo.Progress("link: robossis follower + robossis leader as two processes over secured DDS (loopback)");
  // Credentials for this run only, outside the report (private keys do not belong in a report folder).
  const std::filesystem::path keys =
      std::filesystem::temp_directory_path() / ("robossis-demo-keys-" + std::to_string(::getpid()));
  std::filesystem::remove_all(keys);
  link::InitKeys(keys, {});
  struct RemoveKeys {
    std::filesystem::path dir;
    ~RemoveKeys() {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  } remove_keys{keys};

  const double duration_s = demo.fast ? 3.0 : 17.0;
  link::TwoProcessRequest r;
  r.program = SelfExecutable();
  r.global_args = {"--data-dir", demo.app.data_dir.string()};
  // A domain outside the tests' (1..200) and the default (42), so the demo never meets another session on this host.
  const int domain = 201 + ::getpid() % 29;
  r.link_args = {"--domain", std::to_string(domain)};
  r.keys_dir = keys;  // each process gets its own folder of it
  // As section 8: the fast hand, proxy-safe walls, the Bullet follower, caps raised to 100 mm/s and 20 deg/s.
  const std::vector<std::string> caps = {"--max-speed-mm-s", "100", "--max-angular-speed-deg-s", "20"};
  r.leader_args = {"--device", "replay:" + (demo.app.data_dir / "teleop" / "fast_hand.csv").string(), "--method",
                   "proxy-safe"};
  r.leader_args.insert(r.leader_args.end(), caps.begin(), caps.end());
  r.follower_args = {"--follower", "sim"};
  r.follower_args.insert(r.follower_args.end(), caps.begin(), caps.end());
  r.duration_s = duration_s;
  r.out_dir = demo.out.Path("link");
  const link::TwoProcessResult result = link::RunTwoProcessSession(r);
  demo.out.Write("link/summary.json", nlohmann::ordered_json{{"leader", result.leader_summary},
                                                             {"follower", result.follower_summary}}
                                              .dump(2) + "\n");

  const auto& l = result.leader_summary;
  const auto& f = result.follower_summary;
  const auto& ll = l["link"];
  const auto& fl = f["link"];
  auto num = [](const nlohmann::ordered_json& j, const char* key) { return FormatNumber(j[key].get<double>(), "%.3g"); };
  demo.report << "## 9. The link: leader and follower as two processes over secured DDS (src/link)\n\n"
              << "`robossis teleop --link dds --keys DIR` with section 8's run: `robossis follower --follower sim` "
                 "and `robossis leader --device replay:data/teleop/fast_hand.csv --method proxy-safe` as two "
                 "processes on loopback, DDS Security on (authenticated, encrypted, each participant limited to its "
                 "own topics by signed permissions), "
              << FormatFixed(duration_s, 0) << " s. The set-point latency against `ddsperf` is in BENCHMARKS.md.\n\n"
              << "| quantity | value |\n|---|---|\n"
              << "| set-points sent by the leader | " << ll["setpoints_sent"] << " |\n"
              << "| received / accepted by the follower's link | " << fl["setpoints_received"] << " / "
              << fl["setpoints_accepted"] << " |\n"
              << "| dropped as stale / replayed / other session / invalid | " << fl["dropped_stale"] << " / "
              << fl["dropped_replayed"] << " / " << fl["dropped_session"] << " / " << fl["rejected_invalid"] << " |\n"
              << "| accepted / rejected by the follower unit | " << f["setpoints_accepted"] << " / "
              << f["setpoints_rejected"] << " |\n"
              << "| DDS deadline misses (10 ms) | " << fl["deadline_missed"] << " |\n"
              << "| follower limit violations | " << f["follower_limit_violations"] << " |\n"
              << "| watchdog holds | " << f["watchdog_holds"] << " |\n"
              << "| max follower speed | " << num(f, "max_follower_speed_mm_s") << " mm/s, "
              << num(f, "max_follower_angular_speed_deg_s") << " °/s |\n"
              << "| max force on the hand | " << num(l, "max_force_n") << " N |\n"
              << "| overruns of the leader's / follower's / simulated robot's loop | " << OverrunsByCause(l, "leader")
              << " / " << OverrunsByCause(f, "follower") << " / " << OverrunsByCause(f, "plant") << " |\n"
              << "| period jitter p99 leader / follower (µs) | " << num(l, "leader_period_jitter_us_p99") << " / "
              << num(f, "follower_period_jitter_us_p99") << " |\n\n";
  demo.report << "Follower state transitions:";
  for (const auto& t : f["follower_transitions"]) {
    demo.report << " " << FormatFixed(t["t_s"].get<double>(), 3) << " s " << t["from"].get<std::string>() << " → "
                << t["to"].get<std::string>() << " (" << t["reason"].get<std::string>() << ");";
  }
  demo.report << " (a hold after the leader's last set-point is the end of the leader's run: the follower holds, "
                 "as it would for a lost leader).\n\n";
  ReportRunVerdict(demo, f, "section 9 (link)");
}

}  // namespace robossis::apps
