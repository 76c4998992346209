#pragma once
// The panel's leader side outside haptic mode: it plays the panel's jogs (eq. 9 timed moves) as 1 kHz set-points
// through a teleop::LeaderLink, exactly as a leader unit would, so that the follower unit validates and executes
// them on its one path. It knows the follower only through the link's status messages. (In haptic mode the
// runtime's leader unit sends the set-points instead: local_session_backend.h.)
//
// Like a leader at rest, it sends a set-point every leader tick: the hold pose without the presence flag (the
// follower holds in READY), and the eq. 9 pose with presence while a jog runs (the follower follows in ENABLED).
// The path advances by one set-point period per set-point, not by the clock: a late tick (a loaded machine) lags
// the move by that much instead of jumping along it, because the follower judges each set-point's step against its
// caps over its sequence steps (teleop::SetPointValidator), as it does the leader unit's.
// Stop ends the move where the path is: no more of its set-points are sent and the follower holds. Whenever the follower
// leaves its powered states, a running move is dropped and, once powered again, the player re-synchronises its hold
// pose to the measured pose in a new leader session (so the follower judges no rate across the gap).
//
// Real time: one thread calls every method; Tick() and the orders are allocation-free, lock-free and noexcept.

#include <cstdint>
#include <optional>

#include <Eigen/Geometry>

#include "haptics/transfer/timed_move.h"
#include "src/core/rt/clock.h"
#include "src/teleop/link.h"

namespace robossis::panel {

class JogPlayer {
 public:
  // `period_s`: the time between two Tick()s, the set-point period.
  JogPlayer(teleop::LeaderLink& link, const rt::Clock& clock, double period_s) noexcept
      : link_(link), clock_(clock), period_s_(period_s) {}

  // Starts an eq. 9 move from the hold pose now; false (nothing sent) unless the follower is READY and idle.
  bool StartMove(const Eigen::Vector3d& delta_p_F, const Eigen::Vector3d& delta_rot_F, double duration_s) noexcept;
  // Ends the running move where its path is now (the new hold pose).
  void StopMove() noexcept;

  // Another leader sent the set-points for a while (the panel's haptic mode): the next set-points start from the
  // follower's next status, in a new leader session, with no move running.
  void Resync() noexcept {
    move_.reset();
    has_status_ = false;
    synced_ = false;
  }

  // One leader tick: takes the newest follower status and sends one set-point.
  void Tick() noexcept;

  bool moving() const noexcept { return move_.has_value(); }
  // The shared clock's time of the last set-point sent with presence; < 0 if none yet.
  double last_presence_s() const noexcept { return last_presence_s_; }
  std::uint64_t sent() const noexcept { return sequence_; }

 private:
  teleop::LeaderLink& link_;
  const rt::Clock& clock_;
  const double period_s_;
  bool has_status_ = false;
  teleop::FollowerStatusMessage status_;
  bool synced_ = false;  // the hold pose belongs to the current powered period
  Eigen::Isometry3d X_hold_ = Eigen::Isometry3d::Identity();
  std::optional<transfer::TimedMove> move_;
  std::int64_t path_ticks_ = 0;  // set-points the running move has sent: its time is path_ticks_ × period_s_
  std::uint64_t session_ = 1;
  std::uint64_t sequence_ = 0;
  double last_presence_s_ = -1;
};

}  // namespace robossis::panel
