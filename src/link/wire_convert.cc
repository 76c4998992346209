#include "src/link/wire_convert.h"

#include <time.h>

#include <cstring>

namespace robossis::link {

builtin_interfaces_msg_dds__Time_ ToTime(std::int64_t stamp_ns) noexcept {
  std::int64_t sec = stamp_ns / 1000000000;
  std::int64_t nsec = stamp_ns % 1000000000;
  if (nsec < 0) {
    nsec += 1000000000;
    sec -= 1;
  }
  return {static_cast<std::int32_t>(sec), static_cast<std::uint32_t>(nsec)};
}

std::int64_t FromTime(const builtin_interfaces_msg_dds__Time_& t) noexcept {
  return static_cast<std::int64_t>(t.sec) * 1000000000 + static_cast<std::int64_t>(t.nanosec);
}

std::int64_t SystemNowNs() noexcept {
  timespec t{};
  clock_gettime(CLOCK_REALTIME, &t);
  return static_cast<std::int64_t>(t.tv_sec) * 1000000000 + t.tv_nsec;
}

namespace {
void ToPose(const std::array<double, 3>& p, const std::array<double, 4>& q, geometry_msgs_msg_dds__Pose_& w) noexcept {
  w.position = {p[0], p[1], p[2]};
  w.orientation = {q[1], q[2], q[3], q[0]};
}
void FromPose(const geometry_msgs_msg_dds__Pose_& w, std::array<double, 3>& p, std::array<double, 4>& q) noexcept {
  p = {w.position.x, w.position.y, w.position.z};
  q = {w.orientation.w, w.orientation.x, w.orientation.y, w.orientation.z};
}

struct CommandNameEntry { teleop::StateCommand command; const char* name; };
constexpr CommandNameEntry kCommands[] = {{teleop::StateCommand::kEnable, "enable"},
                                          {teleop::StateCommand::kDisable, "disable"},
                                          {teleop::StateCommand::kHome, "home"},
                                          {teleop::StateCommand::kEStop, "estop"},
                                          {teleop::StateCommand::kReset, "reset"}};
struct StateNameEntry { teleop::OperatingState state; const char* name; };
constexpr StateNameEntry kStates[] = {{teleop::OperatingState::kDisabled, "DISABLED"},
                                      {teleop::OperatingState::kHoming, "HOMING"},
                                      {teleop::OperatingState::kReady, "READY"},
                                      {teleop::OperatingState::kEnabled, "ENABLED"},
                                      {teleop::OperatingState::kClutched, "PAUSED"},
                                      {teleop::OperatingState::kFault, "FAULT"},
                                      {teleop::OperatingState::kEStop, "ESTOP"}};
}  // namespace

void ToWire(const teleop::SetPointMessage& m, robossis_msgs_msg_dds__SetPoint_& w) noexcept {
  w.seq = m.sequence;
  w.leader_session = m.leader_session;
  w.stamp_ns = m.stamp_ns;
  ToPose(m.p_FM, m.q_FM, w.pose);
  w.twist.linear = {m.twist_F[0], m.twist_F[1], m.twist_F[2]};
  w.twist.angular = {m.twist_F[3], m.twist_F[4], m.twist_F[5]};
  w.clutch = (m.flags & teleop::kSetPointClutched) != 0;
  w.presence = (m.flags & teleop::kSetPointPresence) != 0;
  w.flags = m.flags;  // all bits, including those added after clutch and presence
  w.hand_energy_in_j = m.hand_energy_in_j;
}

void FromWire(const robossis_msgs_msg_dds__SetPoint_& w, teleop::SetPointMessage& m) noexcept {
  m.sequence = w.seq;
  m.leader_session = w.leader_session;
  m.stamp_ns = w.stamp_ns;
  FromPose(w.pose, m.p_FM, m.q_FM);
  m.twist_F = {w.twist.linear.x, w.twist.linear.y, w.twist.linear.z,
               w.twist.angular.x, w.twist.angular.y, w.twist.angular.z};
  m.flags = static_cast<std::uint8_t>(w.flags | (w.clutch ? teleop::kSetPointClutched : 0) |
                                      (w.presence ? teleop::kSetPointPresence : 0));
  m.hand_energy_in_j = w.hand_energy_in_j;
}

const char* CommandName(teleop::StateCommand c) noexcept {
  for (const auto& e : kCommands) {
    if (e.command == c) return e.name;
  }
  return "?";
}

bool ParseCommandName(const char* name, teleop::StateCommand& c) noexcept {
  if (name == nullptr) return false;
  for (const auto& e : kCommands) {
    if (std::strcmp(e.name, name) == 0) {
      c = e.command;
      return true;
    }
  }
  return false;
}

void ToWire(const teleop::StateCommandMessage& m, char* frame_id, robossis_msgs_msg_dds__StateCommand_& w) noexcept {
  w.header.stamp = ToTime(m.stamp_ns);
  w.header.frame_id = frame_id;
  w.command = const_cast<char*>(CommandName(m.command));
  w.session = m.session;
  w.seq = m.sequence;
  w.stamp_ns = m.stamp_ns;
  w.source = m.source;
}

bool FromWire(const robossis_msgs_msg_dds__StateCommand_& w, teleop::StateCommandMessage& m) noexcept {
  if (!ParseCommandName(w.command, m.command)) return false;
  m.session = w.session;
  m.sequence = w.seq;
  m.stamp_ns = w.stamp_ns;
  m.source = w.source;
  return true;
}

const char* OperatingStateName(teleop::OperatingState s) noexcept {
  for (const auto& e : kStates) {
    if (e.state == s) return e.name;
  }
  return "?";
}

bool ParseOperatingStateName(const char* name, teleop::OperatingState& s) noexcept {
  if (name == nullptr) return false;
  for (const auto& e : kStates) {
    if (std::strcmp(e.name, name) == 0) {
      s = e.state;
      return true;
    }
  }
  return false;
}

void ToMeasuredCp(const teleop::FollowerStatusMessage& m, std::int64_t header_stamp_ns, char* frame_id,
                  geometry_msgs_msg_dds__PoseStamped_& w) noexcept {
  w.header.stamp = ToTime(header_stamp_ns);
  w.header.frame_id = frame_id;
  ToPose(m.p_FM, m.q_FM, w.pose);
}

void ToOperatingState(const teleop::FollowerStatusMessage& m, std::int64_t header_stamp_ns, char* frame_id,
                      robossis_msgs_msg_dds__OperatingState_& w) noexcept {
  w.header.stamp = ToTime(header_stamp_ns);
  w.header.frame_id = frame_id;
  w.state = const_cast<char*>(OperatingStateName(m.state));
  w.is_homed = m.homed;
  w.is_busy = m.state == teleop::OperatingState::kHoming;
  w.seq = m.sequence;
  w.stamp_ns = m.stamp_ns;
  w.fault_reason = static_cast<std::uint8_t>(m.fault_reason);
  w.back_end_fault = m.back_end_fault;
  w.setpoints_accepted = m.setpoints_accepted;
  w.setpoints_rejected = m.setpoints_rejected;
  w.watchdog_holds = m.watchdog_holds;
  w.last_sequence = m.last_sequence;
  w.max_linear_speed_m_s = m.limits.max_linear_speed_m_s;
  w.max_angular_speed_rad_s = m.limits.max_angular_speed_rad_s;
  w.max_linear_accel_m_s2 = m.limits.max_linear_accel_m_s2;
  w.max_angular_accel_rad_s2 = m.limits.max_angular_accel_rad_s2;
  w.max_setpoint_age_s = m.limits.max_age_s;
  w.model_fingerprint = m.limits.model_fingerprint;
  for (int i = 0; i < 6; ++i) w.wrench[i] = m.wrench_F[i];
  w.wrench_source = static_cast<std::uint8_t>(m.wrench_source);
  w.port_energy_in_j = m.port_energy_in_j;
  w.port_energy_out_j = m.port_energy_out_j;
}

void FromMeasuredCp(const geometry_msgs_msg_dds__PoseStamped_& w, teleop::FollowerStatusMessage& m) noexcept {
  m.stamp_ns = FromTime(w.header.stamp);
  FromPose(w.pose, m.p_FM, m.q_FM);
}

void FromOperatingState(const robossis_msgs_msg_dds__OperatingState_& w, teleop::FollowerStatusMessage& m) noexcept {
  teleop::OperatingState s;
  m.state = ParseOperatingStateName(w.state, s) ? s : teleop::OperatingState::kFault;
  m.sequence = w.seq;
  m.homed = w.is_homed;
  m.fault_reason = w.fault_reason <= static_cast<std::uint8_t>(teleop::FaultReason::kNotHomed)
                       ? static_cast<teleop::FaultReason>(w.fault_reason) : teleop::FaultReason::kBackEnd;
  m.back_end_fault = w.back_end_fault;
  m.setpoints_accepted = w.setpoints_accepted;
  m.setpoints_rejected = w.setpoints_rejected;
  m.watchdog_holds = w.watchdog_holds;
  m.last_sequence = w.last_sequence;
  m.limits.max_linear_speed_m_s = w.max_linear_speed_m_s;
  m.limits.max_angular_speed_rad_s = w.max_angular_speed_rad_s;
  m.limits.max_linear_accel_m_s2 = w.max_linear_accel_m_s2;
  m.limits.max_angular_accel_rad_s2 = w.max_angular_accel_rad_s2;
  m.limits.max_age_s = w.max_setpoint_age_s;
  m.limits.model_fingerprint = w.model_fingerprint;
  for (int i = 0; i < 6; ++i) m.wrench_F[i] = w.wrench[i];
  // An unknown source is no wrench: the leader shows none.
  m.wrench_source = w.wrench_source <= static_cast<std::uint8_t>(teleop::WrenchSource::kForceSensor)
                        ? static_cast<teleop::WrenchSource>(w.wrench_source) : teleop::WrenchSource::kNone;
  m.port_energy_in_j = w.port_energy_in_j;
  m.port_energy_out_j = w.port_energy_out_j;
}

}  // namespace robossis::link
