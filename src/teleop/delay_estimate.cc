#include "src/teleop/delay_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace robossis::teleop {

namespace {

// [assumed] The reference counts as a pure rotation when it moved less than this (m) and turned.
constexpr double kMinLinearRange_m = 1e-3;

struct Prepared {
  std::vector<double> velocity;      // 6 per sample, NaN where no difference within a segment exists
  std::vector<double> speed;         // of the compared part
  std::vector<double> compared;      // its velocity: 3 per sample
  std::vector<std::uint8_t> judged;
  std::vector<std::uint8_t> at_cap;  // the cap bound at this sample
  std::size_t capped = 0;            // samples not judged because the cap bound (at them or shortly before)
};

Prepared Prepare(const DelaySeries& s, std::size_t n, int off, double cap) {
  Prepared p;
  std::vector<double> flat(6 * n);
  for (std::size_t k = 0; k < n; ++k) {
    for (int i = 0; i < 6; ++i) flat[6 * k + static_cast<std::size_t>(i)] = s.x[k][i];
  }
  const std::span<const int> segment = s.segment.size() == n ? s.segment : std::span<const int>{};
  p.velocity = RatesWithinSegments(s.t_s.first(n), flat, 6, segment);
  p.speed.resize(n);
  p.compared.resize(3 * n);
  p.judged.assign(n, 1);
  p.at_cap.assign(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const double* v = &p.velocity[6 * k + static_cast<std::size_t>(off)];
    p.speed[k] = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; ++i) p.compared[3 * k + static_cast<std::size_t>(i)] = v[i];
    const std::uint8_t bit = off == 0 ? kCappedLinear : kCappedAngular;
    const bool capped = (s.capped.size() == n && (s.capped[k] & bit) != 0) || p.speed[k] >= kCapBindsFraction * cap;
    if (capped) {
      p.at_cap[k] = 1;
      p.judged[k] = 0;
      ++p.capped;
    }
  }
  return p;
}

}  // namespace

const char* ToString(DelayStatus status) {
  switch (status) {
    case DelayStatus::kOk: return "ok";
    case DelayStatus::kCapBinds: return "cap_binds";
    case DelayStatus::kTooFewSamples: return "too_few_samples";
    case DelayStatus::kNoOverlap: return "no_overlap";
    case DelayStatus::kNoMotion: return "no_motion";
    case DelayStatus::kNoMatch: return "no_match";
  }
  return "unknown";
}

std::uint8_t HeldBack(const Eigen::Isometry3d& X_transfer, const Eigen::Isometry3d& X_sent) {
  const bool linear = (X_sent.translation() - X_transfer.translation()).norm() > kHeldBackLinear_m;
  const bool angular = RotationAngleBetween(X_transfer.linear(), X_sent.linear()) > kHeldBackAngular_rad;
  return static_cast<std::uint8_t>((linear ? kCappedLinear : 0) | (angular ? kCappedAngular : 0));
}

std::vector<int> RebaseSegments(std::span<const Vector6d> ideal, std::span<const Vector6d> setpoint) {
  std::vector<int> segment(ideal.size(), 0);
  int id = 0;
  for (std::size_t k = 0; k < ideal.size(); ++k) {
    // A zero displacement starts afresh: never differenced with what came before. Either one: the record's ideal
    // displacement is the transfer tick's, so at the tick of a Rebase the set-point is zero before the ideal is.
    if (IsRebased(ideal[k]) || (k < setpoint.size() && IsRebased(setpoint[k]))) ++id;
    segment[k] = id;
  }
  return segment;
}

