#pragma once
// The one validated path for every motion command (the teleoperation follower, `robossis move`, `robossis
// transfer`, the panel): a set-point is accepted only if it is finite, fresh, in order, inside the workspace by the
// exact IK (the spherical-joint cones included) and within the speed and acceleration caps, both as it states its
// twist and as its pose moved since the previous accepted set-point. No entry point has another way to the robot.
//
// Real time: Check() and CheckMessage() are allocation-free and noexcept.

#include <array>
#include <cstdint>

#include <Eigen/Geometry>

#include "haptics/transfer/transfer_config.h"
#include "robot/rsr_kinematics.h"
#include "src/teleop/link_messages.h"

namespace robossis::teleop {

// The limits a set-point must meet. The speed caps are the transfer's (transfer.yaml `caps`, eq. 11): one place
// for each limit. The others come from follower.yaml (`setpoint:`), each [assumed] there.
struct SetPointLimits {
  transfer::SpeedCaps caps;
  double max_linear_accel_m_s2 = 5.0;      // [assumed] follower.yaml
  double max_angular_accel_rad_s2 = 10.0;  // [assumed] follower.yaml
  double max_age_s = 0.030;                // [issue: 30 ms] arrival → use
  // Relative slack on the caps for rounding and for the finite difference of two set-points ([assumed]).
  double cap_tolerance = 0.02;
  // The leader's set-point period (1 / transfer.yaml `rates.transfer_rate_hz`): one sequence step is one period of
  // the transfer's motion, however late or early the leader sampled its device.
  double setpoint_period_s = 1e-3;
  // How much shorter than the sequence says the stamps' interval may be ([assumed], follower.yaml): a leader tick
  // that runs late and the next one on time bring two device samples closer than one period.
  double stamp_jitter_s = 1e-3;
  // How much longer than the follower's own clock measured between their arrivals the intervals judged may be
  // ([assumed], follower.yaml): the spread of the link's delay (a set-point delayed and the next on time arrive
  // closer together than they were sent). Per step, and in all since the reference (a credit of the follower's
  // elapsed time that starts at this), so that a leader forging stamps and sequences never buys a faster sustained
  // speed. One set-point period is allowed whatever this says.
  double arrival_allowance_s = 5e-3;
  // Throws std::invalid_argument naming the field.
  void Validate() const;
};

enum class SetPointVerdict : std::uint8_t {
  kAccepted,
  kNotFinite,        // a NaN or infinite field, or a quaternion that is not unit
  kStale,            // older than max_age_s at use
  kOutOfOrder,       // not newer than the last accepted set-point of the same leader session
  kInfeasible,       // outside the workspace (exact IK: strokes, rotary ranges, spherical cones)
  kTooFast,          // the twist or the pose change breaks a speed cap
  kTooAccelerating,  // the twist changed faster than the acceleration cap
};
inline constexpr int kNumSetPointVerdicts = 7;
const char* ToString(SetPointVerdict verdict);

// The twist step [dp; dtheta] shortened to the speed caps over dt (each part along its own direction): how a
// follower moves towards a set-point that is farther than one tick at the caps.
Vector6d CapStepToSpeeds(const Vector6d& step, const transfer::SpeedCaps& caps, double dt) noexcept;

// One set-point in SI: time (s), pose, twist [v; omega] in F.
struct SetPointSample {
  double time_s = 0;
  Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();
  Vector6d twist_F = Vector6d::Zero();
};

// The pose and twist of a link message (no checks).
SetPointSample SampleFromMessage(const SetPointMessage& message) noexcept;

class SetPointValidator {
 public:
  // Validates the limits (throws std::invalid_argument). Keeps a reference to the model.
  SetPointValidator(const robot::RsrModel& model, const SetPointLimits& limits);

  // Checks one set-point against the workspace and the caps, and against the previous accepted one over
  // `interval_s` (<= 0: the two samples' time difference). An accepted set-point becomes the reference for the next.
  SetPointVerdict Check(const SetPointSample& sample, double interval_s = 0) noexcept;

  // A link message: the field checks, freshness (now_s - arrival_s <= max_age_s) and order (sequence within a
  // leader session; a new session starts a new reference), then Check() over the interval since the reference:
  // the sequence steps times the set-point period, but no longer than the stamps' interval plus stamp_jitter_s,
  // nor than the arrivals' interval plus arrival_allowance_s, nor than the follower's time credit (its clock's
  // elapsed time plus arrival_allowance_s, less the intervals already accepted): the leader's stamp and sequence
  // are its word, the arrivals are the follower's, so no forged pair buys a longer step or a faster sustained
  // speed. `sample` receives the converted set-point.
  SetPointVerdict CheckMessage(const SetPointMessage& message, double arrival_s, double now_s,
                               SetPointSample& sample) noexcept;

  // Forget the reference (after a clutch, a hold or a fault the next set-point re-anchors; no rate is judged
  // across the gap).
  void Reset() noexcept {
    has_reference_ = false;
    has_arrival_ = false;
  }

  const SetPointLimits& limits() const noexcept { return limits_; }
  std::uint64_t count(SetPointVerdict verdict) const noexcept { return counts_[static_cast<int>(verdict)]; }
  std::uint64_t rejected() const noexcept;
  // The last check's exact-IK tightest limit (valid after kInfeasible or kAccepted).
  const robot::RsrLimitCheck& tightest() const noexcept { return tightest_; }

 private:
  SetPointVerdict Count(SetPointVerdict v) noexcept {
    ++counts_[static_cast<int>(v)];
    return v;
  }
  const robot::RsrModel& model_;
  SetPointLimits limits_;
  bool has_reference_ = false;
  SetPointSample reference_;
  bool has_sequence_ = false;
  std::uint64_t session_ = 0;
  std::uint64_t sequence_ = 0;
  // The follower's clock (CheckMessage): the reference's arrival, the time credit (s) and the arrival it was last
  // brought up to.
  double reference_arrival_s_ = 0;
  bool has_arrival_ = false;
  double last_arrival_s_ = 0;
  double credit_s_ = 0;
  robot::RsrLimitCheck tightest_{};
  std::array<std::uint64_t, kNumSetPointVerdicts> counts_{};
};

// The first set-point of a path that fails, for the command line's moves. `index` is the sample's position.
struct PathVerdict {
  SetPointVerdict verdict = SetPointVerdict::kAccepted;
  std::size_t index = 0;
  double time_s = 0;
  robot::RsrLimitCheck tightest{};
  bool shorter_than_a_tick = false;  // kTooFast because the move changes the pose within one actuation tick
  bool ok() const noexcept { return verdict == SetPointVerdict::kAccepted; }
};

}  // namespace robossis::teleop
