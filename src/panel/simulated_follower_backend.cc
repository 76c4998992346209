#include "src/panel/simulated_follower_backend.h"

#include <time.h>

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "src/panel/view_model.h"

namespace robossis::panel {
namespace {

using teleop::OperatingState;

// The leader's set-point rate: the paper's 1 kHz link (the follower ticks at 10 kHz between set-points).
constexpr double kSetPointRateHz = 1000;

sim::SimOptions MechanismOnly(bool gravity) {
  sim::SimOptions options;
  options.with_bone = false;      // at the home pose the fragments touch: a jog would push one into the other
  options.with_traction = false;
  options.gravity = gravity;
  return options;
}

}  // namespace

SimulatedFollowerBackend::SimulatedFollowerBackend(const robot::RsrModel& model, const sim::SimConfig& sim_config,
                                                   bool gravity, const teleop::FollowerConfig& follower_config,
                                                   const actuation::ActuationConfig& actuation_config,
                                                   const JogLimits& jog_limits, double tick_rate_hz,
                                                   const rt::Clock& clock)
    : model_(model),
      jog_limits_(jog_limits),
      period_s_(1.0 / tick_rate_hz),
      ticks_per_setpoint_(std::max(1, static_cast<int>(std::lround(tick_rate_hz / kSetPointRateHz)))),
      clock_(clock),
      follower_config_(follower_config),
      actuation_config_(actuation_config),
      sim_(std::make_unique<sim::RsrSimulation>(model, sim_config, nullptr, nullptr, model.geometry().X_FM_home,
                                                MechanismOnly(gravity))),
      link_(clock),
      player_(link_, clock) {
  sim_->Disable();  // the follower starts DISABLED, drives holding
  unit_ = std::make_unique<teleop::FollowerUnit>(model_, actuation_config_, follower_config_, *sim_, link_, clock_);
  health_record_.period_s = period_s_;
  health_.Publish(health_record_);
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
  const std::int64_t period_ns = static_cast<std::int64_t>(std::llround(period_s_ * 1e9));
  std::int64_t deadline_ns = rt::MonotonicNowNs() + period_ns;
  while (!stop_.load(std::memory_order_relaxed)) {
    timespec wake{static_cast<time_t>(deadline_ns / 1000000000), static_cast<long>(deadline_ns % 1000000000)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &wake, nullptr) != 0) {
    }
    Step();
    deadline_ns += period_ns;
    if (rt::MonotonicNowNs() > deadline_ns) {  // missed the next deadline: count it and start afresh
      ++health_record_.overruns;
      deadline_ns = rt::MonotonicNowNs() + period_ns;
    }
  }
}

bool SimulatedFollowerBackend::ReadHandWrench(HandWrench& wrench) noexcept {
  wrench = HandWrench{};  // no leader device and no hand in this session
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

bool SimulatedFollowerBackend::SendCommand(teleop::StateCommand command) noexcept {
  teleop::StateCommandMessage message;
  message.sequence = ++command_sequence_;
  message.stamp_ns = static_cast<std::int64_t>(std::llround(clock_.NowS() * 1e9));
  message.command = command;
  message.source = 2;  // panel
  return link_.operator_commands().Send(message);
}

JogVerdict SimulatedFollowerBackend::PreviewJog(const JogRequest& request) {
  teleop::FollowerStatusMessage status;
  if (!ReadStatus(status)) {
    JogVerdict verdict;
    verdict.reason = "jog: no follower status yet";
    return verdict;
  }
  JogVerdict verdict = panel::PreviewJog(model_, PoseOf(status), request, jog_limits_);
  if (verdict.accepted && status.state != OperatingState::kReady) {
    verdict.accepted = false;
    verdict.reason = std::string("jog: the follower is ") + teleop::ToString(status.state) + ", jogs run only when ready";
  }
  return verdict;
}

JogVerdict SimulatedFollowerBackend::StartJog(const JogRequest& request) {
  JogVerdict verdict = PreviewJog(request);
  if (!verdict.accepted) return verdict;
  Order order;
  order.kind = Order::kJog;
  const transfer::TimedMoveRequest move = ToTimedMoveRequest(request, 0);
  for (int i = 0; i < 3; ++i) {
    order.delta_p_F[i] = move.delta_p_F[i];
    order.delta_rot_F[i] = move.delta_rot_F[i];
  }
  order.duration_s = verdict.duration_s;
  if (!orders_.TryPush(order)) {
    verdict.accepted = false;
    verdict.reason = "jog: the follower's jog queue is full";
  }
  return verdict;
}

void SimulatedFollowerBackend::StopJog() noexcept {
  Order order;
  order.kind = Order::kStopJog;
  orders_.TryPush(order);
}

bool SimulatedFollowerBackend::RequestHapticMode(const HapticModeRequest& request, std::string& reason) {
  reason.clear();
  teleop::FollowerStatusMessage status;
  ReadStatus(status);
  const bool operable = status.state == OperatingState::kReady || status.state == OperatingState::kEnabled ||
                        status.state == OperatingState::kClutched;
  if (request.enabled && !operable) {
    reason = std::string("haptic mode: the follower is ") + teleop::ToString(status.state) + ", home it first";
    return false;
  }
  Order order;
  order.kind = Order::kHaptic;
  order.haptic = request.enabled;
  order.clutched = request.clutched;
  if (!orders_.TryPush(order)) {
    reason = "haptic mode: the follower's request queue is full";
    return false;
  }
  return true;
}

// ---- loop thread ----

void SimulatedFollowerBackend::Step() noexcept {
  const double now_s = clock_.NowS();
  if (last_step_s_ >= 0) {
    health_record_.last_jitter_s = std::abs((now_s - last_step_s_) - period_s_);
    health_record_.max_jitter_s = std::max(health_record_.max_jitter_s, health_record_.last_jitter_s);
  }
  last_step_s_ = now_s;
  ++health_record_.ticks;

  Order order;
  while (orders_.TryPop(order)) {
    switch (order.kind) {
      case Order::kJog:
        player_.StartMove(Eigen::Vector3d(order.delta_p_F[0], order.delta_p_F[1], order.delta_p_F[2]),
                          Eigen::Vector3d(order.delta_rot_F[0], order.delta_rot_F[1], order.delta_rot_F[2]),
                          order.duration_s);
        break;
      case Order::kStopJog:
        player_.StopMove();
        break;
      case Order::kHaptic:
        player_.SetHaptic(order.haptic, order.clutched);
        break;
    }
  }
  if (tick_ % static_cast<std::uint64_t>(ticks_per_setpoint_) == 0) player_.Tick();  // the leader side, 1 kHz
  ++tick_;
  unit_->Tick();  // the follower unit: the one validated path

  const Eigen::Isometry3d& X = unit_->commanded_pose();
  const Eigen::Quaterniond q(X.linear());
  commanded_.Publish({{X.translation().x(), X.translation().y(), X.translation().z()}, {q.w(), q.x(), q.y(), q.z()}});
  const double last = player_.last_presence_s();
  health_record_.setpoint_age_s = last < 0 ? -1 : now_s - last;
  health_record_.watchdog_holds = unit_->counters().watchdog_holds;
  health_.Publish(health_record_);
}

}  // namespace robossis::panel
