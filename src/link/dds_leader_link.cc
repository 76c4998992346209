#include "src/link/dds_leader_link.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <thread>

#include "robossis_link.h"
#include "src/core/rt/periodic_loop.h"
#include "src/core/rt/clock.h"
#include "src/link/wire_convert.h"

namespace robossis::link {

DdsLeaderLink::DdsLeaderLink(const LinkOptions& options) : options_(options), dds_(options) {
  if (options.role != Role::kLeader && options.role != Role::kPanel) {
    throw std::runtime_error("DdsLeaderLink: the role must be leader or panel");
  }
  // Each role gets the writers its permissions grant (keys.cc, TopicsOf), and could create no other: the leader
  // sends set-points only, the panel state commands only (enable, reset, home: never the leader's to give).
  if (options.role == Role::kLeader) setpoint_writer_ = dds_.CreateWriter(Topic::kSetPoint);
  if (options.role == Role::kPanel) command_writer_ = dds_.CreateWriter(Topic::kStateCommand);
  estop_writer_ = dds_.CreateWriter(Topic::kEStop);
  session_ = (static_cast<std::uint64_t>(std::random_device{}()) << 32) ^ std::random_device{}();
  cp_reader_ = dds_.CreateReader(Topic::kMeasuredCp);
  js_reader_ = dds_.CreateReader(Topic::kMeasuredJs);
  state_reader_ = dds_.CreateReader(Topic::kOperatingState);
  waitset_ = Check(dds_create_waitset(dds_.participant()), "waitset");
  stop_guard_ = Check(dds_create_guardcondition(dds_.participant()), "guard condition");
  for (dds_entity_t e : {cp_reader_, js_reader_, state_reader_, stop_guard_}) {
    Check(dds_waitset_attach(waitset_, e, e), "waitset attach");
  }
  receive_thread_ = std::thread([this] { ReceiveLoop(); });
  send_thread_ = std::thread([this] { SendLoop(); });
  // Where permitted (else they stay at normal priority): below the loops, above normal-priority work.
  rt::SetFifoPriority(receive_thread_, rt::kLinkThreadFifoPriority);
  rt::SetFifoPriority(send_thread_, rt::kLinkThreadFifoPriority);
}

DdsLeaderLink::~DdsLeaderLink() {
  stop_.store(true, std::memory_order_release);
  dds_set_guardcondition(stop_guard_, true);
  send_wake_.Notify();
  receive_thread_.join();
  send_thread_.join();
}

void DdsLeaderLink::SendSetPoint(const teleop::SetPointMessage& message) noexcept {
  setpoint_.Publish(message);
  send_wake_.Notify();
}

void DdsLeaderLink::SendEStop() noexcept {
  estop_.Engage();
  send_wake_.Notify();
}

bool DdsLeaderLink::SendCommand(const teleop::StateCommandMessage& message) noexcept {
  if (message.command == teleop::StateCommand::kEStop) {
    SendEStop();
    return true;
  }
  if (command_writer_ == 0 || !commands_.TryPush(message)) {
    counters_.refused.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  send_wake_.Notify();
  return true;
}

bool DdsLeaderLink::TakeFollowerStatus(teleop::FollowerStatusMessage& message) noexcept {
  return status_.ReadNewer(message, status_version_taken_);
}

std::uint32_t DdsLeaderLink::FollowersMatched() const noexcept {
  dds_subscription_matched_status_t matched;
  return dds_get_subscription_matched_status(state_reader_, &matched) == DDS_RETCODE_OK ? matched.current_count : 0;
}

void DdsLeaderLink::WaitForFollower(double wait_s) const {
  using Clock = std::chrono::steady_clock;
  // One deadline for both steps: the follower authenticated, then its state heard.
  const auto until = Clock::now() + std::chrono::duration<double>(wait_s);
  const auto wait_until = [&](auto&& done) {
    while (!done()) {
      if (Clock::now() >= until) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
  };
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.1f", wait_s);
  if (!wait_until([&] { return FollowersMatched() > 0; })) {
    const std::string where = "no follower authenticated on DDS domain " + std::to_string(options_.domain_id) +
                              " within " + seconds + " s: ";
    const std::string refused = dds_.HandshakeFailure();
    if (!options_.insecure && !refused.empty()) {
      throw std::runtime_error(where + "a DDS Security handshake was refused (Cyclone: \"" + refused + "\"): the " +
                               "peer's certificate is not signed by this unit's CA (" +
                               (options_.keys_dir / "ca_cert.pem").string() + "), or ours not by its CA: give " +
                               "both units folders of the same `robossis keys init`");
    }
    throw std::runtime_error(where + "no peer answered (is `robossis follower` running on the same --domain, " +
                             "reachable through --interface and --peer" + (options_.insecure ? ", and with --insecure too?)" : "?)"));
  }
  if (!wait_until([&] { return Statistics().state_received > 0; })) {
    throw std::runtime_error("a follower was authenticated on DDS domain " + std::to_string(options_.domain_id) +
                             " but its operating state was not heard within " + seconds + " s");
  }
}

LeaderLinkStatistics DdsLeaderLink::Statistics() const noexcept {
  LeaderLinkStatistics s;
  s.setpoints_sent = counters_.setpoints.load();
  s.commands_sent = counters_.commands.load();
  s.commands_refused = counters_.refused.load();
  s.status_received = counters_.status.load();
  s.state_received = counters_.state.load();
  s.estops_sent = counters_.estops.load();
  if (setpoint_writer_ > 0) {
    dds_publication_matched_status_t matched;
    if (dds_get_publication_matched_status(setpoint_writer_, &matched) == DDS_RETCODE_OK) {
      s.followers_matched = matched.current_count;
    }
  }
  return s;
}

void DdsLeaderLink::WriteEStop(std::uint64_t count) {
  const std::int64_t now = rt::MonotonicNowNs();
  robossis_msgs_msg_dds__EStop_ w{};
  w.sender_session = session_;
  w.seq = count;
  w.stamp_ns = now;
  w.engaged = true;
  if (dds_write(estop_writer_, &w) == DDS_RETCODE_OK) counters_.estops.fetch_add(1, std::memory_order_relaxed);
}

void DdsLeaderLink::SendLoop() {
  std::uint64_t version_sent = 0;
  std::uint64_t estops_written = 0;
  char frame_id[] = "";
  while (true) {
    send_wake_.Wait();
    if (stop_.load(std::memory_order_acquire)) break;
    teleop::SetPointMessage m;
    if (setpoint_writer_ > 0 && setpoint_.ReadNewer(m, version_sent)) {
      robossis_msgs_msg_dds__SetPoint_ w{};
      ToWire(m, w);
      if (dds_write(setpoint_writer_, &w) == DDS_RETCODE_OK) counters_.setpoints.fetch_add(1, std::memory_order_relaxed);
    }
    teleop::StateCommandMessage c;
    while (commands_.TryPop(c)) {
      robossis_msgs_msg_dds__StateCommand_ w{};
      ToWire(c, frame_id, w);
      if (dds_write(command_writer_, &w) == DDS_RETCODE_OK) counters_.commands.fetch_add(1, std::memory_order_relaxed);
    }
    // After the commands taken above: a reset queued before an E-stop never reaches the follower after it. Several
    // E-stops engaged since the last write are one sample (the level is engaged either way).
    const std::uint64_t estops = estop_.engaged();
    if (estops != estops_written) {
      WriteEStop(estops);
      estops_written = estops;
    }
  }
}

void DdsLeaderLink::ReceiveLoop() {
  dds_attach_t triggered[4];
  teleop::FollowerStatusMessage assembled;
  // A status is the follower's state with its measured pose: until both have arrived (the topics are independent, and
  // the state may come first), the assembled message would report a robot at the origin.
  bool have_state = false, have_pose = false;
  using JointState = sensor_msgs_msg_dds__JointState_;
  using PoseStamped = geometry_msgs_msg_dds__PoseStamped_;
  using OperatingState = robossis_msgs_msg_dds__OperatingState_;
  while (!stop_.load(std::memory_order_acquire)) {
    const dds_return_t n = dds_waitset_wait(waitset_, triggered, 4, DDS_MSECS(100));
    if (stop_.load(std::memory_order_acquire)) break;
    if (n <= 0) continue;
    bool changed = TakeEach<JointState>(js_reader_, [&](const JointState& js) {
      for (std::uint32_t i = 0; i < 6 && i < js.position._length; ++i) assembled.joints[i] = js.position._buffer[i];
      for (std::uint32_t i = 0; i < 6 && i < js.effort._length; ++i) assembled.effort[i] = js.effort._buffer[i];
    });
    changed |= TakeEach<OperatingState>(state_reader_, [&](const OperatingState& st) {
      FromOperatingState(st, assembled);
      have_state = true;
      counters_.state.fetch_add(1, std::memory_order_relaxed);
    });
    changed |= TakeEach<PoseStamped>(cp_reader_, [&](const PoseStamped& cp) {
      FromMeasuredCp(cp, assembled);
      have_pose = true;
      counters_.status.fetch_add(1, std::memory_order_relaxed);
    });
    if (changed && have_state && have_pose) status_.Publish(assembled);
  }
}

}  // namespace robossis::link
