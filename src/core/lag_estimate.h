#pragma once
// The project's one lag estimator: how long one sampled signal trails another. The mocap-to-command-log clock
// offset (calibration/time_alignment.h) and the hand-to-set-point delay of the motion transfer
// (src/teleop/delay_estimate.h) are both this search, so that one figure means one thing everywhere.
//
// Both series are rate profiles (speeds or velocity components: rates, not positions, so that a constant offset
// between them does not bias the lag). Each is averaged into bins of width dt, the channels are combined (each
// standardized and summed, or compared as one vector: LagChannels), and the lag maximizing the normalized
// cross-correlation of the two profiles
// is found coarse-to-fine (bins 10x finer around the best candidates at each level), with a parabolic sub-step
// peak. Samples can be excluded (a per-sample flag, or a non-finite value): an excluded sample is never judged,
// and a bin holding only excluded samples drops out of the comparison at every lag. Positions are turned into
// rates by RatesWithinSegments, which never differences across a segment boundary (a reset of the signal).
//
// Not real-time: it allocates.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace robossis {

enum class LagStatus {
  kOk,
  kTooFewSamples,  // fewer judged bins than LagSearchOptions::min_bins in either series
  kNoOverlap,      // no lag of the searched range leaves the series enough overlap
  kNoMotion,       // a series is constant over its judged samples (nothing to align), or no lag compares any
  kNoMatch,        // the best correlation is below LagSearchOptions::min_correlation
};
const char* ToString(LagStatus status);

// One sampled series: `values` holds t_s.size() rows of `channels` values (row-major), at increasing times t_s.
struct LagSeries {
  std::span<const double> t_s;
  std::span<const double> values;
  std::size_t channels = 1;
  // Optional, one per sample: 0 excludes the sample from the comparison. Empty: every finite sample is judged.
  std::span<const std::uint8_t> judged = {};
};

// How several channels make one comparison.
enum class LagChannels {
  // Each channel standardized, then summed into one profile (channels in different units: the calibration's
  // linear and angular speeds).
  kSumStandardized,
  // The channels are the components of one vector (a velocity): the correlation is that of the vectors,
  // sum_c cov_c / sqrt(sum_c var_a_c * sum_c var_b_c), so a reversal counts against a lag, as it should.
  kVector,
};

struct LagSearchOptions {
  LagChannels channels = LagChannels::kSumStandardized;
  // The lags searched: [min_lag_s, max_lag_s], further limited to those where the series overlap by at least
  // min_overlap_fraction of the shorter one's time span (and, at each lag, the judged bins compared must cover
  // that much time).
  double min_lag_s = -std::numeric_limits<double>::infinity();
  double max_lag_s = std::numeric_limits<double>::infinity();
  double min_overlap_fraction = 0.5;
  // The finest lag grid (s); the peak is refined below it by a parabola.
  double finest_step_s = 0.001;
  // The finest bins: never below this, nor below twice the sparser series' mean sample interval (a bin must hold
  // a sample).
  double min_bin_s = 1e-4;
  // Local maxima of the coarse scan refined one level further: with coarse bins the true peak may rank below a
  // near-repeat of a repeated motion.
  std::size_t candidates = 5;
  // Fewer bins than this in either series, or compared at a lag: no estimate (a correlation of fewer points is
  // noise).
  std::size_t min_bins = 8;
  // Below this normalized correlation the profiles are not the same motion: kNoMatch.
  double min_correlation = 0.2;
};

struct LagEstimate {
  LagStatus status = LagStatus::kTooFewSamples;
  double lag_s = 0;           // delayed(t) ≈ reference(t − lag_s)
  double correlation = 0;     // normalized cross-correlation at the peak, in [-1, 1] (also set for kNoMatch)
  std::size_t samples_judged = 0;  // samples of `delayed` in the bins compared at lag_s (finest bins)
  bool ok() const { return status == LagStatus::kOk; }
};

// The lag by which `delayed` trails `reference`: delayed(t) ≈ reference(t − lag). Channels must agree in count.
// Throws std::invalid_argument on malformed input (sizes that disagree, no channels).
LagEstimate EstimateLag(const LagSeries& reference, const LagSeries& delayed, const LagSearchOptions& options = {});

// Rates of `values` (t_s.size() rows of `channels`, row-major) per second at the times t_s: central differences
// inside a segment, one-sided at its ends; never across a change of `segment` (one id per sample; empty: one
// segment). A sample alone in its segment, or whose neighbours share its time, gets NaN (not judged by EstimateLag).
std::vector<double> RatesWithinSegments(std::span<const double> t_s, std::span<const double> values,
                                        std::size_t channels, std::span<const int> segment = {});

}  // namespace robossis
