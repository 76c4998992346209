#include "src/link/two_process_session.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "src/core/child_process.h"
#include "src/core/files.h"
#include "src/core/json_finite.h"
#include "src/teleop/split_session.h"

namespace robossis::link {

namespace {

std::string LastLine(const std::filesystem::path& log) {
  std::string text;
  try {
    text = ReadTextFile(log);
  } catch (const std::exception&) {
    return "(no output)";
  }
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  const auto nl = text.rfind('\n');
  return nl == std::string::npos ? text : text.substr(nl + 1);
}

std::string Seconds(double s) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3f", s);
  return buffer;
}

std::vector<std::string> UnitArgs(const TwoProcessRequest& r, const char* unit, const std::vector<std::string>& own,
                                  double duration_s, const std::filesystem::path& out) {
  std::vector<std::string> args = r.global_args;
  args.push_back(unit);
  args.insert(args.end(), own.begin(), own.end());
  args.insert(args.end(), r.link_args.begin(), r.link_args.end());
  if (!r.keys_dir.empty()) args.insert(args.end(), {"--keys", (r.keys_dir / unit).string()});
  for (const std::string& a : {std::string("--duration-s"), Seconds(duration_s), std::string("--out"), out.string(),
                               std::string("--no-plots")}) {
    args.push_back(a);
  }
  return args;
}

nlohmann::ordered_json ReadSummary(const std::filesystem::path& file, const char* unit) {
  try {
    const std::string text = ReadTextFile(file);
    return ParseJsonInput<nlohmann::ordered_json>(text.begin(), text.end(), "summary");
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(unit) + " process: " + file.string() + ": " + e.what());
  }
}

}  // namespace

TwoProcessResult RunTwoProcessSession(const TwoProcessRequest& r) {
  std::filesystem::create_directories(r.out_dir);
  const std::filesystem::path follower_log = r.out_dir / "follower.log";
  const std::filesystem::path leader_log = r.out_dir / "leader.log";
  // The follower outlives the leader: it is stopped by a signal, its duration is only a backstop.
  const double follower_backstop_s = std::min(3600.0, r.duration_s + r.follower_start_timeout_s + 60);
  ChildProcess follower(r.program, UnitArgs(r, "follower", r.follower_args, follower_backstop_s, r.out_dir / "follower"),
                        follower_log);
  const auto fail = [](const char* unit, const ChildExit& e, const std::filesystem::path& log) {
    return std::runtime_error(std::string(unit) + " process: " + e.Describe() + ": " + LastLine(log) + " (log: " +
                              log.string() + ")");
  };
  // The leader's --duration-s bounds its whole run: it starts once the follower's loops run (its Bullet robot built),
  // and then waits only for the secured handshake.
  const auto started_by =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(r.follower_start_timeout_s);
  for (;;) {
    if (const std::optional<ChildExit> e = follower.WaitFor(std::chrono::milliseconds(20))) {
      throw fail("follower", *e, follower_log);
    }
    std::string text;
    try {
      text = ReadTextFile(follower_log);
    } catch (const std::exception&) {  // not written yet
    }
    if (text.find(kFollowerRunningLine) != std::string::npos) break;
    if (std::chrono::steady_clock::now() > started_by) {
      throw std::runtime_error("follower process: its loops did not run within " +
                               Seconds(r.follower_start_timeout_s) + " s (log: " + follower_log.string() + ")");
    }
  }
  std::vector<std::string> leader_args = r.leader_args;
  leader_args.push_back("--wait-for-follower-s");
  leader_args.push_back(Seconds(r.follower_start_timeout_s));
  ChildProcess leader(r.program, UnitArgs(r, "leader", leader_args, r.duration_s, r.out_dir / "leader"), leader_log);

  // The leader's run, its start included; a follower that dies first ends the session.
  const auto leader_budget = std::chrono::milliseconds(
      static_cast<long long>(1e3 * (r.duration_s + r.follower_start_timeout_s + 60)));
  const auto until = std::chrono::steady_clock::now() + leader_budget;
  std::optional<ChildExit> leader_exit;
  while (!(leader_exit = leader.WaitFor(std::chrono::milliseconds(50)))) {
    if (!follower.running()) throw fail("follower", follower.Wait(), follower_log);
    if (std::chrono::steady_clock::now() > until) {
      throw std::runtime_error("leader process: still running after " + Seconds(leader_budget.count() / 1e3) +
                               " s (log: " + leader_log.string() + ")");
    }
  }
  if (!leader_exit->exited || leader_exit->code != 0) throw fail("leader", *leader_exit, leader_log);
  follower.Signal(SIGINT);
  const std::optional<ChildExit> follower_exit = follower.WaitFor(std::chrono::seconds(20));
  if (!follower_exit) throw std::runtime_error("follower process: did not stop within 20 s of SIGINT");
  if (!follower_exit->exited || follower_exit->code != 0) throw fail("follower", *follower_exit, follower_log);

  TwoProcessResult result;
  result.leader_summary = ReadSummary(r.out_dir / "leader" / "summary.json", "leader");
  result.follower_summary = ReadSummary(r.out_dir / "follower" / "summary.json", "follower");
  const std::filesystem::path leader_rlog = r.out_dir / "leader" / "session.rlog";
  const std::filesystem::path follower_rlog = r.out_dir / "follower" / "session.rlog";
  result.joined_summary = teleop::ReplaySplitSession(leader_rlog, follower_rlog).summary;
  return result;
}

}  // namespace robossis::link
