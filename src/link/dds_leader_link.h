#pragma once
// The leader's end of the link over Cyclone DDS (teleop::LeaderLink).
//
// Threads: the real-time caller only touches lock-free structures (src/core/rt): SendSetPoint writes a snapshot and
// wakes the send thread (an eventfd write), SendCommand pushes a queue, SendEStop increments an atomic count,
// TakeFollowerStatus reads a snapshot. The send thread writes the newest set-point, the queued commands, then the
// E-stop if its count grew; a receive thread takes measured_cp, measured_js and operating_state and assembles the
// follower's status. DDS is never called on the caller's thread.
//
// The E-stop (SendEStop, or a kEStop command, from any thread) goes on its own topic (rt/<ns>/estop), never through
// the command queue: every role's credentials grant it.

#include <atomic>
#include <thread>

#include "src/core/rt/snapshot.h"
#include "src/core/rt/spsc_queue.h"
#include "src/link/dds_entities.h"
#include "src/link/link_statistics.h"
#include "src/teleop/estop_latch.h"
#include "src/teleop/link.h"

namespace robossis::link {

class DdsLeaderLink final : public teleop::LeaderLink {
 public:
  // Joins the network (options.role must be kLeader or kPanel: a panel sends commands and watches).
  // Throws std::runtime_error on bad options or refused credentials.
  explicit DdsLeaderLink(const LinkOptions& options);
  ~DdsLeaderLink() override;

  // One producer thread only (the leader's loop): the newest set-point is handed over through a seqlock.
  void SendSetPoint(const teleop::SetPointMessage& message) noexcept override;
  bool TakeFollowerStatus(teleop::FollowerStatusMessage& message) noexcept override;
  // The panel only (one producer thread: the commands go through a single-producer queue). The leader's
  // credentials do not grant state_command, so a leader link has no command writer: false, counted as refused.
  // A kEStop command engages the E-stop (as SendEStop) and is never refused.
  bool SendCommand(const teleop::StateCommandMessage& message) noexcept override;
  // Any thread, any number of them.
  void SendEStop() noexcept override;

  LeaderLinkStatistics Statistics() const noexcept;
  // Not real-time: waits until a follower is matched (which, secured, means authenticated and allowed by access
  // control), then until its operating state has arrived (so that the first set-points are not sent into the void),
  // both within the one bound `wait_s` from the call. Throws std::runtime_error with one line naming the cause: no
  // peer at all, a handshake Cyclone refused (its reason), or a follower that stays silent.
  void WaitForFollower(double wait_s) const;

 private:
  void ReceiveLoop();
  void SendLoop();
  std::uint32_t FollowersMatched() const noexcept;  // the follower's operating_state writers matched now
  void WriteEStop(std::uint64_t count);

  LinkOptions options_;
  DdsParticipant dds_;
  dds_entity_t setpoint_writer_ = 0, command_writer_ = 0, estop_writer_ = 0;
  dds_entity_t cp_reader_ = 0, js_reader_ = 0, state_reader_ = 0;
  dds_entity_t waitset_ = 0, stop_guard_ = 0;

  rt::Snapshot<teleop::SetPointMessage> setpoint_;
  rt::SpscQueue<teleop::StateCommandMessage> commands_{64};
  teleop::EStopLatch estop_;
  std::uint64_t session_ = 0;  // this sender's random id on the E-stop topic
  WakeSignal send_wake_;
  rt::Snapshot<teleop::FollowerStatusMessage> status_;
  std::uint64_t status_version_taken_ = 0;  // caller's thread only

  std::atomic<bool> stop_{false};
  struct Counters {
    std::atomic<std::uint64_t> setpoints{0}, commands{0}, refused{0}, status{0}, state{0}, estops{0};
    std::atomic<std::uint32_t> matched{0};
  } counters_;
  std::thread receive_thread_, send_thread_;
};

}  // namespace robossis::link