DelayEstimate EstimateDelay(const DelaySeries& reference, const DelaySeries& setpoint, const DelaySearch& search) {
  DelayEstimate out;
  const std::size_t n_ref = std::min(reference.t_s.size(), reference.x.size());
  const std::size_t n = std::min(setpoint.t_s.size(), setpoint.x.size());
  out.samples = n;
  if (n_ref < 2 || n < 2) return out;
  double lin_range = 0, ang_range = 0;
  for (std::size_t j = 0; j < n_ref; ++j) {
    lin_range = std::max(lin_range, reference.x[j].head<3>().norm());
    ang_range = std::max(ang_range, reference.x[j].tail<3>().norm());
  }
  out.angular = !(lin_range >= kMinLinearRange_m || ang_range == 0);
  const int off = out.angular ? 3 : 0;
  const double cap = out.angular ? search.max_angular_speed_rad_s : search.max_linear_speed_m_s;
  const Prepared ref = Prepare(reference, n_ref, off, cap);
  Prepared set = Prepare(setpoint, n, off, cap);
  // A set-point within cap_settle_s after the cap bound in either series is still catching up: not judged.
  {
    double last_capped = -std::numeric_limits<double>::infinity();
    std::size_t j = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double t = setpoint.t_s[k];
      for (; j < n_ref && reference.t_s[j] <= t; ++j) {
        if (ref.at_cap[j]) last_capped = std::max(last_capped, reference.t_s[j]);
      }
      if (set.at_cap[k]) last_capped = std::max(last_capped, t);
      if (set.judged[k] && t - last_capped <= search.cap_settle_s) {
        set.judged[k] = 0;
        ++set.capped;
      }
    }
  }

  LagSearchOptions options;
  options.min_lag_s = 0;
  options.max_lag_s = search.max_lag_s;
  options.min_overlap_fraction = 0;  // judged by the judged duration below, not by the series' spans
  options.min_correlation = kMinDelayCorrelation;
  options.channels = LagChannels::kVector;  // velocities, so that an overshoot's reversal counts against a lag
  const LagEstimate e =
      EstimateLag({.t_s = reference.t_s.first(n_ref), .values = ref.compared, .channels = 3, .judged = ref.judged},
                  {.t_s = setpoint.t_s.first(n), .values = set.compared, .channels = 3, .judged = set.judged}, options);
  out.correlation = e.correlation;
  out.samples_judged = e.samples_judged;
  const double sample_interval_s = (setpoint.t_s[n - 1] - setpoint.t_s[0]) / static_cast<double>(n - 1);
  LagStatus status = e.status;
  if (status == LagStatus::kOk && static_cast<double>(e.samples_judged) * sample_interval_s < kMinJudgedDuration_s) {
    status = LagStatus::kTooFewSamples;
  }
  if (status == LagStatus::kOk && e.lag_s > search.max_lag_s - kDelayEdgeMargin_s) status = LagStatus::kNoMatch;
  switch (status) {
    case LagStatus::kOk: out.status = DelayStatus::kOk; break;
    case LagStatus::kNoOverlap: out.status = DelayStatus::kNoOverlap; break;
    case LagStatus::kTooFewSamples: out.status = DelayStatus::kTooFewSamples; break;
    case LagStatus::kNoMotion: out.status = DelayStatus::kNoMotion; break;
    case LagStatus::kNoMatch: out.status = DelayStatus::kNoMatch; break;
  }
  // Had the cap not bound, these samples would have been judged: the failure is the cap's.
  if (!out.ok() && out.status != DelayStatus::kNoOverlap && ref.capped + set.capped > 0) {
    out.status = DelayStatus::kCapBinds;
  }
  if (!out.ok()) return out;
  out.delay_s = e.lag_s;

  // The velocity residual at that lag, over the judged set-point samples whose reference is judged and
  // interpolable within one segment.
  double sq = 0;
  std::size_t count = 0;
  const std::span<const double> t_ref = reference.t_s.first(n_ref);
  const bool segmented = reference.segment.size() == n_ref;
  for (std::size_t k = 0; k < n; ++k) {
    if (!set.judged[k] || !std::isfinite(set.speed[k])) continue;
    const double q = setpoint.t_s[k] - out.delay_s;
    const auto it = std::upper_bound(t_ref.begin(), t_ref.end(), q);
    if (it == t_ref.begin() || it == t_ref.end()) continue;
    const std::size_t j1 = static_cast<std::size_t>(it - t_ref.begin()), j0 = j1 - 1;
    if (!ref.judged[j0] || !ref.judged[j1] || (segmented && reference.segment[j0] != reference.segment[j1])) continue;
    const double f = t_ref[j1] > t_ref[j0] ? (q - t_ref[j0]) / (t_ref[j1] - t_ref[j0]) : 0.0;
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
      const std::size_t c = static_cast<std::size_t>(off + i);
      const double v_ref = (1 - f) * ref.velocity[6 * j0 + c] + f * ref.velocity[6 * j1 + c];
      const double d = set.velocity[6 * k + c] - v_ref;
      d2 += d * d;
    }
    if (!std::isfinite(d2)) continue;
    sq += d2;
    ++count;
  }
  out.rms_residual = count ? std::sqrt(sq / static_cast<double>(count)) : 0.0;
  return out;
}

}  // namespace robossis::teleop
