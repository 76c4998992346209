#include "src/teleop/leader_unit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "robot/rsr_kinematics.h"
#include "src/core/pose.h"
#include "src/teleop/capped_motion.h"

namespace robossis::teleop {

const char* ToString(LeaderState state) {
  switch (state) {
    case LeaderState::kWaiting: return "waiting";
    case LeaderState::kTracking: return "tracking";
    case LeaderState::kDeviceFault: return "device_fault";
    case LeaderState::kEnded: return "ended";
  }
  return "unknown";
}

void PoseToArrays(const Eigen::Isometry3d& X, std::array<double, 3>& p, std::array<double, 4>& q) noexcept {
  const Eigen::Quaterniond quat(X.linear());
  for (int i = 0; i < 3; ++i) p[i] = X.translation()[i];
  q = {quat.w(), quat.x(), quat.y(), quat.z()};
}

Eigen::Isometry3d PoseFromArrays(const std::array<double, 3>& p, const std::array<double, 4>& q) noexcept {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
  X.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
  return X;
}

namespace {

void ToArray(const Eigen::Vector3d& v, std::array<double, 3>& a) noexcept {
  for (int i = 0; i < 3; ++i) a[i] = v[i];
}

// The pose a fraction s of the way from A to B: position on the line, orientation on the geodesic.
Eigen::Isometry3d Interpolate(const Eigen::Isometry3d& A, const Eigen::Isometry3d& B, double s) noexcept {
  Eigen::Isometry3d X = A;
  X.translation() = (1 - s) * A.translation() + s * B.translation();
  X.linear() = RotationFromVector(s * RotationVector(B.linear() * A.linear().transpose())) * A.linear();
  return X;
}

}  // namespace

LeaderUnit::LeaderUnit(const LeaderConfig& config, const transfer::TransferConfig& transfer,
                       const robot::RsrModel& model, haptics::HapticDevice& device,
                       haptics::HapticRenderer& renderer, LeaderLink& link, const Eigen::Isometry3d& X_FM_start,
                       std::uint64_t session_id)
    : config_(config),
      model_(model),
      device_(device),
      renderer_(renderer),
      link_(link),
      guard_(model, config.guard),
      transfer_(transfer, X_FM_start),
      frame_(transfer.mapping.frame()),
      transfer_every_(static_cast<int>(std::lround(config.rate_hz / transfer.rates.transfer_rate_hz))),
      setpoint_period_s_(1.0 / transfer.rates.transfer_rate_hz),
      actuation_ratio_(transfer.rates.upsampling_ratio()),
      session_id_(session_id),
      X_goal_(X_FM_start),
      X_sent_(OnTheWire(X_FM_start)),
      passivity_(config.feedback.passivity),
      let_go_(config.feedback.let_go),
      records_(config.record_queue_capacity) {
  config.Validate();
  follower_limits_.caps = transfer.caps;
  follower_limits_.max_linear_accel_m_s2 = config.max_linear_accel_m_s2;
  follower_limits_.max_angular_accel_rad_s2 = config.max_angular_accel_rad_s2;
  motor_speeds_ = config.motor_speed_share * config.max_joint_speed;
  if (transfer_every_ < 1 ||
      std::abs(transfer_every_ * transfer.rates.transfer_rate_hz - config.rate_hz) > 1e-6 * config.rate_hz) {
    throw std::invalid_argument("leader: rate_hz " + std::to_string(config.rate_hz) +
                                " must be a multiple of the transfer rate " +
                                std::to_string(transfer.rates.transfer_rate_hz) + " Hz");
  }
  if (std::abs(renderer.dt() * config.rate_hz - 1.0) > 1e-9) {
    throw std::invalid_argument("leader: the renderer runs at " + std::to_string(1.0 / renderer.dt()) +
                                " Hz, the leader at " + std::to_string(config.rate_hz) + " Hz");
  }
  if (!FeasibleOnTheWire(X_FM_start)) {
    throw std::invalid_argument("leader: the follower's start pose is outside the workspace");
  }
  follower_.state = OperatingState::kDisabled;
  // The walls map the hand's velocities and rotate their wrench back with the transfer's frame map, whatever map
  // the renderer was built with: one mapping for the set-points and the walls.
  try {
    frame_.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("leader: transfer ") + e.what());
  }
  haptics::HcToRsrMap map = renderer.map();
  map.frame = frame_;
  renderer.SetMap(map);
}

