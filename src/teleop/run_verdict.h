#pragma once
// Whether a teleoperation run was clean: the follower, once it followed, followed until the leader's set-points
// ended, and if not, when it stopped and why. Computed from the follower's records alone (as the rest of the
// summary), so that a replayed session log gives the same verdict; read back from summary.json by whoever shows it
// (the demo's sections, scripts/realtime_runs.py).
//
// Not clean:
//   - a fault or an E-stop, at any time;
//   - the follower stopped following while the leader asked it to follow (the newest set-point had presence and no
//     clutch) and set-points still arrived afterwards, and did not follow again: a watchdog hold (no valid set-point
//     for hold_after_ms) that never ended; or the leader declared lost (the drives disabled), or a disable;
//   - it never followed at all, or the run did not end (no end record).
// Clean: a hold after the leader's last set-point is the end of the leader's run (two processes: the follower outlives
// the leader), and a hold the leader asked for (presence off, the clutch, the end of a replay) is the operator's.
// A watchdog hold that following resumes from is the designed answer to a late set-point (the robot stands still,
// then follows again within its caps): counted with its length, not a fault.

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "src/teleop/follower_unit.h"

namespace robossis::teleop {

struct RunVerdict {
  bool judged = false;  // follower records were seen (a leader-only process has nothing to judge)
  bool clean = false;
  std::uint64_t faults = 0;  // the episodes that were not clean
  std::uint64_t holds = 0;   // watchdog holds that following resumed from
  double hold_s = 0;         // their total length
  // The first of them: when it began (the follower's clock), a short reason (fault, estop, leader_lost, disabled,
  // watchdog_hold, never_followed, incomplete) and one line for a report.
  double t_s = 0;
  std::string reason;
  std::string description;
};

class RunVerdictCheck {
 public:
  void AddFollower(const FollowerTickRecord& r);
  RunVerdict Verdict(bool complete) const;

 private:
  void Fault(double t_s, std::string reason, std::string description);
  void CloseEpisode(double end_s, bool resumed);

  RunVerdict first_;
  std::uint64_t faults_ = 0;
  std::uint64_t holds_ = 0;
  double hold_s_ = 0;
  bool seen_ = false;
  bool followed_ = false;         // the follower was enabled at some tick
  OperatingState state_ = OperatingState::kDisabled;
  double last_t_s_ = 0;
  // An episode: the follower stopped following while the leader asked it to follow. A fault once a set-point
  // arrives after its start (the leader was still sending), whether following resumes or not.
  bool open_ = false;
  bool confirmed_ = false;
  double start_s_ = 0;
  std::string reason_;
  std::string what_;
};

// The verdict's keys of summary.json: run_clean (null when not judged), run_faults, run_fault (null when clean:
// t_s, reason, description), run_holds, run_hold_s.
void WriteRunVerdict(const RunVerdict& v, nlohmann::ordered_json& summary);
// The verdict back from a summary.json (throws std::invalid_argument naming the key if it is missing).
RunVerdict ReadRunVerdict(const nlohmann::ordered_json& summary);

}  // namespace robossis::teleop
