#include "src/panel/jog_player.h"

#include <cmath>

namespace robossis::panel {
namespace {

using teleop::OperatingState;

bool Powered(OperatingState state) {
  return state == OperatingState::kReady || state == OperatingState::kEnabled || state == OperatingState::kClutched;
}

Eigen::Isometry3d PoseOfStatus(const teleop::FollowerStatusMessage& status) noexcept {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::Quaterniond(status.q_FM[0], status.q_FM[1], status.q_FM[2], status.q_FM[3])
                   .normalized()
                   .toRotationMatrix();
  X.translation() = Eigen::Vector3d(status.p_FM[0], status.p_FM[1], status.p_FM[2]);
  return X;
}

}  // namespace

bool JogPlayer::StartMove(const Eigen::Vector3d& delta_p_F, const Eigen::Vector3d& delta_rot_F,
                          double duration_s) noexcept {
  if (!has_status_ || !synced_ || status_.state != OperatingState::kReady || move_) return false;
  if (!(duration_s >= 0) || !std::isfinite(duration_s)) return false;
  transfer::TimedMoveRequest request;
  request.delta_p_F = delta_p_F;
  request.delta_rot_F = delta_rot_F;
  request.start_time_s = 0;
  path_ticks_ = 0;
  move_.emplace(X_hold_, request, duration_s);  // eq. 9
  return true;
}

void JogPlayer::StopMove() noexcept {
  if (!move_) return;
  X_hold_ = move_->Evaluate(static_cast<double>(path_ticks_) * period_s_).X_FM;  // eq. 9: where the path is now
  move_.reset();
}

void JogPlayer::Tick() noexcept {
  teleop::FollowerStatusMessage status;
  if (link_.TakeFollowerStatus(status)) {
    status_ = status;
    if (!has_status_) X_hold_ = PoseOfStatus(status);
    has_status_ = true;
  }
  if (!has_status_) return;  // the follower has not spoken yet: nothing to hold
  if (!Powered(status_.state)) {
    move_.reset();  // E-stop, fault or disable ended it where the follower stopped
    synced_ = false;
  } else if (!synced_) {
    X_hold_ = PoseOfStatus(status_);
    ++session_;
    synced_ = true;
  }

  const double now = clock_.NowS();
  teleop::SetPointMessage message;
  Eigen::Isometry3d X = X_hold_;
  Vector6d twist = Vector6d::Zero();
  std::uint8_t flags = 0;
  if (move_) {
    const double path_time_s = static_cast<double>(++path_ticks_) * period_s_;
    const transfer::RsrSetPoint set_point = move_->Evaluate(path_time_s);  // eq. 9
    X = set_point.X_FM;
    twist = set_point.velocity;
    flags = teleop::kSetPointPresence;
    if (path_time_s >= move_->end_time_s()) {
      X_hold_ = move_->X_FM_end();
      move_.reset();
    }
  }
  message.sequence = ++sequence_;
  message.leader_session = session_;
  message.stamp_ns = static_cast<std::int64_t>(std::llround(now * 1e9));
  const Eigen::Quaterniond q(X.linear());
  message.p_FM = {X.translation().x(), X.translation().y(), X.translation().z()};
  message.q_FM = {q.w(), q.x(), q.y(), q.z()};
  for (int i = 0; i < 6; ++i) message.twist_F[i] = twist[i];
  message.flags = flags;
  link_.SendSetPoint(message);
  if (flags & teleop::kSetPointPresence) last_presence_s_ = now;
}

}  // namespace robossis::panel