Eigen::Isometry3d LeaderUnit::OnTheWire(const Eigen::Isometry3d& X) noexcept {
  std::array<double, 3> p;
  std::array<double, 4> q;
  PoseToArrays(X, p, q);
  return PoseFromArrays(p, q);
}

bool LeaderUnit::FeasibleOnTheWire(const Eigen::Isometry3d& X) const noexcept {
  return robot::IsPoseFeasible(model_, OnTheWire(X));
}

Eigen::Isometry3d LeaderUnit::FeasibleToward(const Eigen::Isometry3d& goal, bool& stopped) noexcept {
  stopped = false;
  if (FeasibleOnTheWire(goal)) return OnTheWire(goal);
  stopped = true;
  // X_sent_ is feasible as sent; the boundary lies between it and the goal. Every probe is judged as the follower
  // will receive it (quaternion round trip), so a pose exactly on the boundary is not pushed out by rounding.
  double lo = 0, hi = 1;
  for (int k = 0; k < config_.boundary_bisection_steps; ++k) {
    const double mid = 0.5 * (lo + hi);
    (FeasibleOnTheWire(Interpolate(X_sent_, goal, mid)) ? lo : hi) = mid;
  }
  return OnTheWire(Interpolate(X_sent_, goal, lo));
}

void LeaderUnit::AnchorWalls(const Eigen::Isometry3d& X_OH) noexcept {
  // The walls' own map (used only to place a proxy or a cloud at reset): the hand now ↔ the set-point now.
  haptics::HcToRsrMap map;
  map.X_OH_anchor = X_OH;
  map.X_FM_anchor = X_sent_;
  map.frame = frame_;
  renderer_.SetMap(map);
  renderer_.Reset(X_OH);
}

void LeaderUnit::FollowTheMeasuredRobot(bool status_fresh) noexcept {
  // While the robot does not follow, the set-point, the walls and the motion transfer stay with the robot as it
  // was last measured (the leader no longer renders motion it does not make), so that nothing jumps when it
  // follows again, wherever it was left: a hold, a fault, a restart of either unit.
  if (status_fresh) {
    const Eigen::Isometry3d X = OnTheWire(PoseFromArrays(follower_.p_FM, follower_.q_FM));
    // There within the follower's caps, as every set-point: the robot may have stopped short of the last one.
    if (X.matrix().allFinite() && FeasibleOnTheWire(X)) X_sent_ = WithinFollowerCaps(X);
  }
  X_goal_ = X_sent_;
  transfer_.Rebase(X_sent_);
}

bool LeaderUnit::StopsInside(const Eigen::Isometry3d& X, const Vector6d& twist) const noexcept {
  // Braking at the acceleration caps from `twist`, each part (linear, angular) covers |v|^2 / (2 a) along its
  // direction. The path is checked at its middle and its end.
  Vector6d stop;
  stop.head<3>() = twist.head<3>() * (0.5 * twist.head<3>().norm() / follower_limits_.max_linear_accel_m_s2);
  stop.tail<3>() = twist.tail<3>() * (0.5 * twist.tail<3>().norm() / follower_limits_.max_angular_accel_rad_s2);
  return FeasibleOnTheWire(robot::ApplyTwistStep(X, 0.5 * stop)) && FeasibleOnTheWire(robot::ApplyTwistStep(X, stop));
}

