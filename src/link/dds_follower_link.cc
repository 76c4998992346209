#include "src/link/dds_follower_link.h"

#include <cmath>
#include <stdexcept>

#include "robossis_link.h"
#include "src/core/rt/periodic_loop.h"
#include "src/link/setpoint_validation.h"
#include "src/link/wire_convert.h"

namespace robossis::link {

namespace {
std::int64_t Ns(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }
constexpr char kFrameId[] = "rsr_fixed_ring";
constexpr const char* kJointNames[6] = {"theta1", "theta2", "theta3", "d1", "d2", "d3"};
}  // namespace

DdsFollowerLink::DdsFollowerLink(const LinkOptions& options, const rt::Clock& clock)
    : options_(options),
      clock_(clock),
      status_stamp_offset_ns_(SystemNowNs() - Ns(clock.NowS())),
      dds_(options),
      setpoint_reader_(dds_.CreateReader(Topic::kSetPoint)),
      command_reader_(dds_.CreateReader(Topic::kStateCommand)),
      estop_reader_(dds_.CreateReader(Topic::kEStop)),
      cp_writer_(dds_.CreateWriter(Topic::kMeasuredCp)),
      js_writer_(dds_.CreateWriter(Topic::kMeasuredJs)),
      state_writer_(dds_.CreateWriter(Topic::kOperatingState)),
      freshness_(Ns(options.tuning.setpoint_max_age_s), Ns(options.tuning.session_takeover_s),
                 options.tuning.clock_drift_allowance),
      command_filter_(Ns(options.tuning.command_max_age_s), options.tuning.clock_drift_allowance) {
  if (options.role != Role::kFollower) throw std::runtime_error("DdsFollowerLink: the role must be follower");
  Check(dds_set_status_mask(setpoint_reader_, DDS_DATA_AVAILABLE_STATUS | DDS_REQUESTED_DEADLINE_MISSED_STATUS |
                                                  DDS_LIVELINESS_CHANGED_STATUS),
        "set-point reader status mask");
  waitset_ = Check(dds_create_waitset(dds_.participant()), "waitset");
  stop_guard_ = Check(dds_create_guardcondition(dds_.participant()), "guard condition");
  Check(dds_waitset_attach(waitset_, setpoint_reader_, setpoint_reader_), "waitset attach");
  Check(dds_waitset_attach(waitset_, command_reader_, command_reader_), "waitset attach");
  if (estop_reader_ > 0) Check(dds_waitset_attach(waitset_, estop_reader_, estop_reader_), "waitset attach");
  Check(dds_waitset_attach(waitset_, stop_guard_, stop_guard_), "waitset attach");
  receive_thread_ = std::thread([this] { ReceiveLoop(); });
  send_thread_ = std::thread([this] { SendLoop(); });
  // Where permitted (else they stay at normal priority): below the loops, above normal-priority work.
  rt::SetFifoPriority(receive_thread_, rt::kLinkThreadFifoPriority);
  rt::SetFifoPriority(send_thread_, rt::kLinkThreadFifoPriority);
}

DdsFollowerLink::~DdsFollowerLink() {
  stop_.store(true, std::memory_order_release);
  dds_set_guardcondition(stop_guard_, true);
  status_wake_.Notify();
  receive_thread_.join();
  send_thread_.join();
}

bool DdsFollowerLink::TakeSetPoint(teleop::SetPointMessage& message, std::int64_t& arrival_ns) noexcept {
  SetPointArrival a;
  if (!setpoint_.ReadNewer(a, setpoint_version_taken_)) return false;
  message = a.message;
  arrival_ns = a.arrival_ns;
  return true;
}

bool DdsFollowerLink::TakeCommand(teleop::StateCommandMessage& message) noexcept { return commands_.TryPop(message); }

void DdsFollowerLink::PublishStatus(const teleop::FollowerStatusMessage& message) noexcept {
  status_.Publish(message);
  status_wake_.Notify();
}

FollowerLinkStatistics DdsFollowerLink::Statistics() const noexcept {
  FollowerLinkStatistics s;
  s.setpoints_received = counters_.received.load();
  s.setpoints_accepted = counters_.accepted.load();
  s.dropped_stale = counters_.stale.load();
  s.dropped_replayed = counters_.replayed.load();
  s.dropped_session = counters_.session.load();
  s.rejected_invalid = counters_.invalid.load();
  s.commands_received = counters_.commands.load();
  s.commands_dropped = counters_.commands_dropped.load();
  s.commands_replayed = counters_.commands_replayed.load();
  s.commands_stale = counters_.commands_stale.load();
  s.estops_received = estop_.engaged();
  s.status_published = counters_.status.load();
  s.deadline_missed = counters_.deadline.load();
  s.leaders_alive = counters_.alive.load();
  return s;
}

void DdsFollowerLink::ReceiveLoop() {
  dds_attach_t triggered[4];
  while (!stop_.load(std::memory_order_acquire)) {
    const dds_return_t n = dds_waitset_wait(waitset_, triggered, 4, DDS_MSECS(100));
    if (stop_.load(std::memory_order_acquire)) break;
    if (n < 0) continue;
    TakeEStops();  // first: the E-stop waits for nothing
    TakeSetPoints();
    TakeCommands();
    ReadStatuses();
  }
}

void DdsFollowerLink::TakeSetPoints() {
  TakeEach<robossis_msgs_msg_dds__SetPoint_>(setpoint_reader_, [&](const robossis_msgs_msg_dds__SetPoint_& w) {
    const std::int64_t arrival = Ns(clock_.NowS());
    counters_.received.fetch_add(1, std::memory_order_relaxed);
    SetPointArrival a;
    FromWire(w, a.message);
    a.arrival_ns = arrival;
    if (!IsSaneSetPoint(a.message, options_.tuning, nullptr)) {
      counters_.invalid.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    switch (freshness_.Check(a.message, arrival)) {
      case Freshness::kAccepted:
        setpoint_.Publish(a);
        counters_.accepted.fetch_add(1, std::memory_order_relaxed);
        break;
      case Freshness::kStale: counters_.stale.fetch_add(1, std::memory_order_relaxed); break;
      case Freshness::kReplayed: counters_.replayed.fetch_add(1, std::memory_order_relaxed); break;
      case Freshness::kRetiredSession:
      case Freshness::kConcurrentSession: counters_.session.fetch_add(1, std::memory_order_relaxed); break;
    }
  });
}

void DdsFollowerLink::TakeCommands() {
  TakeEach<robossis_msgs_msg_dds__StateCommand_>(command_reader_, [&](const robossis_msgs_msg_dds__StateCommand_& w) {
    const std::int64_t arrival = Ns(clock_.NowS());
    counters_.commands.fetch_add(1, std::memory_order_relaxed);
    teleop::StateCommandMessage m;
    if (!FromWire(w, m)) {
      counters_.commands_dropped.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    if (m.command == teleop::StateCommand::kEStop) {
      estop_.Engage();  // the level, not the queue; an E-stop is never refused as replayed or stale
      return;
    }
    // Only the panel's credentials can publish here (access control); this drops what it sent before again.
    switch (command_filter_.Check(m, arrival)) {
      case CommandFreshness::kAccepted: break;
      case CommandFreshness::kReplayed: counters_.commands_replayed.fetch_add(1, std::memory_order_relaxed); return;
      case CommandFreshness::kStale: counters_.commands_stale.fetch_add(1, std::memory_order_relaxed); return;
    }
    if (!commands_.TryPush(m)) counters_.commands_dropped.fetch_add(1, std::memory_order_relaxed);
  });
}

void DdsFollowerLink::TakeEStops() {
  if (estop_reader_ <= 0) return;
  TakeEach<robossis_msgs_msg_dds__EStop_>(estop_reader_, [&](const robossis_msgs_msg_dds__EStop_& w) {
    if (w.engaged) estop_.Engage();
  });
}

void DdsFollowerLink::ReadStatuses() {
  dds_requested_deadline_missed_status_t deadline;
  if (dds_get_requested_deadline_missed_status(setpoint_reader_, &deadline) == DDS_RETCODE_OK) {
    counters_.deadline.store(deadline.total_count, std::memory_order_relaxed);
  }
  dds_liveliness_changed_status_t liveliness;
  if (dds_get_liveliness_changed_status(setpoint_reader_, &liveliness) == DDS_RETCODE_OK) {
    counters_.alive.store(liveliness.alive_count, std::memory_order_relaxed);
  }
}

void DdsFollowerLink::SendLoop() {
  char frame_id[sizeof kFrameId];
  std::copy(kFrameId, kFrameId + sizeof kFrameId, frame_id);
  char* names[6];
  for (int i = 0; i < 6; ++i) names[i] = const_cast<char*>(kJointNames[i]);
  std::uint64_t version_sent = 0;
  std::int64_t last_state_ns = 0;
  bool have_state = false;
  teleop::OperatingState last_state = teleop::OperatingState::kDisabled;
  teleop::FaultReason last_reason = teleop::FaultReason::kNone;
  while (true) {
    status_wake_.Wait();
    if (stop_.load(std::memory_order_acquire)) break;
    teleop::FollowerStatusMessage m;
    if (!status_.ReadNewer(m, version_sent)) continue;
    // The status's own time on the system clock (not the time of this write, which trails it by the thread's
    // wake-up): a header is the time of its data, and the leader's records join the follower's on it exactly.
    const std::int64_t stamp = m.stamp_ns + status_stamp_offset_ns_;
    geometry_msgs_msg_dds__PoseStamped_ cp{};
    ToMeasuredCp(m, stamp, frame_id, cp);
    dds_write(cp_writer_, &cp);
    sensor_msgs_msg_dds__JointState_ js{};
    js.header = cp.header;
    js.name = {6, 6, names, false};
    js.position = {6, 6, m.joints.data(), false};
    js.velocity = {0, 0, nullptr, false};
    js.effort = {6, 6, m.effort.data(), false};
    dds_write(js_writer_, &js);
    const std::int64_t now = rt::MonotonicNowNs();
    if (!have_state || m.state != last_state || m.fault_reason != last_reason ||
        now - last_state_ns >= Ns(options_.tuning.status_state_period_s)) {
      robossis_msgs_msg_dds__OperatingState_ st{};
      ToOperatingState(m, stamp, frame_id, st);
      dds_write(state_writer_, &st);
      have_state = true;
      last_state = m.state;
      last_reason = m.fault_reason;
      last_state_ns = now;
    }
    counters_.status.fetch_add(1, std::memory_order_relaxed);
  }
}

}  // namespace robossis::link
