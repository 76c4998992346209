#include "src/core/lag_estimate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace robossis {

namespace {

// What Correlation() returns when a lag cannot be judged (below any correlation).
constexpr double kNotJudged = -2;

// One series binned on the grid t0 + k·dt: `channels` values per bin (one, the sum of the standardized channels, for
// kSumStandardized; the bin means of each channel for kVector), NaN in a bin that holds no judged sample; `count`
// the judged samples in each bin.
struct Profile {
  double t0 = 0, dt = 0;
  std::size_t channels = 1;
  std::vector<double> v;
  std::vector<std::size_t> count;
  std::size_t valid_bins = 0;
  bool moving = false;  // some channel varies over the judged bins
  double at(std::size_t k, std::size_t c) const { return v[k * channels + c]; }
};

double Span(const LagSeries& s) { return s.t_s.back() - s.t_s.front(); }

bool Judged(const LagSeries& s, std::size_t i) {
  if (!s.judged.empty() && s.judged[i] == 0) return false;
  for (std::size_t c = 0; c < s.channels; ++c) {
    if (!std::isfinite(s.values[i * s.channels + c])) return false;
  }
  return std::isfinite(s.t_s[i]);
}

Profile Bin(const LagSeries& s, double dt, LagChannels mode) {
  // Bin means, not point samples, so that a coarse grid does not alias fast motion.
  Profile p;
  p.t0 = s.t_s.front();
  p.dt = dt;
  const std::size_t n = static_cast<std::size_t>(std::floor(Span(s) / dt));
  const std::size_t m = s.channels;
  std::vector<double> mean_in_bin(n * m, 0.0);
  p.count.assign(n, 0);
  for (std::size_t i = 0; i < s.t_s.size(); ++i) {
    if (!Judged(s, i)) continue;
    const double u = (s.t_s[i] - p.t0) / dt;
    if (!(u >= 0)) continue;
    const std::size_t k = static_cast<std::size_t>(u);
    if (k >= n) continue;
    for (std::size_t c = 0; c < m; ++c) mean_in_bin[k * m + c] += s.values[i * m + c];
    ++p.count[k];
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (p.count[k] == 0) continue;
    ++p.valid_bins;
    for (std::size_t c = 0; c < m; ++c) mean_in_bin[k * m + c] /= static_cast<double>(p.count[k]);
  }
  const double valid = static_cast<double>(std::max<std::size_t>(p.valid_bins, 1));
  std::vector<double> mean(m, 0.0), sd(m, 0.0);
  for (std::size_t c = 0; c < m; ++c) {
    for (std::size_t k = 0; k < n; ++k) {
      if (p.count[k] > 0) mean[c] += mean_in_bin[k * m + c];
    }
    mean[c] /= valid;
    for (std::size_t k = 0; k < n; ++k) {
      if (p.count[k] > 0) sd[c] += (mean_in_bin[k * m + c] - mean[c]) * (mean_in_bin[k * m + c] - mean[c]);
    }
    sd[c] = std::sqrt(sd[c] / valid);
    if (sd[c] > 0) p.moving = true;  // a constant channel carries no timing
  }
  if (mode == LagChannels::kVector) {
    p.channels = m;
    p.v = std::move(mean_in_bin);
  } else {
    // Each channel standardized over the judged bins (so that channels in different units weigh alike), then summed.
    p.channels = 1;
    p.v.assign(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      for (std::size_t c = 0; c < m; ++c) {
        if (p.count[k] > 0 && sd[c] > 0) p.v[k] += (mean_in_bin[k * m + c] - mean[c]) / sd[c];
      }
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (p.count[k] > 0) continue;
    for (std::size_t c = 0; c < p.channels; ++c) p.v[k * p.channels + c] = std::nan("");
  }
  return p;
}

// Normalized correlation of a(t) and b(t − lag) over the bins of `a` where both are judged (b linearly interpolated
// between judged bins), over all channels as one vector; kNotJudged if they cover less than min_overlap_s or fewer
// than min_bins bins, or either is constant there. `samples` gets the judged samples of `a` in the bins compared.
double Correlation(const Profile& a, const Profile& b, double lag_s, double min_overlap_s, std::size_t min_bins,
                   std::size_t* samples = nullptr) {
  const std::size_t m = a.channels;
  std::vector<double> sa(m, 0.0), sb(m, 0.0);
  double saa = 0, sbb = 0, sab = 0;
  std::size_t count = 0, judged = 0;
  const std::size_t nb = b.v.size() / b.channels;
  for (std::size_t k = 0; k < a.v.size() / m; ++k) {
    if (std::isnan(a.at(k, 0))) continue;
    const double t_b = a.t0 + static_cast<double>(k) * a.dt - lag_s;
    const double u = (t_b - b.t0) / b.dt;
    if (u < 0 || u > static_cast<double>(nb) - 1) continue;
    const std::size_t j = static_cast<std::size_t>(u);
    const double f = u - static_cast<double>(j);
    const bool blend = j + 1 < nb && f > 0;
    if (std::isnan(b.at(j, 0)) || (blend && std::isnan(b.at(j + 1, 0)))) continue;
    for (std::size_t c = 0; c < m; ++c) {
      const double vb = blend ? (1 - f) * b.at(j, c) + f * b.at(j + 1, c) : b.at(j, c);
      const double va = a.at(k, c);
      sa[c] += va;
      sb[c] += vb;
      saa += va * va;
      sbb += vb * vb;
      sab += va * vb;
    }
    ++count;
    judged += a.count[k];
  }
  if (samples != nullptr) *samples = judged;
  if (static_cast<double>(count) * a.dt < min_overlap_s || count < min_bins) return kNotJudged;
  const double n = static_cast<double>(count);
  double cov = sab / n, va = saa / n, vb = sbb / n;
  for (std::size_t c = 0; c < m; ++c) {
    cov -= (sa[c] / n) * (sb[c] / n);
    va -= (sa[c] / n) * (sa[c] / n);
    vb -= (sb[c] / n) * (sb[c] / n);
  }
  if (va <= 0 || vb <= 0) return kNotJudged;
  return cov / std::sqrt(va * vb);
}

void Check(const LagSeries& s, const char* name) {
  if (s.channels == 0) throw std::invalid_argument(std::string("EstimateLag: ") + name + " has no channels");
  if (s.values.size() != s.t_s.size() * s.channels) {
    throw std::invalid_argument(std::string("EstimateLag: ") + name + ": values must hold t_s.size() x channels");
  }
  if (!s.judged.empty() && s.judged.size() != s.t_s.size()) {
    throw std::invalid_argument(std::string("EstimateLag: ") + name + ": judged must hold one flag per sample");
  }
}

}  // namespace

const char* ToString(LagStatus status) {
  switch (status) {
    case LagStatus::kOk: return "ok";
    case LagStatus::kTooFewSamples: return "too_few_samples";
    case LagStatus::kNoOverlap: return "no_overlap";
    case LagStatus::kNoMotion: return "no_motion";
    case LagStatus::kNoMatch: return "no_match";
  }
  return "unknown";
}

LagEstimate EstimateLag(const LagSeries& reference, const LagSeries& delayed, const LagSearchOptions& options) {
  Check(reference, "reference");
  Check(delayed, "delayed");
  if (reference.channels != delayed.channels) {
    throw std::invalid_argument("EstimateLag: the series have different channel counts");
  }
  LagEstimate out;
  if (reference.t_s.size() < 2 || delayed.t_s.size() < 2 || !(Span(reference) > 0) || !(Span(delayed) > 0)) {
    return out;  // kTooFewSamples
  }
  const double shorter = std::min(Span(reference), Span(delayed));
  const double min_overlap = options.min_overlap_fraction * shorter;
  // delayed(t) ≈ reference(t − lag): the lags that leave at least min_overlap of common time.
  const double lo = std::max(delayed.t_s.front() - reference.t_s.back() + min_overlap, options.min_lag_s);
  const double hi = std::min(delayed.t_s.back() - reference.t_s.front() - min_overlap, options.max_lag_s);
  if (!(hi >= lo)) {
    out.status = LagStatus::kNoOverlap;
    return out;
  }
  // Coarse-to-fine. Each level bins at dt and tries lags every dt/4 (a peak can fall between bins); the next level
  // bins 10x finer around the best lag. The last level's parabolic peak gives the sub-step lag.
  const double native_dt = std::max(Span(reference) / static_cast<double>(reference.t_s.size() - 1),
                                    Span(delayed) / static_cast<double>(delayed.t_s.size() - 1));
  // [assumed] 200,000 bins over the shorter series at most: the finest level's cost stays bounded on long takes.
  constexpr double kMaxFinestBins = 200000.0;
  const double finest_dt = std::max({2.0 * native_dt, shorter / kMaxFinestBins, options.min_bin_s});
  LagStatus scan_status = LagStatus::kOk;
  // One level: lags in [a, b] every dt/4 on profiles binned at dt.
  auto scan = [&](double dt, double a, double b, std::vector<double>& lags, std::vector<double>& cs) {
    lags.clear();
    cs.clear();
    const Profile pd = Bin(delayed, dt, options.channels);
    const Profile pr = Bin(reference, dt, options.channels);
    if (pd.valid_bins < options.min_bins || pr.valid_bins < options.min_bins) {
      scan_status = LagStatus::kTooFewSamples;
      return false;
    }
    if (!pd.moving || !pr.moving) {
      scan_status = LagStatus::kNoMotion;
      return false;
    }
    const double step = std::max(dt / 4.0, options.finest_step_s);
    for (std::size_t i = 0;; ++i) {
      const double lag = a + static_cast<double>(i) * step;
      if (lag > b + 1e-12) break;
      lags.push_back(lag);
      cs.push_back(Correlation(pd, pr, lag, min_overlap, options.min_bins));
    }
    return !cs.empty();
  };
  auto peak = [](const std::vector<double>& lags, const std::vector<double>& cs, std::size_t k) {
    double best = lags[k];
    if (k > 0 && k + 1 < cs.size() && cs[k - 1] > kNotJudged && cs[k + 1] > kNotJudged) {  // parabolic peak
      const double d = cs[k - 1] - 2 * cs[k] + cs[k + 1];
      if (d < 0) best += 0.5 * (lags[1] - lags[0]) * (cs[k - 1] - cs[k + 1]) / d;
    }
    return best;
  };
  // [assumed] 2000 coarse bins across the searched range: fine enough to see a peak, cheap on long ranges.
  constexpr double kCoarseBinsPerRange = 2000.0;
  const double dt0 = std::max((hi - lo) / kCoarseBinsPerRange, finest_dt);
  std::vector<double> lags, cs;
  if (!scan(dt0, lo, hi, lags, cs)) {
    out.status = scan_status == LagStatus::kOk ? LagStatus::kTooFewSamples : scan_status;
    return out;
  }
  std::vector<std::size_t> maxima;
  for (std::size_t i = 0; i < cs.size(); ++i) {
    const bool left = i == 0 || cs[i] >= cs[i - 1], right = i + 1 == cs.size() || cs[i] >= cs[i + 1];
    if (left && right && cs[i] > kNotJudged) maxima.push_back(i);
  }
  if (maxima.empty()) {
    out.status = LagStatus::kNoMotion;  // no lag compares enough judged, varying bins
    return out;
  }
  std::sort(maxima.begin(), maxima.end(), [&](std::size_t x, std::size_t y) { return cs[x] > cs[y]; });
  maxima.resize(std::min(maxima.size(), std::max<std::size_t>(options.candidates, 1)));
  // Each candidate is refined one level (within the searched range); the best of them down to the finest bins.
  auto refine = [&](double candidate, double dt, double& c_out) {
    const double next = std::max(dt / 10.0, finest_dt);
    std::vector<double> l2, c2;
    if (!scan(next, std::max(candidate - 2 * dt, lo), std::min(candidate + 2 * dt, hi), l2, c2)) return candidate;
    const std::size_t k = static_cast<std::size_t>(std::max_element(c2.begin(), c2.end()) - c2.begin());
    if (c2[k] <= kNotJudged) return candidate;
    c_out = c2[k];
    return peak(l2, c2, k);
  };
  double best = peak(lags, cs, maxima[0]), best_c = cs[maxima[0]];
  double dt = dt0;
  if (dt0 > finest_dt * 1.0001) {
    best_c = kNotJudged - 1;
    for (std::size_t m : maxima) {
      double c = cs[m];
      const double candidate = refine(peak(lags, cs, m), dt0, c);
      if (c > best_c) {
        best = candidate;
        best_c = c;
      }
    }
    dt = std::max(dt0 / 10.0, finest_dt);
  }
  while (dt > finest_dt * 1.0001) {
    best = refine(best, dt, best_c);
    dt = std::max(dt / 10.0, finest_dt);
  }
  out.lag_s = best;
  out.correlation = best_c;
  Correlation(Bin(delayed, finest_dt, options.channels), Bin(reference, finest_dt, options.channels), best, 0, 0,
              &out.samples_judged);
  out.status = best_c >= options.min_correlation ? LagStatus::kOk : LagStatus::kNoMatch;
  return out;
}

std::vector<double> RatesWithinSegments(std::span<const double> t_s, std::span<const double> values,
                                        std::size_t channels, std::span<const int> segment) {
  const std::size_t n = t_s.size();
  if (channels == 0 || values.size() != n * channels || (!segment.empty() && segment.size() != n)) {
    throw std::invalid_argument("RatesWithinSegments: values must hold t_s.size() x channels, segment one per sample");
  }
  auto same = [&](std::size_t i, std::size_t j) { return segment.empty() || segment[i] == segment[j]; };
  std::vector<double> rates(n * channels, std::nan(""));
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t a = j > 0 && same(j - 1, j) ? j - 1 : j;
    const std::size_t b = j + 1 < n && same(j + 1, j) ? j + 1 : j;
    const double span = t_s[b] - t_s[a];
    if (!(span > 0)) continue;
    for (std::size_t c = 0; c < channels; ++c) {
      rates[j * channels + c] = (values[b * channels + c] - values[a * channels + c]) / span;
    }
  }
  return rates;
}

}  // namespace robossis
