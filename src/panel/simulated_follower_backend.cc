#include "src/panel/simulated_follower_backend.h"

#include <time.h>

#include <cmath>

#include <Eigen/Geometry>

#include "src/core/rt/clock.h"
#include "src/panel/view_model.h"

namespace robossis::panel {
namespace {

using teleop::FaultReason;
using teleop::OperatingState;
using teleop::StateCommand;

sim::SimOptions MechanismOnly(bool gravity) {
  sim::SimOptions options;
  options.with_bone = false;      // at the home pose the fragments touch: a jog would push one into the other
  options.with_traction = false;
  options.gravity = gravity;
  return options;
}

bool Jogging(OperatingState state) { return state == OperatingState::kReady; }

}  // namespace

SimulatedFollowerBackend::SimulatedFollowerBackend(const robot::RsrModel& model, const sim::SimConfig& sim_config,
                                                   bool gravity, const JogLimits& jog_limits, double loop_rate_hz)
    : model_(model),
      jog_limits_(jog_limits),
      period_s_(1.0 / loop_rate_hz),
      sim_(std::make_unique<sim::RsrSimulation>(model, sim_config, nullptr, nullptr, model.geometry().X_FM_home,
                                                MechanismOnly(gravity))),
      validator_(model_, jog_limits.setpoint) {
  sim_->Disable();  // the follower starts DISABLED, drives holding
  X_hold_ = model.geometry().X_FM_home;
  health_record_.period_s = period_s_;
  Publish(0);
}

SimulatedFollowerBackend::~SimulatedFollowerBackend() { Stop(); }

void SimulatedFollowerBackend::Start() {
  if (thread_.joinable()) return;
  stop_.store(false);
  thread_ = std::thread([this] { Loop(); });
}

void SimulatedFollowerBackend::Stop() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

void SimulatedFollowerBackend::Loop() {
  const rt::MonotonicClock clock;
  const std::int64_t period_ns = static_cast<std::int64_t>(std::llround(period_s_ * 1e9));
  std::int64_t deadline_ns = clock.epoch_ns() + period_ns;
  while (!stop_.load(std::memory_order_relaxed)) {
    timespec wake{static_cast<time_t>(deadline_ns / 1000000000), static_cast<long>(deadline_ns % 1000000000)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &wake, nullptr) != 0) {
    }
    Step(clock.NowS());
    deadline_ns += period_ns;
    if (rt::MonotonicNowNs() > deadline_ns) {  // missed the next deadline: count it and start afresh
      ++health_record_.overruns;
      deadline_ns = rt::MonotonicNowNs() + period_ns;
    }
  }
}

bool SimulatedFollowerBackend::ReadHandWrench(HandWrench& wrench) noexcept {
  wrench = HandWrench{};  // no leader and no hand in this session
  return true;
}

bool SimulatedFollowerBackend::ReadCommandedPose(Eigen::Isometry3d& X_FM) noexcept {
  CommandedPose pose;
  if (!commanded_.Read(pose)) return false;
  X_FM = Eigen::Isometry3d::Identity();
  X_FM.linear() = Eigen::Quaterniond(pose.q[0], pose.q[1], pose.q[2], pose.q[3]).normalized().toRotationMatrix();
  X_FM.translation() = Eigen::Vector3d(pose.p[0], pose.p[1], pose.p[2]);
  return true;
}

bool SimulatedFollowerBackend::SendCommand(StateCommand command) noexcept {
  teleop::StateCommandMessage message;
  message.sequence = ++command_sequence_;
  message.stamp_ns = rt::MonotonicNowNs();
  message.command = command;
  message.source = 2;  // panel
  return commands_.TryPush(message);
}

JogVerdict SimulatedFollowerBackend::PreviewJog(const JogRequest& request) {
  teleop::FollowerStatusMessage status;
  if (!status_.Read(status)) {
    JogVerdict verdict;
    verdict.reason = "jog: no follower status yet";
    return verdict;
  }
  JogVerdict verdict = panel::PreviewJog(model_, PoseOf(status), request, jog_limits_);
  if (verdict.accepted && !Jogging(status.state)) {
    verdict.accepted = false;
    verdict.reason = std::string("jog: the follower is ") + teleop::ToString(status.state) + ", jogs run only when ready";
  }
  return verdict;
}

