#pragma once
// What a teleoperation run did, computed from the flight recorder's records alone (so that replaying a session log
// reproduces the run's summary exactly): summary.json, leader.csv, follower.csv and the loop-period histograms.
// Fed one record at a time (the logger thread during a run, the log reader in `robossis replay`); not real-time.
// Its memory stays flat however long the run when the caller moves the CSV text out as it goes (MoveCsvTo): every
// other figure is a running one, and the delay estimate keeps at most kMaxDelaySamples set-points.

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "src/core/pose.h"
#include "src/core/rt/loop_stats.h"
#include "src/teleop/delay_estimate.h"
#include "src/teleop/flight_recorder.h"
#include "src/teleop/run_verdict.h"

namespace robossis::teleop {

struct SummaryOptions {
  double leader_rate_hz = 1000;
  double follower_rate_hz = 10000;
  double leader_csv_rate_hz = 1000;   // leader.csv rows (decimated from the loop rate)
  double follower_csv_rate_hz = 200;  // follower.csv rows (>= 100 Hz)
  // The transfer's speed caps (SI), for the hand-to-set-point delay: a set-point at its cap is not judged (the cap,
  // not the filters, decides where it is). Infinite: not known (a log from before the header's meta held them);
  // the records' eq. 11 scales still mark where the hand was faster than the cap.
  double max_linear_speed_m_s = std::numeric_limits<double>::infinity();
  double max_angular_speed_rad_s = std::numeric_limits<double>::infinity();
  // The leader's map of the follower's force into the device frame (f_O = gain·scale·R_FOᵀ·f_F), for the shown load
  // against the follower's true one (FollowerTickRecord::true_wrench_F). Not known: not judged.
  bool feedback_map_known = false;
  double feedback_gain = 0;
  double feedback_translation_scale = 1;
  Eigen::Matrix3d feedback_R_FO = Eigen::Matrix3d::Identity();
};

// The options of a session log's summary from its header's meta (the loop rates, the caps, the feedback map).
// Throws nlohmann::json's exceptions when the loop rates are missing, std::runtime_error on a malformed map.
SummaryOptions SummaryOptionsFromMeta(const nlohmann::json& meta);

// [assumed] The hand-to-set-point delay is estimated over the first this many set-points sent (2^18: 4.4 min at the
// 1 kHz transfer rate, ~28 MB; a power of two, so that the vectors' doubling ends exactly there): the delay is the
// transfer's filters', the same all session long, and minutes of motion judge it as well as hours; kept whole, an
// 8-hour run's series would take ~3 GB.
inline constexpr std::size_t kMaxDelaySamples = std::size_t{1} << 18;

// The position drift: the follower's distance from the path of the set-points it received over the last
// kDriftPathS (the leader's scaled pose as sent: the link's delay is already behind them). A follower that only lags
// its set-points lies on that path, however far behind; one that accumulated an offset (the network form's follower
// bound holding it back, a lost set-point never made up) lies off it by that offset. [assumed] 0.5 s: ten times the
// follower's tracking lag at the speed cap, so the lag never leaves the window; the offset is sampled every
// kDriftEveryS (10 ms), once the path spans the whole window, for its largest value over the run.
inline constexpr double kDriftPathS = 0.5;
inline constexpr double kDriftEveryS = 0.01;

class SessionSummary {
 public:
  explicit SessionSummary(const SummaryOptions& options);

  void AddLeader(const LeaderTickRecord& r);
  void AddFollower(const FollowerTickRecord& r);
  void SetEnd(const SessionEndRecord& end) { end_ = end; has_end_ = true; }

  // The headline keys first (the run's verdict, run_verdict.h), then the details.
  nlohmann::ordered_json Summary() const;
  // Whether the follower followed to the end, and if not, when it stopped and why (not judged without its records).
  RunVerdict Verdict() const { return verdict_.Verdict(has_end_); }
  // The CSV text not yet moved out (all of it, the header first, if MoveCsvTo was never called).
  const std::string& leader_csv() const { return leader_csv_; }
  const std::string& follower_csv() const { return follower_csv_; }
  // Appends the CSV text added since the last call to `leader` and `follower` and forgets it here.
  void MoveCsvTo(std::string& leader, std::string& follower);
  // loop,period_us,count: the start-to-start intervals of each loop (1 µs bins), from the records.
  std::string PeriodsCsv() const;

