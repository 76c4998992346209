#pragma once
// The hand-to-set-point delay of the motion transfer, for every caller (the teleoperation summary, the off-line
// chain, the filter-delay benchmark): the lag by which the set-point's velocity trails the velocity of the ideal
// incremental trajectory (the hand through eq. 10–11 alone, before any filter), compared as vectors. The search
// itself is the project's one lag estimator (src/core/lag_estimate.h); this file only says which samples it may
// judge.
//
// - Velocities are taken within a segment only: a reset of the transfer (MotionTransfer::Rebase, while the robot
//   does not follow) returns both displacements to zero, and a difference across it would be a spike that outweighs
//   the whole motion.
// - Samples where the speed cap binds are not judged: when the hand is faster than the cap, eq. 11 holds the
//   ideal's speed at the cap and the set-point's velocity is the clipped one, which no single lag aligns with the
//   hand. What remains is the filters' delay; if too little remains, the status says so (kCapBinds), not a number.
//
// The linear part is compared, unless the reference only turned (then the angular part). Not real-time.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "src/core/lag_estimate.h"
#include "src/core/pose.h"

namespace robossis::teleop {

enum class DelayStatus { kOk, kCapBinds, kTooFewSamples, kNoOverlap, kNoMotion, kNoMatch };
const char* ToString(DelayStatus status);

// [assumed] At least this much judged motion (s) for a delay: a correlation over less than a second of a hand's
// motion (a few strokes at most) is decided by one stroke's edges and wanders from run to run.
inline constexpr double kMinJudgedDuration_s = 1.0;
// [assumed] Below this correlation of the speed profiles the set-point is not a delayed copy of the reference (the
// transfer's filters change the shape little; a lower figure means something else moved the set-point).
inline constexpr double kMinDelayCorrelation = 0.5;
// [assumed] A speed at or above this fraction of the cap counts as capped, in either series: eq. 11 holds the
// reference at the cap's headroom (95 % in transfer.yaml) and the cap guard holds the set-point at the cap while it
// catches up after a filter's overshoot; at such a speed the cap, not the filters, decides where it is.
inline constexpr double kCapBindsFraction = 0.9;

// [assumed] A lag within this of the searched range's end is not a peak (the best alignment may lie beyond it):
// no_match. A transfer whose set-point trails by that much is not following the hand at all.
inline constexpr double kDelayEdgeMargin_s = 0.005;

// After the cap bound (in either series), the set-point is not judged for this long: it may still be catching up on
// the motion the cap held back (the cap guard drives it at the cap, then its filters settle: 0.4 s from 10 mm/s in
// the fast-hand runs at the shipped caps), so its velocity answers to the cap, not to the hand a delay earlier. As
// long as the longest lag searched: a set-point at t may answer to any reference within the searched lags before t.
// (With 0.1–0.3 s the fast hand at the shipped caps still gave a 442 ms "delay", correlation 0.64.)
inline constexpr double kCapSettle_s = 0.5;

struct DelaySearch {
  double max_lag_s = 0.5;  // lags searched: 0 .. max_lag_s
  double cap_settle_s = kCapSettle_s;  // see kCapSettle_s
  // The caps (SI). A sample at or above kCapBindsFraction of a cap is not judged. Infinite: not known.
  double max_linear_speed_m_s = std::numeric_limits<double>::infinity();
  double max_angular_speed_rad_s = std::numeric_limits<double>::infinity();
};

// Bits of DelaySeries::capped: a cap held that part back at the sample (eq. 11 scaled it below 1, or HeldBack). The
// linear and angular caps are separate (eq. 11 scales each part on its own), so only the compared part's bit counts.
inline constexpr std::uint8_t kCappedLinear = 1;
inline constexpr std::uint8_t kCappedAngular = 2;

// [assumed] A set-point sent farther than this from the transfer's set-point was held back by the leader's own bounds
// (its acceleration caps, the motors' top speeds, a wall): there the bound, not the transfer's filters, decides where
// it is, and the transfer's lag is not the hand's lag to the robot. While it follows, the set-point sent trails the
// transfer's by microns (median 6 um and 0.006 deg on a recorded hand); held back, by up to tens of millimetres.
inline constexpr double kHeldBackLinear_m = 1e-4;
inline constexpr double kHeldBackAngular_rad = 1.745e-4;  // 0.01 deg

// The capped bits of a set-point sent at X_sent while the transfer asked for X_transfer: each part held back
// by more than its tolerance.
std::uint8_t HeldBack(const Eigen::Isometry3d& X_transfer, const Eigen::Isometry3d& X_sent);

// One series: displacements [p; theta] at increasing times, with optional per-sample segment ids (velocities are
// never taken across a change) and `capped` bits (kCappedLinear, kCappedAngular).
struct DelaySeries {
  std::span<const double> t_s;
  std::span<const Vector6d> x;
  std::span<const int> segment = {};
  std::span<const std::uint8_t> capped = {};
};

struct DelayEstimate {
  DelayStatus status = DelayStatus::kTooFewSamples;
  double delay_s = 0;            // meaningful only when ok()
  double correlation = 0;        // of the speed profiles at that lag
  double rms_residual = 0;       // the velocity RMS left at that lag over the judged samples (m/s, or rad/s)
  std::size_t samples = 0;       // set-point samples given
  std::size_t samples_judged = 0;
  bool angular = false;          // the angular part was compared (the reference only turned)
  bool ok() const { return status == DelayStatus::kOk; }
  double judged_fraction() const {
    return samples ? static_cast<double>(samples_judged) / static_cast<double>(samples) : 0;
  }
};

// Segment ids of a transfer's displacement series (the ideal and the set-point at the same ticks): a new segment
// wherever either is exactly zero (the transfer was rebased, or has not moved since). A run of such samples is one
// segment each, so they have no velocity and are not judged; the first sample after it is differenced from zero,
// where the transfer restarted.
std::vector<int> RebaseSegments(std::span<const Vector6d> ideal, std::span<const Vector6d> setpoint = {});
inline bool IsRebased(const Vector6d& ideal) { return (ideal.array() == 0).all(); }

// `reference`: the ideal displacement; `setpoint`: the transfer's set-point displacement (the same frame).
DelayEstimate EstimateDelay(const DelaySeries& reference, const DelaySeries& setpoint, const DelaySearch& search = {});

}  // namespace robossis::teleop
