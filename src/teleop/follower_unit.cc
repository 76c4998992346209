#include "src/teleop/follower_unit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "src/teleop/capped_motion.h"
#include "src/teleop/follower_limits.h"

namespace robossis::teleop {

namespace {

void StorePose(const Eigen::Isometry3d& X, std::array<double, 3>& p, std::array<double, 4>& q) noexcept {
  const Eigen::Quaterniond quat(X.linear());
  for (int i = 0; i < 3; ++i) p[i] = X.translation()[i];
  q = {quat.w(), quat.x(), quat.y(), quat.z()};
}

template <int N, typename Vec>
void StoreVector(const Vec& v, std::array<double, N>& out) noexcept {
  for (int i = 0; i < N; ++i) out[i] = v[i];
}

}  // namespace

FollowerUnit::FollowerUnit(const robot::RsrModel& model, const actuation::ActuationConfig& actuation,
                           const FollowerConfig& config, robot::Follower& back_end, FollowerLink& link,
                           const rt::Clock& clock)
    : model_(model),
      config_((config.Validate(), config)),
      back_end_(back_end),
      link_(link),
      clock_(clock),
      validator_(model, config.setpoint),
      guard_(model, config.guard),
      actuator_(model, actuation, back_end.State().X_FM, clock.NowS()),
      records_(config.recorder_capacity) {
  X_cmd_ = back_end.State().X_FM;
  limits_ = LimitsOf(config_);
  if (!robot::CalcInverseKinematics(model, X_cmd_).feasible) {
    throw std::invalid_argument("follower unit: the back end's measured pose is outside the joint limits");
  }
  last_tick_s_ = clock.NowS();
}

Eigen::Isometry3d FollowerUnit::WantedPose(double now_s) noexcept {
  // The 1 kHz set-point at this tick: first-order hold by its twist, extrapolated at most max_extrapolation_s.
  const double ahead = std::clamp(now_s - setpoint_arrival_s_, 0.0, config_.watchdog.max_extrapolation_s);
  const Eigen::Isometry3d X_sp = robot::ApplyTwistStep(setpoint_.X_FM, setpoint_.twist_F * ahead);
  if (need_anchor_) {
    X_anchor_setpoint_ = setpoint_.X_FM;
    X_anchor_cmd_ = X_cmd_;
    need_anchor_ = false;
  }
  // Re-anchored: the set-point's motion since the anchor, applied to the commanded pose at the anchor (in F, as
  // the incremental mapping of eq. 10 does), so that resuming never jumps.
  Eigen::Isometry3d X = X_anchor_cmd_;
  X.translation() += X_sp.translation() - X_anchor_setpoint_.translation();
  X.linear() = (X_sp.linear() * X_anchor_setpoint_.linear().transpose()) * X_anchor_cmd_.linear();
  return X;
}

void FollowerUnit::Tick() noexcept {
  const double now = clock_.NowS();
  // The interval this tick moves over: the time since the last tick, but never more than max_tick_interval_s.
  const double dt = first_tick_ ? 1.0 / 10000.0
                                : std::clamp(now - last_tick_s_, 0.0, config_.watchdog.max_tick_interval_s);
  first_tick_ = false;
  last_tick_s_ = now;
  ++counters_.ticks;
  FollowerTickRecord& rec = record_;
  rec.tick = counters_.ticks;
  rec.time_s = now;
  rec.took_setpoint = false;

  // 0. The E-stop level, before anything else: an E-stop engaged since the last tick disables the drives now,
  // whatever waits in the command queues.
  const std::uint64_t estops = link_.EStopsEngaged();
  const bool estop_now = estops != estops_seen_;
  if (estop_now) {
    estops_seen_ = estops;
    ++counters_.estops;
    machine_.OnCommand(StateCommand::kEStop, back_end_);
  }

  // 1. Commands (from every participant, in arrival order). A reset taken in the tick that engaged an E-stop may
  // have been sent before it (the level overtakes the queues): it is refused, the operator resets again.
  StateCommandMessage command;
  while (link_.TakeCommand(command)) {
    ++counters_.commands_taken;
    const bool refused = estop_now && command.command == StateCommand::kReset;
    if (refused || !machine_.OnCommand(command.command, back_end_)) ++counters_.commands_refused;
  }

  // 2. The newest set-point, validated.
  SetPointMessage message;
  std::int64_t arrival_ns = 0;
  if (link_.TakeSetPoint(message, arrival_ns)) {
    ++counters_.setpoints_taken;
    rec.took_setpoint = true;
    const double arrival_s = 1e-9 * static_cast<double>(arrival_ns);
    SetPointSample sample;
    const SetPointVerdict verdict = validator_.CheckMessage(message, arrival_s, now, sample);
    rec.setpoint_verdict = verdict;
    ++counters_.setpoints_by_verdict[static_cast<int>(verdict)];
    if (verdict == SetPointVerdict::kAccepted) {
      ++counters_.setpoints_accepted;
      // Another leader session's poses are relative to its own start: its motion is applied from here.
      if (has_setpoint_ && message.leader_session != setpoint_session_) need_anchor_ = true;
      has_setpoint_ = true;
      setpoint_session_ = message.leader_session;
      setpoint_ = sample;
      setpoint_arrival_s_ = arrival_s;
      setpoint_sequence_ = message.sequence;
      setpoint_stamp_ns_ = message.stamp_ns;
      setpoint_flags_ = message.flags;
      setpoint_hand_energy_j_ = message.hand_energy_in_j;
    } else {
      ++counters_.setpoints_rejected;
    }
  }
  const double age = has_setpoint_ ? now - setpoint_arrival_s_ : 1e300;
  const bool live = has_setpoint_ && age <= config_.watchdog.hold_after_s;
  const bool lost = has_setpoint_ && age > config_.watchdog.leader_lost_after_s;
  if (setpoint_live_ && !live) {
    if (machine_.powered()) ++counters_.watchdog_holds;
    validator_.Reset();  // after the hold, the next valid set-point re-anchors (no rate judged across the gap)
  }
  setpoint_live_ = live;

  // 3. The state machine.
  FollowerInputs inputs;
  inputs.presence = (setpoint_flags_ & kSetPointPresence) != 0;
  inputs.clutched = (setpoint_flags_ & kSetPointClutched) != 0;
  inputs.have_valid_setpoint = live;
  inputs.leader_lost = lost;
  if (recorder_failed_ != nullptr && recorder_failed_->load(std::memory_order_relaxed)) {
    inputs.presence = false;  // unrecorded: hold (decelerate to rest within the caps), never follow again
    inputs.have_valid_setpoint = false;
  }
  const OperatingState before = machine_.state();
  machine_.Update(inputs, back_end_);
  // The leader's device failed (stale, NaN, lost): a latched fault here too, so that recovery needs a reset.
  if (live && (setpoint_flags_ & kSetPointDeviceFault) != 0 && machine_.powered()) {
    machine_.RaiseFault(FaultReason::kDeviceFailure, back_end_);
  }
  if (machine_.state() == OperatingState::kDisabled && before != OperatingState::kDisabled &&
      machine_.reason() == FaultReason::kLeaderLost) {
    ++counters_.leader_lost;
    has_setpoint_ = false;  // a returning leader starts afresh
    validator_.Reset();
  }

  // 4. Motion: follow, or hold; either way within the speed caps and the acceleration caps (the validator's: one
  // place for each limit). Following approaches the wanted pose no faster than it can stop there; holding (the
  // watchdog, no presence, the clutch) decelerates from the commanded velocity to rest at the acceleration cap.
  const transfer::SpeedCaps& caps = config_.setpoint.caps;
  Vector6d step = Vector6d::Zero();
  if (machine_.powered()) {
    Vector6d remaining = Vector6d::Zero();  // holding: the wanted motion is none
    if (machine_.following()) {
      remaining = robot::TwistStepBetween(X_cmd_, WantedPose(now));
    } else {
      need_anchor_ = true;  // resuming re-anchors
    }
    step = CapStepToSpeeds(NextCappedTwist(twist_cmd_, remaining, config_.setpoint, dt) * dt, caps, dt);
  } else {
    need_anchor_ = true;
  }
  step *= BudgetedStepShare(step);
  robot::FeasibleMotionResult guarded;
  if (step.isZero(0.0)) {
    guarded.X_FM = X_cmd_;
    guarded.status = robot::FeasibleMotionStatus::kTracked;
  } else {
    guarded = guard_.Step(X_cmd_, robot::ApplyTwistStep(X_cmd_, step));
    if (guarded.status != robot::FeasibleMotionStatus::kTracked) ++counters_.guard_constrained;
  }
  const Eigen::Isometry3d X_before = X_cmd_;
  const Vector6d moved = robot::TwistStepBetween(X_cmd_, guarded.X_FM);
  if (dt > 0) twist_cmd_ = moved / dt;  // a tick without elapsed time (a clock that did not advance) keeps it
  X_cmd_ = guarded.X_FM;

  // 5. Actuation (eq. 15–17) and the back end. Unpowered, no pulses are made (the drives are off: pulses made now
  // would be counted as motion the motors never did), and the commanded pose and the actuator's joints follow the
  // measured ones, so that powering up again starts from where the robot is, without a jump, however long the
  // drives were off and wherever the robot was pushed meanwhile.
  const actuation::ActuationOutput& out =
      machine_.powered() ? actuator_.Tick(now, X_cmd_, twist_cmd_, config_.watchdog.max_tick_interval_s)
                         : actuator_.output();
  if (machine_.powered() && out.fraction < 1.0) {
    // The motors made only part of the step (a step rate above their maximum, or a joint limit): the commanded pose
    // is the one they reach, the forward kinematics of the actuator's joints, so that it never runs ahead of them.
    // (A fraction of the step in pose space would not do: a step that slides along a curved limit is feasible at
    // its end, not along its chord.) Kept only when inside the limits, else the guarded pose stands.
    const robot::RsrFkResult fk = robot::CalcForwardKinematics(model_, out.command.q, X_cmd_);
    if (fk.converged() && robot::IsPoseFeasible(model_, fk.X_FM)) {
      if (dt > 0) twist_cmd_ = robot::TwistStepBetween(X_before, fk.X_FM) / dt;
      X_cmd_ = fk.X_FM;
    }
  }
  rec.command_time_s = now;
  if (machine_.powered()) {
    back_end_.Command(out.command);
    rec.command_time_s = clock_.NowS();
  }
  back_end_.Service(now);
  const robot::RsrFollowerState measured = back_end_.State();
  const robot::RsrIkResult ik = robot::CalcInverseKinematics(model_, measured.X_FM);
  if (!ik.feasible) ++counters_.limit_violations;
  if (!machine_.powered() && ik.feasible) {
    X_cmd_ = measured.X_FM;
    twist_cmd_.setZero();
    actuator_.Resync(now, measured.q);
  }

  ObserveWrench(measured, dt);

  // 6. Status (decimated) and the record.
  if (now >= next_status_s_) {
    PublishStatus(now, measured);
    const double period = 1.0 / config_.status_rate_hz;
    next_status_s_ = std::max(next_status_s_ + period, now);
  }
  rec.setpoint_sequence = setpoint_sequence_;
  rec.setpoint_stamp_ns = setpoint_stamp_ns_;
  StorePose(setpoint_.X_FM, rec.setpoint_p_FM, rec.setpoint_q_FM);
  StoreVector<6>(setpoint_.twist_F, rec.setpoint_twist_F);
  rec.setpoint_flags = setpoint_flags_;
  StorePose(X_cmd_, rec.cmd_p_FM, rec.cmd_q_FM);
  StoreVector<6>(twist_cmd_, rec.cmd_twist_F);
  StoreVector<6>(out.command.q, rec.cmd_joints);
  rec.meas_time_s = measured.time_s;
  StorePose(measured.X_FM, rec.meas_p_FM, rec.meas_q_FM);
  StoreVector<6>(measured.q, rec.meas_joints);
  StoreVector<6>(measured.effort, rec.effort);
  StoreVector<6>(wrench_F_, rec.wrench_F);
  rec.true_load_known = measured.true_wrench_known;
  StoreVector<6>(measured.true_wrench_F, rec.true_wrench_F);
  rec.port_energy_in_j = port_.energies().in_j;
  rec.port_energy_out_j = port_.energies().out_j;
  rec.port_budgeted = budget_running_;
  rec.meas_min_margin = ik.tightest().margin;
  rec.meas_feasible = ik.feasible;
  rec.state = machine_.state();
  rec.reason = machine_.reason();
  rec.back_end_fault = static_cast<std::uint8_t>(measured.fault);
  rec.guard_status = guarded.status;
  rec.actuation_status = static_cast<std::uint8_t>(out.status);
  rec.holding = !machine_.following();
  if (!records_.TryPush(rec)) {
    ++counters_.records_dropped;
    if (recorder_failed_ != nullptr) recorder_failed_->store(true, std::memory_order_relaxed);  // a lost record
  }
}

void FollowerUnit::ObserveWrench(const robot::RsrFollowerState& measured, double dt) noexcept {
  // Only while following: enabled and not holding (a hold, the clutch, the watchdog): the leader then shows none.
  if (!machine_.following() || measured.faulted()) {
    wrench_F_.setZero();
    wrench_source_ = WrenchSource::kNone;
    return;
  }
  // The estimate (the Jacobian of eq. 15 at the measured pose) changes only with a new measurement: the Bullet plant
  // measures at its 1 kHz physics step, the ticks run at 10 kHz.
  if (wrench_source_ == WrenchSource::kNone || measured.time_s != wrench_meas_time_s_) {
    wrench_F_ = EstimateExternalWrench(model_, measured.X_FM, measured.effort, config_.wrench);
    wrench_meas_time_s_ = measured.time_s;
    wrench_source_ = WrenchSource::kDriveEfforts;
  }
  // The port's energy over the commanded step (the drives are position controlled: the ring moves as commanded).
  // W·dq > 0: the environment pushes the ring along its motion, energy enters the network here.
  port_.Book(wrench_F_, twist_cmd_ * dt);
}

double FollowerUnit::BudgetedStepShare(const Vector6d& step) noexcept {
  const bool budgeted = machine_.following() && (setpoint_flags_ & kSetPointEnergyBudget) != 0 &&
                        std::isfinite(setpoint_hand_energy_j_);
  if (!budgeted) {
    budget_running_ = false;
    return 1.0;
  }
  if (!budget_running_ || budget_session_ != setpoint_session_) {
    // The bound starts now: what the port gave before is not the hand's to pay for.
    budget_running_ = true;
    budget_session_ = setpoint_session_;
    budget_offset_j_ = port_.energies().out_j - setpoint_hand_energy_j_;
  }
  record_.port_budget_j = budget_offset_j_ + setpoint_hand_energy_j_;
  return port_.StepShare(step, wrench_F_, record_.port_budget_j);
}

void FollowerUnit::PublishStatus(double now_s, const robot::RsrFollowerState& measured) noexcept {
  FollowerStatusMessage s;
  s.sequence = ++status_sequence_;
  s.stamp_ns = static_cast<std::int64_t>(std::llround(now_s * 1e9));
  StorePose(measured.X_FM, s.p_FM, s.q_FM);
  StoreVector<6>(measured.q, s.joints);
  StoreVector<6>(measured.effort, s.effort);
  s.state = machine_.state();
  s.fault_reason = machine_.reason();
  s.back_end_fault = static_cast<std::uint8_t>(machine_.back_end_fault());
  s.homed = measured.homed;
  s.setpoints_accepted = counters_.setpoints_accepted;
  s.setpoints_rejected = counters_.setpoints_rejected;
  s.watchdog_holds = counters_.watchdog_holds;
  s.last_sequence = setpoint_sequence_;
  s.limits = limits_;
  StoreVector<6>(wrench_F_, s.wrench_F);
  s.wrench_source = wrench_source_;
  s.port_energy_in_j = port_.energies().in_j;
  s.port_energy_out_j = port_.energies().out_j;
  link_.PublishStatus(s);
  ++counters_.status_published;
}

}  // namespace robossis::teleop