Eigen::Isometry3d LeaderUnit::WithinFollowerCaps(const Eigen::Isometry3d& target) noexcept {
  const double T = setpoint_period_s_;
  const Matrix6d motor_rows = MotorRows(model_, X_sent_, motor_speeds_);
  Vector6d twist =
      NextCappedTwist(twist_sent_, robot::TwistStepBetween(X_sent_, target), follower_limits_, T, motor_rows);
  Eigen::Isometry3d X = OnTheWire(robot::ApplyTwistStep(X_sent_, twist * T));
  if (!StopsInside(X, twist)) {
    // From there the set-point could not stop before a limit: brake instead, on along the last set-point's own
    // stopping path (checked when it was sent).
    twist = NextCappedTwist(twist_sent_, Vector6d::Zero(), follower_limits_, T);
    X = OnTheWire(robot::ApplyTwistStep(X_sent_, twist * T));
  }
  // Should that path still cross a boundary between its checked points, the feasible-motion guard slides along the
  // active limits (a dead stop at the boundary would break the acceleration caps).
  bool stopped = false;
  if (!FeasibleOnTheWire(X)) {
    X = FeasibleToward(guard_.Step(X_sent_, X).X_FM, stopped);
    // The guard's slide turns the motion: within the acceleration caps where that turn is still feasible.
    const Vector6d slid =
        NextCappedTwist(twist_sent_, robot::TwistStepBetween(X_sent_, X), follower_limits_, T, motor_rows);
    const Eigen::Isometry3d X_slid = OnTheWire(robot::ApplyTwistStep(X_sent_, slid * T));
    if (FeasibleOnTheWire(X_slid)) X = X_slid;
  }
  twist_sent_ = robot::TwistStepBetween(X_sent_, X) / T;
  return X;
}

void LeaderUnit::SendSetPoint(std::int64_t sample_ns) noexcept {
  SetPointMessage m;
  m.sequence = ++sequence_;
  m.leader_session = session_id_;
  m.stamp_ns = sample_ns;
  PoseToArrays(X_sent_, m.p_FM, m.q_FM);
  for (int i = 0; i < 6; ++i) m.twist_F[i] = twist_sent_[i];
  std::uint8_t flags = 0;
  if (state_ == LeaderState::kTracking) flags |= kSetPointPresence;
  if (state_ != LeaderState::kTracking || clutched_) flags |= kSetPointClutched;
  if (state_ == LeaderState::kDeviceFault) flags |= kSetPointDeviceFault;
  // The network form's follower half: the hand's input, on the follower port's scale (a gain of zero shows nothing
  // and asks nothing of the hand: no bound).
  const LeaderFeedbackConfig& fb = config_.feedback;
  if (fb.mode == FeedbackMode::kBilateral && fb.passivity.scheme == FeedbackPassivityScheme::kNetwork && fb.gain > 0) {
    flags |= kSetPointEnergyBudget;
    m.hand_energy_in_j = counters_.feedback_energy_in_j / fb.gain;
  }
  m.flags = flags;
  last_flags_ = flags;
  link_.SendSetPoint(m);
  ++counters_.setpoints_sent;
}

Vector6d LeaderUnit::FeedbackWrench(bool shown) const noexcept {
  Vector6d w = Vector6d::Zero();
  if (!shown) return w;
  Eigen::Vector3d f_F, tau_F;
  for (int i = 0; i < 3; ++i) {
    f_F[i] = follower_.wrench_F[i];
    tau_F[i] = follower_.wrench_F[3 + i];
  }
  if (!f_F.allFinite() || !tau_F.allFinite()) return w;  // a corrupt status shows nothing
  // The transfer's map inverted as energy requires: v_F = s·R_FO·v_O, so f_O = s·R_FOᵀ·f_F keeps f_O·v_O = f_F·v_F.
  const double g = config_.feedback.gain;
  w.head<3>() = g * frame_.translation_scale * frame_.WrenchToHc(f_F);
  w.tail<3>() = g * frame_.rotation_scale * frame_.WrenchToHc(tau_F);
  return w;
}