 private:
  DelayEstimate HandToSetPointDelay() const;
  // The load shown against the follower's true load, N rms (NaN: not known, e.g. hardware or a leader-only log).
  double ShownAgainstTrueForceRms() const;

  SummaryOptions options_;
  // Leader.
  std::uint64_t leader_ticks_ = 0;
  std::int64_t leader_last_ns_ = -1;
  std::map<std::int64_t, std::uint64_t> leader_periods_us_;
  double max_force_n_ = 0;
  double max_torque_nm_ = 0;
  std::uint64_t nonfinite_ = 0;
  std::uint64_t stopped_at_boundary_ = 0;
  int leader_state_ = -1;
  nlohmann::ordered_json leader_transitions_ = nlohmann::ordered_json::array();
  std::vector<double> t_sent_;                     // transfer ticks: for the delay estimate
  std::vector<Vector6d> ideal_, transfer_;
  std::vector<std::uint8_t> capped_;               // eq. 11 scaled the hand down at that tick: kCappedLinear, ...
  std::string leader_csv_;
  int leader_decimation_ = 1;
  double max_hand_speed_m_s_ = 0;
  // Bilateral feedback (feedback_passivity.h): the port's books, the force shown against the load wanted.
  double feedback_energy_j_ = 0;         // out − in at the last tick
  double max_feedback_energy_j_ = 0;     // the largest out − in at any tick
  double feedback_in_j_ = 0;             // the hand gave, over the run
  double max_feedback_force_n_ = 0;
  double feedback_error_sq_sum_ = 0;     // |f shown − f wanted|², over the ticks it was shown
  // The shown load against the follower's true one: the ticks shown (the status stamp in use, the force shown) and
  // the follower's true force (its time, the force) once a millisecond, the first kMaxDelaySamples of each.
  std::vector<std::pair<double, Eigen::Vector3d>> shown_at_stamp_;
  std::vector<std::pair<double, Eigen::Vector3d>> true_force_;
  std::uint64_t feedback_ticks_ = 0;     // ticks the follower's load was shown
  std::uint64_t passivity_active_ticks_ = 0;  // the controller changed the shown wrench beyond its tolerance
  std::uint64_t taper_active_ticks_ = 0;      // its taper alone did
  double min_passivity_observed_j_ = 0;
  double let_go_detected_s_ = -1;        // the first tick the let-go detector fired (-1: never)
  // Follower.
  std::uint64_t follower_ticks_ = 0;
  double follower_last_s_ = -1;
  std::map<std::int64_t, std::uint64_t> follower_periods_us_;
  std::uint64_t limit_violations_ = 0;
  std::uint64_t rate_limited_ticks_ = 0;  // ticks a motor's top step rate shortened (actuation::kRateLimit)
  std::array<std::uint64_t, kNumSetPointVerdicts> rejected_by_verdict_{};  // the set-points the follower refused
  double min_margin_ = 1e9;
  std::vector<std::pair<double, Eigen::Isometry3d>> window_;  // the last 100 measurements (10 ms at 10 kHz): time, pose
  std::size_t window_next_ = 0;
  double max_speed_m_s_ = 0;
  double max_angular_speed_rad_s_ = 0;
  int follower_state_ = -1;
  nlohmann::ordered_json follower_transitions_ = nlohmann::ordered_json::array();
  std::string follower_csv_;
  int follower_decimation_ = 1;
  // The drift (kDriftPathS): the set-points received (time, position) over the last kDriftPathS while enabled, the
  // last measured position, the largest drift sampled.
  double DriftFrom(const Eigen::Vector3d& p) const;
  std::deque<std::pair<double, Eigen::Vector3d>> setpoint_path_;
  std::uint64_t path_sequence_ = 0;
  Eigen::Vector3d last_meas_p_ = Eigen::Vector3d::Zero();
  double next_drift_s_ = 0;
  double max_position_drift_m_ = 0;
  double follower_port_excess_max_j_ = 0;  // the network form's follower bound: out − budget, largest (J)
  RunVerdictCheck verdict_;
  SessionEndRecord end_;
  bool has_end_ = false;
};

}  // namespace robossis::teleop
