// Atlas and slice errors against the reference signed distance.

#include "geometry/atlas_error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>

#include "src/core/units.h"

namespace robossis::geometry {

namespace {

ReferenceDistanceOptions ReferenceOptionsFor(SliceKind kind) {
  ReferenceDistanceOptions o;
  o.directions = 400;
  if (IsAngularSlice(kind)) {
    o.max_distance = DegToRad(25);
    o.march_step = DegToRad(0.25);
    o.tolerance = 1e-7;
  } else {
    o.max_distance = 0.06;
    o.march_step = 5e-4;
    o.tolerance = 1e-8;
  }
  return o;
}

// One sample: a point near the slice's mesh, compared with the reference of `truth`.
void Sample(const BoundaryDistanceField& field, const SliceFeasibility& truth, double offset, std::mt19937& gen,
            SignedDistanceQuery& query, std::vector<double>& errors, int& not_found, int& sign_errors) {
  std::uniform_int_distribution<std::size_t> pick(0, field.mesh().vertices.size() - 1);
  std::uniform_real_distribution<double> u(-offset, offset);
  const Eigen::Vector3d q = field.mesh().vertices[pick(gen)] + Eigen::Vector3d(u(gen), u(gen), u(gen));
  SignedDistanceResult r;
  query.Query(&field, q, 0.0, &r);
  const ReferenceDistanceResult ref = ComputeReferenceSignedDistance(
      [&truth](const Eigen::Vector3d& x) { return truth(x); }, q, ReferenceOptionsFor(truth.kind()));
  if (!ref.found) {
    ++not_found;
    return;
  }
  if ((r.signed_distance > 0) != (ref.signed_distance > 0) && std::abs(ref.signed_distance) > 0) ++sign_errors;
  errors.push_back(std::abs(r.signed_distance - ref.signed_distance));
}

double Uniform(std::mt19937& gen, const GridAxis& a, bool on_grid) {
  if (on_grid) return a.min + a.step * std::uniform_int_distribution<int>(0, a.count - 1)(gen);
  return std::uniform_real_distribution<double>(a.min, a.max())(gen);
}

}  // namespace

int RequireErrorSamples(double samples, const std::string& option) {
  if (!(samples >= 0 && samples <= kMaxErrorSamples) || samples != std::floor(samples)) {
    char got[32];
    std::snprintf(got, sizeof got, "%g", samples);
    throw std::invalid_argument(option + ": expected an integer from 0 to " + std::to_string(kMaxErrorSamples) +
                                " samples, got " + got);
  }
  return static_cast<int>(samples);
}

ErrorStats SummariseErrors(std::vector<double> e, int not_found, int sign_disagreements) {
  ErrorStats s;
  s.samples = static_cast<int>(e.size());
  s.not_found = not_found;
  s.sign_disagreements = sign_disagreements;
  if (e.empty()) return s;
  std::sort(e.begin(), e.end());
  double sum = 0;
  for (double x : e) sum += x;
  s.mean = sum / e.size();
  s.p50 = e[e.size() / 2];
  s.p95 = e[std::min(e.size() - 1, static_cast<std::size_t>(std::ceil(0.95 * e.size())) - 1)];
  s.max = e.back();
  return s;
}

AtlasErrorReport MeasureAtlasError(const robot::RsrModel& rsr, const robot::Sigma7Model& hc,
                                   const BoundaryAtlas& atlas, const AtlasErrorOptions& o) {
  RequireErrorSamples(o.samples, "atlas error samples");
  AtlasErrorReport report;
  std::mt19937 gen{o.seed};
  SignedDistanceQuery query;
  for (int family = 0; family < 2; ++family) {
    const bool dexterous = family == 0;
    for (int on = 0; on < 2; ++on) {
      std::vector<double> errors;
      int not_found = 0, sign_errors = 0;
      const auto& g = dexterous ? atlas.spec().orientation_grid : atlas.spec().position_grid;
      for (int n = 0, attempts = 0; n < o.samples && attempts < 20 * o.samples; ++attempts) {
        const Eigen::Vector3d fixed(Uniform(gen, g[0], on), Uniform(gen, g[1], on), Uniform(gen, g[2], on));
        const AtlasSlice* slice = dexterous ? atlas.FindDexterous(fixed) : atlas.FindRotational(fixed);
        if (slice == nullptr) continue;
        const SliceFeasibility truth(rsr, hc, dexterous ? SliceKind::kRsrDexterous : SliceKind::kRsrRotational, fixed);
        Sample(*slice->field, truth, dexterous ? o.position_offset_m : o.angle_offset_rad, gen, query, errors,
               not_found, sign_errors);
        ++n;
      }
      const ErrorStats s = SummariseErrors(std::move(errors), not_found, sign_errors);
      (dexterous ? (on ? report.dexterous_on_grid : report.dexterous_off_grid)
                 : (on ? report.rotational_on_grid : report.rotational_off_grid)) = s;
    }
  }
  return report;
}

LiveErrorReport MeasureLiveError(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const AtlasSpec& range,
                                 const LiveBoundaryOptions& live_options, const LiveErrorOptions& o) {
  RequireErrorSamples(o.samples, "live error samples");
  LiveErrorReport report;
  LiveBoundary live(rsr, hc, live_options);
  std::mt19937 gen{o.seed};
  std::normal_distribution<double> normal;
  SignedDistanceQuery query;
  for (int family = 0; family < 2; ++family) {
    const bool dexterous = family == 0;
    const SliceKind kind = dexterous ? SliceKind::kRsrDexterous : SliceKind::kRsrRotational;
    const auto& g = dexterous ? range.orientation_grid : range.position_grid;
    const double staleness = dexterous ? o.orientation_staleness_rad : o.position_staleness_m;
    std::vector<double> errors;
    int not_found = 0, sign_errors = 0;
    double& seconds_max = dexterous ? report.dexterous_seconds_max : report.rotational_seconds_max;
    for (int n = 0, attempts = 0; n < o.samples && attempts < 20 * o.samples; ++attempts) {
      const Eigen::Vector3d actual(Uniform(gen, g[0], false), Uniform(gen, g[1], false), Uniform(gen, g[2], false));
      const Eigen::Vector3d direction = Eigen::Vector3d(normal(gen), normal(gen), normal(gen)).normalized();
      const auto t0 = std::chrono::steady_clock::now();
      const std::unique_ptr<LiveSlice> slice = live.Generate(kind, actual + staleness * direction);
      seconds_max = std::max(seconds_max, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      if (!slice) continue;
      const SliceFeasibility truth(rsr, hc, kind, actual);
      Sample(*slice->field, truth, dexterous ? o.position_offset_m : o.angle_offset_rad, gen, query, errors, not_found,
             sign_errors);
      ++n;
    }
    (dexterous ? report.dexterous : report.rotational) = SummariseErrors(std::move(errors), not_found, sign_errors);
  }
  return report;
}

ClinicalLiveError MeasureClinicalLiveError(const robot::RsrModel& rsr, const robot::Sigma7Model& hc,
                                           const AtlasSpec& range, const LiveBoundaryOptions& live, int samples,
                                           std::uint32_t seed) {
  ClinicalLiveError c;
  c.timing = MeasureRefreshTiming(rsr, hc, live, rsr.geometry().X_FM_home);
  c.staleness = WorstCaseStaleness(c.timing, live, kClinicalLinearSpeedMps, kClinicalAngularSpeedRadps);
  LiveErrorOptions o;
  o.samples = samples;
  o.seed = seed;
  o.orientation_staleness_rad = c.staleness.orientation_rad;
  o.position_staleness_m = c.staleness.position_m;
  c.error = MeasureLiveError(rsr, hc, range, live, o);
  return c;
}

ErrorStats MeasureSliceError(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const WorkspaceSlice& slice,
                             int samples, std::uint32_t seed) {
  RequireErrorSamples(samples, "slice error samples");
  std::mt19937 gen{seed};
  const BoundaryDistanceField field(slice.mesh);
  const SliceFeasibility truth(rsr, hc, slice.spec.kind, slice.spec.fixed);
  SignedDistanceQuery query;
  std::vector<double> errors;
  int not_found = 0, sign_errors = 0;
  const double offset = 1.5 * slice.spec.resolution;
  for (int n = 0; n < samples; ++n) Sample(field, truth, offset, gen, query, errors, not_found, sign_errors);
  return SummariseErrors(std::move(errors), not_found, sign_errors);
}

}  // namespace robossis::geometry