void LeaderUnit::Tick(std::int64_t now_ns) noexcept {
  const double now_s = 1e-9 * static_cast<double>(now_ns);
  if (reset_requested_.exchange(false, std::memory_order_acq_rel) && state_ == LeaderState::kDeviceFault) {
    state_ = LeaderState::kWaiting;
  }
  const haptics::DeviceState& s = device_.Read(now_s);
  FollowerStatusMessage status;
  if (link_.TakeFollowerStatus(status)) {
    follower_ = status;
    follower_heard_ = true;
    last_status_ns_ = now_ns;
    statuses_received_.fetch_add(1, std::memory_order_relaxed);
  }
  // The robot follows (enabled, or clutched by this leader's own flags) on a fresh status. A leader that has never
  // heard a follower (a bench without one) renders and sends as if it did.
  const bool status_fresh = follower_heard_ && static_cast<double>(now_ns - last_status_ns_) <=
                                                   1e9 * config_.follower_status_timeout_s;
  const bool robot_following =
      !follower_heard_ || (status_fresh && (follower_.state == OperatingState::kEnabled ||
                                            follower_.state == OperatingState::kClutched));
  if (!started_ && s.ok()) {
    AnchorWalls(s.X_OH);
    started_ = true;
  }

  // State: a failure latches; otherwise presence decides.
  const bool failure = !s.ok() && s.status != haptics::DeviceStatus::kEndOfScript;
  if (failure) {
    if (state_ != LeaderState::kDeviceFault) {
      // The hand's device no longer says where the hand is: the robot is E-stopped, not only held (a hold needs
      // the set-point stream, which a failing leader may not keep up). The follower leaves it by a reset only.
      ++counters_.device_failures;
      link_.SendEStop();
    }
    state_ = LeaderState::kDeviceFault;
  } else if (state_ != LeaderState::kDeviceFault) {
    if (s.status == haptics::DeviceStatus::kEndOfScript) state_ = LeaderState::kEnded;
    else state_ = s.presence() ? LeaderState::kTracking : LeaderState::kWaiting;
  }
  clutched_ = state_ == LeaderState::kTracking && operator_clutch_.load(std::memory_order_acquire);
  const bool tracking = state_ == LeaderState::kTracking && !clutched_ && robot_following;
  if (robot_following && !robot_was_following_) AnchorWalls(s.X_OH);  // resuming from the measured robot
  robot_was_following_ = robot_following;
  if (tracking != clutch_engaged_) {
    transfer_.SetClutch(tracking);  // engaging re-anchors on the next sample: no jump after a clutch or a fault
    clutch_engaged_ = tracking;
  }

  // Motion transfer (eq. 10–12) at its own rate: the pose the hand asks for.
  const bool transfer_tick = counters_.ticks % static_cast<std::uint64_t>(transfer_every_) == 0;
  if (transfer_tick) {
    if (tracking) {
      transfer::HcSample sample;
      sample.time_s = s.time_s;
      sample.p_OH = s.X_OH.translation();
      sample.R_OH = s.X_OH.linear();
      transfer_.PushHcSample(sample);
    }
    transfer_.TransferTick();
    for (int k = 0; k < actuation_ratio_; ++k) transfer_.ActuationTick();
    X_goal_ = transfer_.set_point().X_FM;
  }

  // Rendering at that pose; the renderer maps the hand's velocities into F and its wrench back into O through the
  // frame map set above.
  haptics::HapticOutput out;
  if (started_) {
    haptics::HapticInput in;
    in.X_OH = s.X_OH;
    in.v_O = s.v_O;
    in.w_O = s.w_O;
    renderer_.TickRsr(X_goal_, in, out);
    if (out.status == haptics::HapticStatus::kFault && s.ok()) ++counters_.nonfinite_outputs;
  }
  haptics::DeviceCommand command;
  if (tracking) {
    command.f_O = out.f_O;
    command.tau_O = out.tau_O;
  }
  // The follower's load: shown only while it follows (enabled; its wrench says it is not holding) on a fresh status
  // and this leader tracks. The port's books start over whenever it is shown again.
  const bool bilateral = config_.feedback.mode == FeedbackMode::kBilateral;
  const bool shown = bilateral && tracking && follower_heard_ && status_fresh &&
                     follower_.state == OperatingState::kEnabled && follower_.wrench_source != WrenchSource::kNone;
  Vector6d feedback_shown = Vector6d::Zero();
  // The let-go detector: the force written at the last tick moved the device from the velocity read then to this
  // one; it judges only while the load was shown (the leader's own motion, not the walls, is the question), and
  // forgets a let-go once the operator's presence or clutch is taken anew.
  if (!tracking) {
    let_go_.Reset();
  } else if (config_.feedback.detect_let_go && feedback_shown_ && shown && s.ok()) {
    let_go_.Update(f_written_, v_read_, s.v_O, 1.0 / config_.rate_hz, passivity_.damping());
  }
  Vector6d feedback_wanted = FeedbackWrench(shown);
  if (shown && let_go_.let_go()) {
    feedback_wanted << -config_.feedback.let_go.rest_damping_n_s_per_m * s.v_O, Eigen::Vector3d::Zero();
  }
  Vector6d twist;
  twist << s.v_O, s.w_O;
  const bool port_runs = bilateral && tracking && s.ok();
  double remote_in = 0;
  if (port_runs) {
    if (shown && !feedback_shown_) {
      passivity_.Reset();
      remote_in_base_j_ = follower_.port_energy_in_j;
    }
    Vector6d wall;
    wall << command.f_O, command.tau_O;
    remote_in = config_.feedback.gain * (follower_.port_energy_in_j - remote_in_base_j_);
    if (!std::isfinite(remote_in)) remote_in = 0;
    const CappedWrench c = passivity_.Apply(wall, feedback_wanted, twist, 1.0 / config_.rate_hz,
                                            config_.feedback.max_force_n, config_.feedback.max_torque_nm, remote_in);
    command.f_O = c.displayed.head<3>();
    command.tau_O = c.displayed.tail<3>();
    feedback_shown = c.feedback;
    if (passivity_.active()) ++counters_.passivity_active_ticks;
    if (passivity_.taper_active()) ++counters_.taper_active_ticks;
  }
  feedback_shown_ = shown;
  const haptics::DeviceWriteReport written = device_.Write(command);
  const Eigen::Vector3d f_sent =
      written.zeroed ? Eigen::Vector3d::Zero() : CapNorm(command.f_O, device_.limits().max_force_n);
  const Eigen::Vector3d tau_sent =
      written.zeroed ? Eigen::Vector3d::Zero() : CapNorm(command.tau_O, device_.limits().max_torque_nm);
  counters_.max_force_n = std::max(counters_.max_force_n, f_sent.norm());
  counters_.max_torque_nm = std::max(counters_.max_torque_nm, tau_sent.norm());
  // The feedback part of what the device actually displays: none when it zeroed its output, and scaled with the
  // whole wrench where its own caps cut it further (HapticDevice keeps the direction).
  if (written.zeroed) {
    feedback_shown.setZero();
  } else {
    const double f_cmd = command.f_O.norm(), tau_cmd = command.tau_O.norm();
    if (f_cmd > 0) feedback_shown.head<3>() *= f_sent.norm() / f_cmd;
    if (tau_cmd > 0) feedback_shown.tail<3>() *= tau_sent.norm() / tau_cmd;
  }
  if (port_runs) {
    // The observer books the force the hand was actually shown over this tick (a device that zeroed its output
    // gave the hand nothing, whatever the controller was asked to show); the run's books add its samples up.
    const FeedbackPortEnergies tick = passivity_.Observe(feedback_shown, twist, 1.0 / config_.rate_hz, remote_in);
    counters_.feedback_energy_in_j += tick.in_j;
    counters_.feedback_energy_out_j += tick.out_j;
    counters_.max_feedback_energy_j = std::max(counters_.max_feedback_energy_j,
                                               counters_.feedback_energy_out_j - counters_.feedback_energy_in_j);
  }
  f_written_ = f_sent;
  v_read_ = s.v_O;
  counters_.max_feedback_force_n = std::max(counters_.max_feedback_force_n, feedback_shown.head<3>().norm());

  // The feasible set-point, sent at the transfer rate.
  bool stopped = false;
  if (transfer_tick && !robot_following) {
    FollowTheMeasuredRobot(status_fresh);
    SendSetPoint(static_cast<std::int64_t>(std::llround(s.time_s * 1e9)));
  } else if (transfer_tick) {
    Eigen::Isometry3d X = X_sent_;
    if (started_) {
      if (const Eigen::Isometry3d* proxy = renderer_.constrained_pose(); proxy != nullptr) {
        // The god-object: always on or inside the true boundary (toward it from the last set-point if the
        // rounding of the message would put it a hair outside).
        bool rounded = false;
        X = FeasibleToward(*proxy, rounded);
        stopped = (X.translation() - X_goal_.translation()).norm() > 1e-9 ||
                  RotationAngleBetween(X.linear(), X_goal_.linear()) > 1e-9;
      } else {
        // The feasible-motion guard: the constrained least-squares step toward the goal (robot/feasible_motion.h),
        // sliding along the active limits; the bisection only if the message's rounding puts it a hair outside.
        const robot::FeasibleMotionResult g = guard_.Step(X_sent_, X_goal_);
        stopped = g.status != robot::FeasibleMotionStatus::kTracked;
        bool rounded = false;
        X = FeasibleToward(g.X_FM, rounded);
      }
    }
    if (!X.matrix().allFinite()) {
      ++counters_.nonfinite_outputs;
      X = X_sent_;
    }
    if (!FeasibleOnTheWire(X)) {  // the exact IK, on the pose as it is sent
      ++counters_.ik_rejected;
      X = X_sent_;
    }
    if (stopped) ++counters_.stopped_at_boundary;
    X_sent_ = WithinFollowerCaps(X);
    SendSetPoint(static_cast<std::int64_t>(std::llround(s.time_s * 1e9)));
  }

  // The record.
  LeaderTickRecord& r = record_;
  r.t_ns = now_ns;
  r.sample_ns = static_cast<std::int64_t>(std::llround(s.time_s * 1e9));
  r.tick = counters_.ticks;
  PoseToArrays(s.X_OH, r.p_OH, r.q_OH);
  ToArray(s.v_O, r.v_O);
  ToArray(s.w_O, r.w_O);
  ToArray(f_sent, r.f_O);
  ToArray(tau_sent, r.tau_O);
  PoseToArrays(X_goal_, r.p_goal, r.q_goal);
  PoseToArrays(X_sent_, r.p_sent, r.q_sent);
  r.p_follower = follower_.p_FM;
  r.q_follower = follower_.q_FM;
  for (int i = 0; i < 6; ++i) {
    r.ideal_disp[i] = transfer_.tick_info().goal[i];
    r.transfer_disp[i] = transfer_.set_point().displacement[i];
  }
  r.scale_linear = transfer_.tick_info().scale_linear;
  r.scale_angular = transfer_.tick_info().scale_angular;
  r.hc_speed_m_s = transfer_.tick_info().hc_speed_m_s;
  r.sequence = sequence_;
  r.buttons = s.buttons;
  r.device_status = static_cast<std::uint8_t>(s.status);
  r.haptic_status = static_cast<std::uint8_t>(out.status);
  r.leader_state = static_cast<std::uint8_t>(state_);
  r.follower_state = static_cast<std::uint8_t>(follower_.state);
  r.flags = last_flags_;
  r.sent_this_tick = transfer_tick ? 1 : 0;
  r.stopped_at_boundary = stopped ? 1 : 0;
  r.force_zeroed = written.zeroed ? 1 : 0;
  r.follower_wrench_F = follower_.wrench_F;
  for (int i = 0; i < 6; ++i) {
    r.feedback_wanted_O[i] = feedback_wanted[i];
    r.feedback_O[i] = feedback_shown[i];
  }
  r.feedback_shown = shown ? 1 : 0;
  r.let_go = let_go_.let_go() ? 1 : 0;
  r.follower_stamp_ns = follower_.stamp_ns;
  r.feedback_energy_in_j = counters_.feedback_energy_in_j;
  r.feedback_energy_out_j = counters_.feedback_energy_out_j;
  r.passivity_observed_j = passivity_.observed_j();
  r.passivity_active = passivity_.active() ? 1 : 0;
  r.taper_active = passivity_.taper_active() ? 1 : 0;
  if (!records_.TryPush(r)) ++counters_.records_dropped;
  latest_.Publish(r);
  ++counters_.ticks;
}

}  // namespace robossis::teleop
