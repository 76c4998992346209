#pragma once
// Actuation of the RSR (paper §V-A, eq. 13–17): from the set-point pose and twist at 10 kHz to joint velocities
// (eq. 15, robot::CalcJacobian), joint positions by the Euler-backward integration of eq. 16, and step/direction
// pulses per motor (eq. 17), with the joint limits and the per-motor step-rate limits enforced.
//
// Limits: a tick whose joint step would cross a limit or exceed a motor's step rate is shortened along its own
// direction (all joints together, so the pose stays consistent) to the largest fraction that stays legal; the
// offending joints are flagged, and the robot holds there until a command leads back inside. A command past a
// limit is never issued.

#include <array>
#include <limits>
#include <cstdint>

#include <Eigen/Geometry>

#include "robot/actuation/actuation_config.h"
#include "robot/actuation/pulse_generator.h"
#include "robot/follower.h"
#include "robot/rsr_kinematics.h"

namespace robossis::actuation {

enum class ActuationStatus : std::uint8_t {
  kOk,
  kJointLimit,  // clamped at a joint limit and holding
  kRateLimit,   // shortened by a motor's maximum step rate
  kSingular,    // non-finite Jacobian: holding
};
const char* ToString(ActuationStatus status);

inline constexpr int kMaxStepEventsPerTick = kNumMotors * kMaxStepsPerTickPerMotor;

struct ActuationOutput {
  robot::RsrJointCommand command;                      // q (eq. 16) and q_dot (eq. 15) at this tick
  std::array<std::int64_t, kNumMotors> steps{};        // steps issued per motor since the start
  std::array<double, kNumMotors> step_error{};         // n - s per motor (steps); |.| <= 1/2
  std::array<StepEvent, kMaxStepEventsPerTick> events{};  // this tick's pulses, in motor order
  int num_events = 0;
  ActuationStatus status = ActuationStatus::kOk;
  double fraction = 1;           // the share of this tick's joint step issued (< 1: shortened at a limit or a rate)
  std::uint8_t limit_flags = 0;  // bit i: joint i was clamped at a limit this tick
  std::uint8_t rate_flags = 0;   // bit i: joint i limited the step rate this tick
};

class Actuator {
 public:
  // q_0 = IK(X_FM_start) is the motors' zero. Throws std::invalid_argument if the config is invalid or the start
  // pose is outside the joint limits.
  Actuator(const robot::RsrModel& model, const ActuationConfig& config, const Eigen::Isometry3d& X_FM_start,
           double start_time_s = 0);

  // One 10 kHz tick: the set-point pose and twist [v; omega] (F) at `time_s`. Allocation-free. The tick integrates
  // over the time since the last one (eq. 16), but at most over max_interval_s: after a stalled loop the caller
  // moved the pose by at most that interval's motion, and the joints must move with it, not run ahead by the
  // twist times the whole gap.
  const ActuationOutput& Tick(double time_s, const Eigen::Isometry3d& X_FM, const Vector6d& twist_F,
                              double max_interval_s = std::numeric_limits<double>::infinity()) noexcept;

  // The motors are at the joints `q` (the back end's measurement) at `time_s`, after ticks were skipped (drives
  // off): the next tick starts from there and from that time, and the steps already issued stand for that
  // position, so no burst of pulses makes up a difference the motors never had to travel (the motors' zero moves
  // by it). Allocation-free.
  void Resync(double time_s, const robot::RsrJointVector& q) noexcept;

  const ActuationOutput& output() const { return out_; }
  const robot::RsrJointVector& q() const { return q_; }
  const robot::RsrJointVector& q_start() const { return q0_; }  // the motors' zero (moved by Resync)
  const robot::RsrJointVector& q_min() const { return q_min_; }
  const robot::RsrJointVector& q_max() const { return q_max_; }
  const ActuationConfig& config() const { return config_; }

 private:
  const robot::RsrModel& model_;
  ActuationConfig config_;
  robot::RsrJointVector q0_;
  robot::RsrJointVector q_;
  robot::RsrJointVector q_min_;
  robot::RsrJointVector q_max_;
  std::array<PulseGenerator, kNumMotors> pulses_;
  double time_s_;
  ActuationOutput out_;
};

// Hands the joint set-point to any follower (the Bullet simulation, a real driver). Allocation-free.
inline void CommandFollower(const ActuationOutput& output, robot::Follower& follower) noexcept {
  follower.Command(output.command);
}

}  // namespace robossis::actuation
