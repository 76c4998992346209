#pragma once
// `robossis teleop --link dds` and the demo's link section: the leader unit and the follower unit as two processes
// of this program (`robossis follower`, then `robossis leader`) on one machine, talking over the DDS link exactly as
// they would between two machines. The follower starts first; the leader is started once the follower says its
// loops run (kFollowerRunningLine in its log), so that the leader's --duration-s, which bounds its whole run, its
// wait for the follower included, is spent in its loop. The follower runs until the leader has finished; then it
// is asked to stop (SIGINT) and disables its drives. Each process writes its half of the outputs into its own folder.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace robossis::link {

// What `robossis follower` prints (stderr) once its loops run.
inline constexpr const char* kFollowerRunningLine = "follower: running";

struct TwoProcessRequest {
  std::filesystem::path program;          // this program (SelfExecutable())
  std::vector<std::string> global_args;   // options before the subcommand (--data-dir DIR)
  std::vector<std::string> link_args;     // both units: --insecure (or keys_dir), --domain N, --interface, --peer
  std::filesystem::path keys_dir;         // made by `keys init`: each unit gets its own folder (--keys DIR/<unit>)
  std::vector<std::string> leader_args;   // `robossis leader` only: --device, --method, --rate-hz, caps
  std::vector<std::string> follower_args; // `robossis follower` only: --follower, caps
  double duration_s = 10;                 // the leader's run time
  double follower_start_timeout_s = 60;   // the follower's loops run within this, the leader is heard within it [assumed]:
                                          // Bullet's start and a secured DDS handshake take seconds on a slow machine
  std::filesystem::path out_dir;          // leader/, follower/, leader.log, follower.log are written here
};

struct TwoProcessResult {
  nlohmann::ordered_json leader_summary;    // leader/summary.json
  nlohmann::ordered_json follower_summary;  // follower/summary.json
  // Both logs' records in one summary (teleop::ReplaySplitSession): the figures that need both units, such as the
  // load shown at the hand against the follower's true load (feedback_force_error_n_rms).
  nlohmann::ordered_json joined_summary;
};

// Runs the two processes to the end. Throws std::runtime_error naming the unit, how it ended and the last line it
// printed when either fails (the other is stopped; no process outlives the call).
TwoProcessResult RunTwoProcessSession(const TwoProcessRequest& request);

}  // namespace robossis::link
