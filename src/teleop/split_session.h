#pragma once
// One summary of a session that ran as two processes (`robossis leader`, `robossis follower`; `robossis teleop
// --link dds` runs both), from the two session logs each wrote: the figures that need both units' records, the
// load shown at the hand (the leader's records) against the follower's true load (the follower's records), come out
// as they do from the one-process records of the same run.
//
// The time base of the join is the follower's clock, as in one process: a leader record holds the stamp of the
// follower status it showed, as that status came over the link, which is the follower's clock plus what the
// follower's link added to it (FollowerLink::StatusStampOffsetNs: over DDS, the system clock's offset from the
// follower's clock). The follower's log keeps that offset in its header (`status_stamp_offset_ns`); taken off the
// leader's stamps, they are the follower records' own times again, to the nanosecond. A follower log without it
// (written before the offset was recorded) leaves the shown load against the true one not judged (null).

#include <filesystem>

#include "src/teleop/teleop_session.h"

namespace robossis::teleop {

// The outputs (summary, leader.csv, follower.csv, loop periods) of the session whose leader wrote `leader_log` and
// whose follower wrote `follower_log`, from both logs' records; "units" is "both". The end record is the two
// processes' together (each loop's figures from its own process); "complete" only when both logs have theirs.
// Throws std::runtime_error naming the file and the problem (unreadable, or not a leader's and a follower's log).
TeleopOutputs ReplaySplitSession(const std::filesystem::path& leader_log, const std::filesystem::path& follower_log);

}  // namespace robossis::teleop
