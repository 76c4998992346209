#pragma once
// The motion-transfer pipeline (paper §V, Fig. 8): HC samples → incremental mapping with dynamic scaling (eq. 10–11)
// → rate limiter (releases what a USB stall accumulated, at the caps) → 1→10 kHz linear up-sampling → moving
// average → Kalman filter (eq. 12) → cap guard → RSR set-point (pose, velocity, acceleration) at 10 kHz.
//
// Ruckig-style use: PushHcSample() for every sample that arrives (any thread-free order, any time), TransferTick()
// at 1 kHz, ActuationTick() at 10 kHz. All three are noexcept and allocation-free.

#include <cstdint>

#include <Eigen/Geometry>

#include "haptics/transfer/incremental_mapping.h"
#include "haptics/transfer/set_point.h"
#include "haptics/transfer/signal_filters.h"
#include "haptics/transfer/transfer_config.h"

namespace robossis::transfer {

struct TransferCounters {
  std::uint64_t accepted = 0;
  std::uint64_t anchored = 0;
  std::uint64_t repeated = 0;
  std::uint64_t late = 0;
  std::uint64_t invalid = 0;
  std::uint64_t clutch_open = 0;
  double dropped_backlog_m = 0;    // motion discarded because a stall left more than max_backlog_s waiting
  double dropped_backlog_rad = 0;
};

// What the 1 kHz tick saw, for plots (Fig. 8b) and logs.
struct TransferTickInfo {
  double scale_linear = 1;           // S of eq. 11 of the last accepted sample
  double scale_angular = 1;
  double hc_speed_m_s = 0;
  double hc_angular_speed_rad_s = 0;
  Vector6d goal = Vector6d::Zero();    // incremental trajectory of eq. 10 (displacement from start)
  Vector6d target = Vector6d::Zero();  // after the stall rate limiter (what is up-sampled)
};

class MotionTransfer {
 public:
  // Throws std::invalid_argument if the config is invalid.
  MotionTransfer(const TransferConfig& config, const Eigen::Isometry3d& X_FM_start);

  SampleVerdict PushHcSample(const HcSample& sample) noexcept;
  void SetClutch(bool engaged) noexcept { mapper_.SetClutch(engaged); }
  // Starts over at rest at X_FM (the robot's measured pose, when the robot was not following): the set-point is
  // X_FM, nothing is left in the filters, and the next engaged sample re-anchors. Counters are kept.
  void Rebase(const Eigen::Isometry3d& X_FM) noexcept;
  void TransferTick() noexcept;                 // 1 kHz
  const RsrSetPoint& ActuationTick() noexcept;  // 10 kHz; time advances by one fast period

  const RsrSetPoint& set_point() const { return set_point_; }
  const TransferTickInfo& tick_info() const { return info_; }
  bool predicting() const;  // the Kalman filter is bridging a gap in the HC stream
  const TransferCounters& counters() const { return counters_; }
  const KalmanCa& kalman() const { return kalman_; }
  const TransferConfig& config() const { return config_; }
  double fast_period_s() const { return dt_fast_; }

 private:
  TransferConfig config_;
  double dt_slow_;
  double dt_fast_;
  IncrementalMapper mapper_;
  LinearUpsampler upsampler_;
  MovingAverage moving_average_;
  KalmanCa kalman_;
  CapGuard guard_;
  Vector6d goal_ = Vector6d::Zero();
  Vector6d target_ = Vector6d::Zero();
  TransferTickInfo info_;
  TransferCounters counters_;
  Eigen::Isometry3d X_FM_start_;
  RsrSetPoint set_point_;
  std::uint64_t fast_ticks_ = 0;
  bool fresh_since_tick_ = false;  // an accepted sample since the last transfer tick
  double stale_s_ = 0;             // time since the last transfer tick that had a new sample
};

}  // namespace robossis::transfer
