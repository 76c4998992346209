#pragma once
// The whole chain, off-line, for the CLI and the demo: HC trajectory (or an eq. 9 move) → motion transfer at 1 and
// 10 kHz → the one validated path (SetPointValidator, then the feasible-motion guard: no joint limit crossed, the
// spherical cones included) → actuation (Jacobian, eq. 16, pulses) → traces, summary and CSV files.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "haptics/transfer/hc_trajectory.h"
#include "haptics/transfer/motion_transfer.h"
#include "haptics/transfer/timed_move.h"
#include "robot/actuation/actuator.h"
#include "src/teleop/move_validation.h"
#include "robot/feasible_motion.h"
#include "src/teleop/setpoint_validator.h"

namespace robossis::teleop {

struct TransferSummary {
  double max_speed_mm_s = 0;          // max |v| of the set-point (norm)
  double max_angular_speed_deg_s = 0; // max |omega|
  double max_accel_mm_s2 = 0;         // max |a| (linear, norm)
  double max_jerk_mm_s3 = 0;          // max |da/dt| (linear, norm, at 10 kHz)
  double max_angular_accel_deg_s2 = 0;
  double delay_ms = 0;                // lag minimising the RMS between set-point and ideal incremental velocities
  double delay_rms_residual_mm_s = 0; // the velocity RMS left at that lag (mm/s, or deg/s for a pure rotation)
  std::string delay_status = "not_estimated";  // teleop::DelayStatus; delay_ms is 0 unless "ok"
  double steps_error_max = 0;         // max |n - s| over motors and ticks (steps)
  double max_hc_speed_mm_s = 0;       // the hand, for Fig. 8b
  double final_tracking_error_mm = 0; // |set-point - ideal| after settling
  double max_joint_ik_error = 0;      // max |q - IK(x)| over ticks (m or rad, the larger)
  std::array<std::int64_t, 6> steps_total{};  // steps issued (signed) per motor at the end
  std::array<double, 6> steps_commanded{};   // s at the end
  std::size_t num_events = 0;
  std::size_t ticks = 0;
  std::size_t limit_ticks = 0;         // ticks the actuation clamped a joint at its range
  std::size_t guard_limited_ticks = 0; // ticks the feasible-motion guard changed the set-point (at a limit)
  std::size_t setpoints_rejected = 0;  // 10 kHz set-points the validator refused (the follower held instead)
  std::array<std::size_t, kNumSetPointVerdicts> rejected_by_verdict{};
  std::size_t follower_limit_violations = 0;  // ticks whose commanded joints break a limit (exact IK; 0 by design)
  double min_limit_margin = 0;          // the tightest joint-limit margin over the run (m or rad)
  std::string tightest_limit;           // which limit that was ("arm 2 spherical_cone")
  std::size_t rate_limited_ticks = 0;
  transfer::TransferCounters counters;
  double max_step_rate_hz = 0;  // highest per-motor step rate seen (actuation::MaxStepRateHz, 10 ms windows)
};

struct TransferTrace {
  // 10 kHz
  std::vector<double> t;
  std::vector<Vector6d> displacement, velocity, acceleration;
  std::vector<robot::RsrJointVector> q, q_dot;
  std::vector<std::array<std::int64_t, 6>> steps;
  // 1 kHz
  std::vector<double> t_slow;
  std::vector<Vector6d> goal, hc_view;  // eq. 10 goal; the last delivered HC pose (mm/deg) as the controller sees it
  std::vector<double> scale_linear, scale_angular, hc_speed;
  // the ideal incremental trajectory (clean hand, eq. 10–11 only), 1 kHz at hand time
  std::vector<double> t_ref;
  std::vector<Vector6d> ref;
  std::vector<std::uint8_t> ref_capped;  // eq. 11 scaled the clean hand down there (teleop::kCappedLinear, ...)
  std::vector<actuation::StepEvent> events;
  robot::RsrJointVector q_start = robot::RsrJointVector::Zero();
  TransferSummary summary;
};

struct ChainSetup {
  transfer::TransferConfig transfer;
  actuation::ActuationConfig actuation;
  const robot::RsrModel* model = nullptr;
  Eigen::Isometry3d X_FM_start = Eigen::Isometry3d::Identity();
  bool with_actuation = true;  // false: transfer only (the filter sweep)
  double settle_s = 1.0;       // extra time after the last sample
  SetPointLimits limits;       // the validator's limits; its caps are always transfer.caps (one place)
  robot::FeasibleMotionConfig guard;
};

// The chain as configured in a config folder (transfer.yaml, actuation.yaml, follower.yaml), starting at the home
// pose of `model` (which must outlive the setup).
ChainSetup LoadChainSetup(const std::filesystem::path& config_dir, const robot::RsrModel& model);

// ValidateMove (src/teleop/move_validation.h) with the chain's model, follower limits, transfer caps and actuation
// rate.
PathVerdict ValidateMove(const transfer::TimedMove& move, const ChainSetup& setup);
// The shortest duration of `request` that ValidateMove accepts as to speed: the caps at eq. 9's peak speeds, and
// at least one actuation tick (0 for no change).
double MinimumMoveDuration(const transfer::TimedMoveRequest& request, const ChainSetup& setup);

// Replays an HC trajectory through the chain.
TransferTrace RunTransferChain(const transfer::HcTrajectory& hc, const ChainSetup& setup);
// A sequence of eq. 9 moves (each from where the previous ended) through the actuation.
TransferTrace RunMoveChain(const std::vector<transfer::TimedMoveRequest>& moves, const std::vector<double>& durations,
                           const ChainSetup& setup);

// A trace's 10 kHz joint commands played into a follower back end (the Bullet simulation, a driver) through
// robot::Follower, one back-end step of `step_s` at a time (each step gets the newest command issued by then), and
// the pose the back end measures compared with the pose the commanded joints define (FK, warm-started).
struct FollowerReplay {
  double duration_s = 0;
  double max_translation_error_m = 0, mean_translation_error_m = 0;
  double max_rotation_error_rad = 0, mean_rotation_error_rad = 0;
  long steps = 0;
  // Every `csv_every`-th step: t_s, commanded and measured position (mm), the errors (mm, deg).
  std::string csv;
};
// Throws std::runtime_error if the back end becomes unstable or the FK of a command does not converge.
FollowerReplay ReplayOnFollower(const TransferTrace& trace, const robot::RsrModel& model, robot::Follower& follower,
                                const Eigen::Isometry3d& X_FM_start, double step_s, double t_end, int csv_every = 10);

// summary.json: the headline keys first, then the details.
nlohmann::ordered_json SummaryJson(const TransferSummary& s);

// CSV writers (units at the edge: mm, deg).
std::string SetPointsCsv(const TransferTrace& trace, int decimate = 1);
std::string JointsCsv(const TransferTrace& trace, int decimate = 1);
std::string PulsesCsv(const TransferTrace& trace);
std::string SlowTraceCsv(const TransferTrace& trace);
std::string HcRecordsCsv(const transfer::HcTrajectory& hc);

}  // namespace robossis::teleop
