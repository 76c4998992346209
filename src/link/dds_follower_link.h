#pragma once
// The follower's end of the link over Cyclone DDS (teleop::FollowerLink).
//
// Threads: the real-time caller only touches lock-free structures (src/core/rt): TakeSetPoint reads a snapshot,
// TakeCommand pops a queue, PublishStatus writes a snapshot and wakes the send thread (an eventfd write). A receive
// thread waits on DDS, takes the samples, runs the freshness filter and the sanity check and publishes what passes;
// a send thread writes measured_cp, measured_js and operating_state. DDS is never called on the caller's thread.
//
// The E-stop: every engaged sample on rt/<ns>/estop, and every "estop" state command, increments an atomic count
// (EStopsEngaged) in the receive thread; nothing queues it, so a full command queue cannot drop it.

#include <atomic>
#include <memory>
#include <thread>

#include "src/core/rt/clock.h"
#include "src/core/rt/snapshot.h"
#include "src/core/rt/spsc_queue.h"
#include "src/link/command_freshness.h"
#include "src/link/dds_entities.h"
#include "src/link/link_statistics.h"
#include "src/link/setpoint_freshness.h"
#include "src/teleop/estop_latch.h"
#include "src/teleop/link.h"

namespace robossis::link {

// A set-point with the follower's clock at its arrival (what the receive thread hands to the caller).
struct SetPointArrival {
  teleop::SetPointMessage message;
  std::int64_t arrival_ns = 0;
};

class DdsFollowerLink final : public teleop::FollowerLink {
 public:
  // Joins the network (options.role must be kFollower); `clock` stamps arrivals and must outlive the link.
  // Throws std::runtime_error on bad options or refused credentials.
  DdsFollowerLink(const LinkOptions& options, const rt::Clock& clock);
  ~DdsFollowerLink() override;

  bool TakeSetPoint(teleop::SetPointMessage& message, std::int64_t& arrival_ns) noexcept override;
  bool TakeCommand(teleop::StateCommandMessage& message) noexcept override;
  void PublishStatus(const teleop::FollowerStatusMessage& message) noexcept override;
  std::uint64_t EStopsEngaged() const noexcept override { return estop_.engaged(); }
  // The system clock (CLOCK_REALTIME) minus `clock`, read once when the link is made: every status goes out
  // stamped with the system time of its own stamp. CLOCK_MONOTONIC and CLOCK_REALTIME are slewed alike, so the
  // offset stays right unless the system clock is stepped during the run (then the headers keep the old offset).
  std::int64_t StatusStampOffsetNs() const noexcept override { return status_stamp_offset_ns_; }

  FollowerLinkStatistics Statistics() const noexcept;

 private:
  void ReceiveLoop();
  void SendLoop();
  void TakeSetPoints();
  void TakeCommands();
  void TakeEStops();
  void ReadStatuses();

  LinkOptions options_;
  const rt::Clock& clock_;
  const std::int64_t status_stamp_offset_ns_;
  DdsParticipant dds_;
  dds_entity_t setpoint_reader_, command_reader_, estop_reader_;
  dds_entity_t cp_writer_, js_writer_, state_writer_;
  dds_entity_t waitset_ = 0, stop_guard_ = 0;
  SetPointFreshness freshness_;
  CommandFilter command_filter_;  // receive thread only

  rt::Snapshot<SetPointArrival> setpoint_;
  std::uint64_t setpoint_version_taken_ = 0;  // caller's thread only
  rt::SpscQueue<teleop::StateCommandMessage> commands_{64};
  teleop::EStopLatch estop_;
  rt::Snapshot<teleop::FollowerStatusMessage> status_;
  WakeSignal status_wake_;

  std::atomic<bool> stop_{false};
  struct Counters {
    std::atomic<std::uint64_t> received{0}, accepted{0}, stale{0}, replayed{0}, session{0}, invalid{0};
    std::atomic<std::uint64_t> commands{0}, commands_dropped{0}, commands_replayed{0}, commands_stale{0};
    std::atomic<std::uint64_t> status{0}, deadline{0};
    std::atomic<std::uint32_t> alive{0};
  } counters_;
  std::thread receive_thread_, send_thread_;
};

}  // namespace robossis::link
