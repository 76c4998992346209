#include "src/panel/local_session_backend.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>

#include "haptics/device/device_factory.h"
#include "haptics/rendering/renderer_factory.h"
#include "src/panel/view_model.h"

namespace robossis::panel {
namespace {

using teleop::OperatingState;

}  // namespace

LocalSessionBackend::LocalSessionBackend(const robot::RsrModel& model, std::unique_ptr<robot::Follower> back_end,
                                         const teleop::FollowerConfig& follower_config,
                                         const actuation::ActuationConfig& actuation_config,
                                         const JogLimits& jog_limits, const transfer::TransferRates& rates,
                                         const rt::Clock& clock)
    : model_(model),
      jog_limits_(jog_limits),
      period_s_(1.0 / rates.actuation_rate_hz),
      setpoint_period_s_(1.0 / rates.transfer_rate_hz),
      ticks_per_setpoint_(std::max(1, rates.upsampling_ratio())),
      clock_(clock),
      follower_config_(follower_config),
      actuation_config_(actuation_config),
      back_end_(std::move(back_end)),
      link_(clock),
      player_(link_, clock, setpoint_period_s_) {
  if (!back_end_) throw std::invalid_argument("panel session: no follower back end");
  back_end_->Disable();  // the follower starts DISABLED, drives holding
  plant_ = back_end_->plant();
  unit_ = std::make_unique<teleop::FollowerUnit>(model_, actuation_config_, follower_config_, *back_end_, link_,
                                                 clock_);
  health_record_.period_s = period_s_;
  health_.Publish(health_record_);
}

LocalSessionBackend::~LocalSessionBackend() {
  Stop();
  if (device_) device_->EnableForces(false);  // the session is over: the device's forces off, the drives disabled
  back_end_->Disable();
}

void LocalSessionBackend::AttachHapticLeader(HapticLeaderSetup setup) {
  if (setup.sigma7 == nullptr) throw std::invalid_argument("haptic leader: no sigma.7 model");
  setup.leader.rate_hz = 1.0 / setpoint_period_s_;  // the panel's leader side runs at the link's rate
  setup.leader.Validate();
  haptics::DeviceScriptOptions script = setup.leader.sim_script;
  script.replay_frame = setup.transfer.mapping;  // as `robossis teleop` places a replay
  std::unique_ptr<haptics::HapticDevice> device =
      haptics::MakeDevice(setup.device, *setup.sigma7, setup.haptics, setup.leader.device, script);
  if (device->EnableForces(true) != haptics::DeviceStatus::kOk)
    throw std::runtime_error("haptic leader: the device " + setup.device + " refused to enable its forces");
  std::random_device entropy;
  leader_session_base_ = (static_cast<std::uint64_t>(entropy()) << 32) | entropy();
  device_ = std::move(device);
  haptic_setup_ = std::make_unique<HapticLeaderSetup>(std::move(setup));
}

std::vector<std::string> LocalSessionBackend::Start() {
  if (follower_loop_) return {};
  const auto* clock = dynamic_cast<const rt::MonotonicClock*>(&clock_);
  if (clock == nullptr) throw std::logic_error("panel session: the loops need the MonotonicClock");
  threaded_ = true;
  rt::LoopOptions follower;
  follower.name = "panel follower unit";
  follower.period_ns = std::llround(period_s_ * 1e9);
  follower.fifo_priority = rt::kActuationLoopFifoPriority;
  rt::LoopOptions leader;
  leader.name = "panel leader side";
  leader.period_ns = std::llround(setpoint_period_s_ * 1e9);
  leader.fifo_priority = rt::kHapticLoopFifoPriority;
  follower_loop_ = std::make_unique<rt::PeriodicLoop>(*clock, follower_task_, follower);
  leader_loop_ = std::make_unique<rt::PeriodicLoop>(*clock, leader_task_, leader);
  std::vector<rt::PeriodicLoop*> loops = {leader_loop_.get(), follower_loop_.get()};
  if (plant_.task != nullptr) {
    plant_loop_ = std::make_unique<rt::PeriodicLoop>(*clock, *plant_.task, rt::PlantLoopOptions(plant_.period_ns, "panel plant"));
    loops.push_back(plant_loop_.get());
  }
  const std::int64_t start_ns = std::llround(clock->NowS() * 1e9) + leader.period_ns;  // on the clock
  std::vector<std::string> warnings;
  for (rt::PeriodicLoop* loop : loops)
    if (std::string warning = loop->Start(start_ns); !warning.empty()) warnings.push_back(std::move(warning));
  return warnings;
}

void LocalSessionBackend::Stop() {
  if (follower_loop_) follower_loop_->Stop();
  if (leader_loop_) leader_loop_->Stop();
  if (plant_loop_) plant_loop_->Stop();
}

bool LocalSessionBackend::ReadLeaderRecord(teleop::LeaderTickRecord& record) noexcept {
  return !leaders_.empty() && leaders_.back()->unit->latest().Read(record);
}

bool LocalSessionBackend::ReadHandWrench(HandWrench& wrench) noexcept {
  wrench = HandWrench{};  // zero unless the haptic leader runs: no device force outside haptic mode
  teleop::LeaderTickRecord record;
  if (!haptic_granted_ || !ReadLeaderRecord(record)) return true;
  // The force the device displays (device base O) in the fixed frame F, as the view draws it.
  const transfer::HcToRsrFrame& frame = haptic_setup_->transfer.mapping.frame();
  const Eigen::Vector3d f = frame.WrenchToRsr(Eigen::Vector3d(record.f_O[0], record.f_O[1], record.f_O[2]));
  const Eigen::Vector3d tau = frame.WrenchToRsr(Eigen::Vector3d(record.tau_O[0], record.tau_O[1], record.tau_O[2]));
  for (int i = 0; i < 3; ++i) {
    wrench.force_n[i] = f[i];
    wrench.torque_nm[i] = tau[i];
  }
  return true;
}

bool LocalSessionBackend::ReadCommandedPose(Eigen::Isometry3d& X_FM) noexcept {
  CommandedPose pose;
  if (!commanded_.Read(pose)) return false;
  X_FM = Eigen::Isometry3d::Identity();
  X_FM.linear() = Eigen::Quaterniond(pose.q[0], pose.q[1], pose.q[2], pose.q[3]).normalized().toRotationMatrix();
  X_FM.translation() = Eigen::Vector3d(pose.p[0], pose.p[1], pose.p[2]);
  return true;
}

bool LocalSessionBackend::SendCommand(teleop::StateCommand command) noexcept {
  return link_.operator_commands().Send(PanelStateCommand(command, ++command_sequence_, clock_.NowS()));
}

JogVerdict LocalSessionBackend::PreviewJog(const JogRequest& request) {
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

JogVerdict LocalSessionBackend::StartJog(const JogRequest& request) {
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

void LocalSessionBackend::StopJog() noexcept {
  Order order;
  order.kind = Order::kStopJog;
  orders_.TryPush(order);
}

std::unique_ptr<LocalSessionBackend::HapticLeader> LocalSessionBackend::BuildLeader(
    const HapticModeRequest& request, const Eigen::Isometry3d& X_FM_start) {
  const HapticLeaderSetup& setup = *haptic_setup_;
  const std::vector<std::string> methods = haptics::KnownMethods();
  if (request.rendering_method < 0 || request.rendering_method >= static_cast<int>(methods.size()))
    throw std::invalid_argument("haptic mode: rendering method " + std::to_string(request.rendering_method) +
                                " is not known");
  auto leader = std::make_unique<HapticLeader>();
  leader->method = request.rendering_method;
  leader->max_linear_speed_m_s = request.max_linear_speed_m_s;
  leader->max_angular_speed_rad_s = request.max_angular_speed_rad_s;
  transfer::TransferConfig transfer = setup.transfer;
  transfer.caps.max_linear_speed_m_s = request.max_linear_speed_m_s;  // eq. 11 scales the hand to these caps
  transfer.caps.max_angular_speed_rad_s = request.max_angular_speed_rad_s;
  leader->renderer = haptics::MakeRenderer(methods[request.rendering_method], setup.haptics, model_,
                                           haptics::HcToRsrMap{}, setup.leader.rate_hz, setup.atlas,
                                           threaded_ ? haptics::BackgroundWork::kThread
                                                     : haptics::BackgroundWork::kSimulated);
  leader->unit = std::make_unique<teleop::LeaderUnit>(setup.leader, transfer, model_, *device_, *leader->renderer,
                                                      link_, X_FM_start, leader_session_base_ + ++leaders_built_);
  return leader;
}

void LocalSessionBackend::FreeRetiredLeaders() noexcept {
  HapticLeader* retired = nullptr;
  while (retired_.TryPop(retired)) {
    for (auto it = leaders_.begin(); it != leaders_.end(); ++it) {
      if (it->get() != retired) continue;
      leaders_.erase(it);
      break;
    }
  }
}

bool LocalSessionBackend::RequestHapticMode(const HapticModeRequest& request, std::string& reason) {
  reason.clear();
  FreeRetiredLeaders();
  if (!haptic_setup_) {
    reason = "haptic mode: this session has no haptic device";
    return false;
  }
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
  std::unique_ptr<HapticLeader> built;
  if (request.enabled) {
    const HapticLeader* current = haptic_granted_ && !leaders_.empty() ? leaders_.back().get() : nullptr;
    const bool same = current != nullptr && current->method == request.rendering_method &&
                      current->max_linear_speed_m_s == request.max_linear_speed_m_s &&
                      current->max_angular_speed_rad_s == request.max_angular_speed_rad_s;
    if (current != nullptr && !same && !request.clutched) {
      // The rule of haptic_mode.h, checked again where it matters: the robot must not follow during the change.
      reason = "haptic mode: the method and the caps change only while clutched";
      return false;
    }
    if (!same) {
      try {
        built = BuildLeader(request, PoseOf(status));  // from where the follower is
      } catch (const std::exception& e) {
        reason = std::string("haptic mode: ") + e.what();
        return false;
      }
      order.leader = built.get();
    }
  }
  if (!orders_.TryPush(order)) {
    reason = "haptic mode: the follower's request queue is full";
    return false;
  }
  if (built) leaders_.push_back(std::move(built));
  haptic_granted_ = request.enabled;
  return true;
}

// ---- loop thread ----

void LocalSessionBackend::LeaderSideTick() noexcept {
  Order order;
  while (orders_.TryPop(order)) {
    switch (order.kind) {
      case Order::kJog:
        if (!haptic_active_)
          player_.StartMove(Eigen::Vector3d(order.delta_p_F[0], order.delta_p_F[1], order.delta_p_F[2]),
                            Eigen::Vector3d(order.delta_rot_F[0], order.delta_rot_F[1], order.delta_rot_F[2]),
                            order.duration_s);
        break;
      case Order::kStopJog:
        player_.StopMove();
        break;
      case Order::kHaptic:
        if (order.leader != nullptr) {
          if (active_leader_ != nullptr) retired_.TryPush(active_leader_);  // full: freed with the backend
          active_leader_ = order.leader;
        }
        if (order.haptic && active_leader_ != nullptr) {
          player_.StopMove();  // haptic mode and a jog never run together
          active_leader_->unit->RequestClutch(order.clutched);
          haptic_active_ = true;
        } else if (!order.haptic && haptic_active_) {
          haptic_active_ = false;
          device_->Write(haptics::DeviceCommand{});  // nobody writes the device any more: leave it at zero force
          player_.Resync();                           // the hand moved the robot: hold where it is now
        }
        break;
    }
  }
  const double now_s = clock_.NowS();
  if (haptic_active_) {
    active_leader_->unit->Tick(static_cast<std::int64_t>(std::llround(now_s * 1e9)));
    teleop::LeaderTickRecord record;
    if (active_leader_->unit->latest().Read(record) && (record.flags & teleop::kSetPointPresence) != 0)
      last_presence_s_.store(now_s, std::memory_order_relaxed);
  } else {
    player_.Tick();
    last_presence_s_.store(player_.last_presence_s(), std::memory_order_relaxed);
  }
}

void LocalSessionBackend::Step() noexcept {
  if (!threaded_ && tick_ % static_cast<std::uint64_t>(ticks_per_setpoint_) == 0) LeaderSideTick();
  FollowerTick();
}

void LocalSessionBackend::FollowerTick() noexcept {
  const double now_s = clock_.NowS();
  if (last_step_s_ >= 0) {
    health_record_.last_jitter_s = std::abs((now_s - last_step_s_) - period_s_);
    health_record_.max_jitter_s = std::max(health_record_.max_jitter_s, health_record_.last_jitter_s);
  }
  last_step_s_ = now_s;
  ++health_record_.ticks;
  ++tick_;
  unit_->Tick();  // the follower unit: the one validated path
  if (!threaded_ && plant_.task != nullptr) {  // without the loops the plant is due here, after the command
    const std::int64_t now_ns = std::llround(now_s * 1e9);
    if (now_ns >= next_plant_ns_) {
      plant_.task->Tick(now_ns);
      next_plant_ns_ = now_ns - now_ns % plant_.period_ns + plant_.period_ns;  // skipped, not made up
    }
  }

  const Eigen::Isometry3d& X = unit_->commanded_pose();
  const Eigen::Quaterniond q(X.linear());
  commanded_.Publish({{X.translation().x(), X.translation().y(), X.translation().z()}, {q.w(), q.x(), q.y(), q.z()}});
  const double last = last_presence_s_.load(std::memory_order_relaxed);
  health_record_.setpoint_age_s = last < 0 ? -1 : now_s - last;
  health_record_.watchdog_holds = unit_->counters().watchdog_holds;
  health_record_.setpoints_by_verdict = unit_->counters().setpoints_by_verdict;
  if (follower_loop_) {  // the loops' own counts (atomics); without the loops, a test's Step() has none
    health_record_.follower_loop = follower_loop_->counts();
    health_record_.leader_loop = leader_loop_->counts();
  }
  health_.Publish(health_record_);
}

}  // namespace robossis::panel