JogVerdict SimulatedFollowerBackend::StartJog(const JogRequest& request) {
  JogVerdict verdict = PreviewJog(request);
  if (!verdict.accepted) return verdict;
  JogOrder order;
  const transfer::TimedMoveRequest move = ToTimedMoveRequest(request, 0);
  for (int i = 0; i < 3; ++i) {
    order.delta_p_F[i] = move.delta_p_F[i];
    order.delta_rot_F[i] = move.delta_rot_F[i];
  }
  order.duration_s = verdict.duration_s;
  if (!jogs_.TryPush(order)) {
    verdict.accepted = false;
    verdict.reason = "jog: the follower's jog queue is full";
  }
  return verdict;
}

void SimulatedFollowerBackend::StopJog() noexcept {
  JogOrder order;
  order.stop = true;
  jogs_.TryPush(order);
}

bool SimulatedFollowerBackend::RequestHapticMode(const HapticModeRequest& request, std::string& reason) {
  reason.clear();
  teleop::FollowerStatusMessage status;
  status_.Read(status);
  const bool operable = status.state == OperatingState::kReady || status.state == OperatingState::kEnabled ||
                        status.state == OperatingState::kClutched;
  if (request.enabled && !operable) {
    reason = std::string("haptic mode: the follower is ") + teleop::ToString(status.state) + ", home it first";
    return false;
  }
  if (!haptic_.TryPush(request)) {
    reason = "haptic mode: the follower's request queue is full";
    return false;
  }
  return true;
}

// ---- loop thread ----

void SimulatedFollowerBackend::Latch(OperatingState state, FaultReason reason) noexcept {
  state_ = state;
  fault_ = reason;
  move_.reset();
  X_hold_ = sim_->State().X_FM;
  sim_->Disable();  // drives hold where they are
  validator_.Reset();  // the next set-point re-anchors
}

void SimulatedFollowerBackend::ApplyCommand(StateCommand command) noexcept {
  const bool latched = state_ == OperatingState::kEStop || state_ == OperatingState::kFault;
  switch (command) {
    case StateCommand::kEStop:
      Latch(OperatingState::kEStop, FaultReason::kEStop);
      break;
    case StateCommand::kReset:
      if (!latched) break;
      if (!sim_->ResetFault() && sim_->State().faulted()) break;  // the cause is still there
      X_hold_ = sim_->State().X_FM;
      validator_.Reset();
      if (sim_->Enable()) {
        state_ = OperatingState::kReady;
        fault_ = FaultReason::kNone;
        back_end_fault_ = 0;
      }
      break;
    case StateCommand::kDisable:
      if (latched) break;
      move_.reset();
      X_hold_ = sim_->State().X_FM;
      sim_->Disable();
      validator_.Reset();
      state_ = OperatingState::kDisabled;
      break;
    case StateCommand::kHome:
      if (state_ == OperatingState::kDisabled) state_ = OperatingState::kHoming;
      break;
    case StateCommand::kEnable:
      if (state_ == OperatingState::kReady) {
        move_.reset();
        state_ = OperatingState::kEnabled;
      }
      break;
  }
}

void SimulatedFollowerBackend::ApplyJogOrder(const JogOrder& order, double now_s) noexcept {
  if (order.stop) {
    if (move_) X_hold_ = move_->Evaluate(now_s).X_FM;  // end where the eq. 9 path is now
    move_.reset();
    return;
  }
  if (!Jogging(state_) || move_ || !(order.duration_s >= 0) || !std::isfinite(order.duration_s)) {
    ++setpoints_rejected_;
    return;
  }
  transfer::TimedMoveRequest request;
  request.delta_p_F = Eigen::Vector3d(order.delta_p_F[0], order.delta_p_F[1], order.delta_p_F[2]);
  request.delta_rot_F = Eigen::Vector3d(order.delta_rot_F[0], order.delta_rot_F[1], order.delta_rot_F[2]);
  request.start_time_s = now_s;
  move_.emplace(X_hold_, request, order.duration_s);  // eq. 9
}

void SimulatedFollowerBackend::ApplyHapticRequest(const HapticModeRequest& request) noexcept {
  // No leader in this session: haptic mode is the follower's ENABLED/CLUTCHED states, holding the pose.
  if (request.enabled) {
    if (state_ == OperatingState::kReady) ApplyCommand(StateCommand::kEnable);
    if (state_ == OperatingState::kEnabled && request.clutched) state_ = OperatingState::kClutched;
    if (state_ == OperatingState::kClutched && !request.clutched) state_ = OperatingState::kEnabled;
  } else if (state_ == OperatingState::kEnabled || state_ == OperatingState::kClutched) {
    state_ = OperatingState::kReady;
  }
}

void SimulatedFollowerBackend::CommandPose(const Eigen::Isometry3d& X_FM, const Vector6d& twist,
                                           double now_s) noexcept {
  // The one validated path (workspace by the exact IK, caps); a refused set-point holds and latches.
  const teleop::SetPointVerdict verdict = validator_.Check({now_s, X_FM, twist});
  if (verdict != teleop::SetPointVerdict::kAccepted) {
    ++setpoints_rejected_;
    Latch(OperatingState::kFault, verdict == teleop::SetPointVerdict::kTooFast ||
                                          verdict == teleop::SetPointVerdict::kTooAccelerating
                                      ? FaultReason::kSetPointTooFast
                                      : FaultReason::kSetPointInvalid);
    return;
  }
  const robot::RsrIkResult ik = robot::CalcInverseKinematics(model_, X_FM);  // eq. 5–8: the joints to command
  robot::RsrJointCommand command;
  command.time_s = now_s;
  command.q = ik.joints.actuated();
  command.q_dot = robot::CalcJacobian(model_, X_FM) * twist;  // eq. 15
  sim_->Command(command);
  const Eigen::Quaterniond q(X_FM.linear());
  commanded_.Publish({{X_FM.translation().x(), X_FM.translation().y(), X_FM.translation().z()}, {q.w(), q.x(), q.y(), q.z()}});
}

void SimulatedFollowerBackend::Step(double now_s) noexcept {
  if (last_step_s_ >= 0) {
    health_record_.last_jitter_s = std::abs((now_s - last_step_s_) - period_s_);
    if (health_record_.last_jitter_s > health_record_.max_jitter_s) health_record_.max_jitter_s = health_record_.last_jitter_s;
  }
  last_step_s_ = now_s;
  ++health_record_.ticks;

  teleop::StateCommandMessage command;
  while (commands_.TryPop(command)) ApplyCommand(command.command);
  HapticModeRequest haptic;
  while (haptic_.TryPop(haptic)) ApplyHapticRequest(haptic);
  JogOrder order;
  while (jogs_.TryPop(order)) ApplyJogOrder(order, now_s);

  if (state_ == OperatingState::kHoming && sim_->Home() && sim_->Enable()) {
    X_hold_ = sim_->State().X_FM;
    validator_.Reset();
    state_ = OperatingState::kReady;
  }
  const bool powered = state_ == OperatingState::kReady || state_ == OperatingState::kEnabled ||
                       state_ == OperatingState::kClutched;
  if (powered) {
    if (move_) {
      const transfer::RsrSetPoint set_point = move_->Evaluate(now_s);  // eq. 9
      CommandPose(set_point.X_FM, set_point.velocity, now_s);
      ++setpoints_accepted_;
      last_setpoint_s_ = now_s;
      if (move_ && now_s >= move_->end_time_s()) {
        X_hold_ = move_->X_FM_end();
        move_.reset();
      }
    } else {
      CommandPose(X_hold_, Vector6d::Zero(), now_s);
    }
  }
  sim_->Service(now_s);
  const robot::RsrFollowerState measured = sim_->State();
  if (measured.faulted() && state_ != OperatingState::kFault && state_ != OperatingState::kEStop) {
    back_end_fault_ = static_cast<std::uint8_t>(measured.fault);
    Latch(OperatingState::kFault, FaultReason::kBackEnd);
  }
  Publish(now_s);
}

void SimulatedFollowerBackend::Publish(double now_s) noexcept {
  const robot::RsrFollowerState measured = sim_->State();
  teleop::FollowerStatusMessage status;
  status.sequence = ++sequence_;
  status.stamp_ns = static_cast<std::int64_t>(std::llround(now_s * 1e9));
  const Eigen::Vector3d p = measured.X_FM.translation();
  const Eigen::Quaterniond q(measured.X_FM.linear());
  status.p_FM = {p.x(), p.y(), p.z()};
  status.q_FM = {q.w(), q.x(), q.y(), q.z()};
  for (int i = 0; i < 6; ++i) {
    status.joints[i] = measured.q[i];
    status.effort[i] = measured.effort[i];
  }
  status.state = state_;
  status.fault_reason = fault_;
  status.back_end_fault = back_end_fault_;
  status.setpoints_accepted = setpoints_accepted_;
  status.setpoints_rejected = setpoints_rejected_;
  status.last_sequence = setpoints_accepted_;
  status_.Publish(status);
  health_record_.setpoint_age_s = last_setpoint_s_ < 0 ? -1 : now_s - last_setpoint_s_;
  health_.Publish(health_record_);
}

}  // namespace robossis::panel
