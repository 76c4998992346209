#include "calibration/tracking_eval.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <Eigen/Dense>

#include "src/core/pose.h"

namespace robossis::calibration {

ErrorStats ComputeStats(std::vector<double> v) {
  ErrorStats s;
  s.count = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  double sum = 0, sq = 0;
  for (double x : v) {
    sum += x;
    sq += x * x;
  }
  const double n = static_cast<double>(v.size());
  s.mean = sum / n;
  s.rmse = std::sqrt(sq / n);
  double var = 0;
  for (double x : v) var += (x - s.mean) * (x - s.mean);
  s.std = std::sqrt(var / n);
  s.max = v.back();
  auto quantile = [&](double q) {
    const double pos = q * (n - 1);
    const std::size_t i = static_cast<std::size_t>(std::floor(pos));
    const double f = pos - static_cast<double>(i);
    return i + 1 < v.size() ? (1 - f) * v[i] + f * v[i + 1] : v[i];
  };
  s.median = quantile(0.5);
  s.p95 = quantile(0.95);
  return s;
}

namespace {

struct Pairs {
  std::vector<std::size_t> index;  // into the track
  std::vector<Eigen::Isometry3d> X_FM, X_TB;
  std::vector<double> t_ref;
};

// Pairs every usable tracked frame with the reference interpolated at its aligned time.
Pairs MakePairs(const RigidBodyTrack& track, const PoseTrajectory& reference, const ClockModel& clock,
                const std::vector<std::uint8_t>& excluded, ExclusionCounts* counts, std::size_t stride = 1) {
  Pairs pairs;
  Eigen::Vector3d p;
  Eigen::Quaterniond q;
  for (std::size_t i = 0; i < track.size(); i += stride) {
    if (!track.present[i]) {
      if (counts) ++counts->missing;
      continue;
    }
    if (excluded[i]) {
      if (counts) ++counts->orientation_flip;
      continue;
    }
    const double t = clock.ToReference(track.t_s[i]);
    if (!InterpolatePose(reference, t, p, q)) {
      if (counts) ++counts->outside_reference;
      continue;
    }
    Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();
    X_FM.linear() = q.toRotationMatrix();
    X_FM.translation() = p;
    Eigen::Isometry3d X_TB = Eigen::Isometry3d::Identity();
    X_TB.linear() = track.q_TB[i].toRotationMatrix();
    X_TB.translation() = track.p_TB[i];
    pairs.index.push_back(i);
    pairs.X_FM.push_back(X_FM);
    pairs.X_TB.push_back(X_TB);
    pairs.t_ref.push_back(t);
  }
  return pairs;
}

}  // namespace

TrackingEvalResult EvaluateTracking(const RigidBodyTrack& track, const PoseTrajectory& reference,
                                    const TrackingEvalOptions& options) {
  TrackingEvalResult result;
  result.frames_total = track.size();
  result.pose_source = track.source;
  result.quaternion_sign_flips = track.quaternion_sign_flips;
  result.frame_jumps = track.frame_jumps;
  result.complete = track.complete;
  result.frames_in_header = track.frames_in_header;
  // Gaps in the rigid body (frame-number jumps count as missing frames).
  {
    std::int64_t run = 0;
    auto close = [&] {
      if (run > 0) {
        ++result.gaps.gaps;
        result.gaps.longest_gap_frames = std::max(result.gaps.longest_gap_frames, run);
      }
      run = 0;
    };
    for (std::size_t i = 0; i < track.size(); ++i) {
      if (i > 0) run += std::max<std::int64_t>(0, track.frame[i] - track.frame[i - 1] - 1);
      if (track.present[i]) {
        close();
        ++result.gaps.frames_present;
      } else {
        ++run;
      }
    }
    close();
  }
  std::vector<double> mme;
  for (std::size_t i = 0; i < track.size(); ++i) {
    if (track.present[i] && !std::isnan(track.mean_marker_error_m[i])) mme.push_back(track.mean_marker_error_m[i]);
  }
  result.mean_marker_error = ComputeStats(std::move(mme));

  const PoseTrajectory tracked = PresentPoses(track);
  if (tracked.size() < 10) {
    throw std::runtime_error("rigid body '" + track.name + "' is present in only " + std::to_string(tracked.size()) +
                             " frames; at least 10 are needed");
  }
  ClockModel clock;
  {
    SpeedCorrelationOptions correlation = options.correlation;
    if (options.offset_given) {
      correlation.bounded = true;
      correlation.center_s = options.offset_s;
      correlation.half_width_s = options.offset_window_s;
    }
    const SpeedCorrelationResult c = EstimateOffsetBySpeedCorrelation(reference, tracked, correlation);
    clock.offset_s = c.offset_s;
    result.speed_correlation = c.correlation;
  }
  std::vector<std::uint8_t> excluded(track.size(), 0);
  // The alternation works on an evenly strided subset (≤ 20,000 frames) so long takes stay cheap; flips are then
  // detected and the final registration and errors computed on every frame.
  const std::size_t stride = std::max<std::size_t>(1, track.size() / 20000);
  HandEyeResult reg;
  auto flag_flips = [&](const Pairs& pairs) {
    bool changed = false;
    for (std::size_t k = 0; k < pairs.index.size(); ++k) {
      const Eigen::Isometry3d X = RingPoseFromTracked(reg, pairs.X_TB[k]);
      if (RotationAngleBetween(X.linear(), pairs.X_FM[k].linear()) > options.flip_threshold_rad) {
        excluded[pairs.index[k]] = 1;
        changed = true;
      }
    }
    return changed;
  };
  {
    Pairs pairs = MakePairs(track, reference, clock, excluded, nullptr, stride);
    if (pairs.index.size() < 10) {
      throw std::runtime_error("only " + std::to_string(pairs.index.size()) +
                               " tracked frames fall inside the command log's time span after alignment; is this the "
                               "right command log?");
    }
    reg = CalibrateTrackerToBase(pairs.X_FM, pairs.X_TB, options.hand_eye);
    if (flag_flips(pairs)) {
      pairs = MakePairs(track, reference, clock, excluded, nullptr, stride);
      if (pairs.index.size() < 10) throw std::runtime_error("too few frames left after excluding orientation flips");
      reg = CalibrateTrackerToBase(pairs.X_FM, pairs.X_TB, options.hand_eye);
    }
  }
  // One fit of the transforms and the clock from there; again if it reveals flips the coarse clock hid.
  auto fit = [&] {
    result.clock_fit = FitClockAndRegistration(track, excluded, reference, reg, clock, options.clock_fit);
    clock = result.clock_fit.clock;
    reg.X_FT = result.clock_fit.X_FT;
    reg.X_MB = result.clock_fit.X_MB;
  };
  reg.method += ", then one fit with the clock";
  fit();
  if (flag_flips(MakePairs(track, reference, clock, excluded, nullptr))) fit();
  // The window is a promise of the options ("searched only within"): a refinement that ends outside it is not
  // an offset within the window, and no clamped value would be the fit's.
  if (options.offset_given && !(std::fabs(clock.offset_s - options.offset_s) <= options.offset_window_s)) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "the clock offset that fits best is %.4f s, outside the window %g s +- %g s given "
                  "(--offset-s, --offset-window-s): widen the window or check the approximate offset",
                  clock.offset_s, options.offset_s, options.offset_window_s);
    throw std::runtime_error(buf);
  }
  const Pairs pairs = MakePairs(track, reference, clock, excluded, &result.excluded);
  if (pairs.index.size() < 10) throw std::runtime_error("too few frames left after alignment");
  ComputeRegistrationResiduals(pairs.X_FM, pairs.X_TB, reg);
  if (!(reg.rms_position_m <= options.max_registration_rms_m) ||
      !(reg.rms_rotation_rad <= options.max_registration_rms_rad)) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "the tracker-to-robot registration leaves an RMS residual of %.3f mm and %.3f deg, expected at most "
                  "%.3f mm and %.3f deg: the recording does not match the reference as a rigid motion. Check the "
                  "length units (m or mm), the rotation type, the rigid body and the reference file",
                  reg.rms_position_m * 1e3, reg.rms_rotation_rad * 57.29577951308232,
                  options.max_registration_rms_m * 1e3, options.max_registration_rms_rad * 57.29577951308232);
    throw std::runtime_error(buf);
  }

  result.clock = clock;
  result.registration = reg;
  std::vector<double> et, er, eta[3], era[3];
  const std::size_t n = pairs.index.size();
  result.t_reference_s = pairs.t_ref;
  result.X_FM_reference = pairs.X_FM;
  result.X_FM_tracked.reserve(n);
  result.translation_error_m.reserve(n);
  result.rotation_error_rad.reserve(n);
  et.reserve(n);
  er.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Isometry3d X = RingPoseFromTracked(reg, pairs.X_TB[k]);
    const Eigen::Vector3d dp = X.translation() - pairs.X_FM[k].translation();
    const Eigen::Vector3d dr = RotationVector(X.linear() * pairs.X_FM[k].linear().transpose());
    result.X_FM_tracked.push_back(X);
    result.translation_error_m.push_back(dp);
    result.rotation_error_rad.push_back(dr);
    et.push_back(dp.norm());
    er.push_back(dr.norm());
    for (int a = 0; a < 3; ++a) {
      eta[a].push_back(std::abs(dp[a]));
      era[a].push_back(std::abs(dr[a]));
    }
  }
  result.translation = ComputeStats(std::move(et));
  result.rotation = ComputeStats(std::move(er));
  for (int a = 0; a < 3; ++a) {
    result.translation_axis[a] = ComputeStats(std::move(eta[a]));
    result.rotation_axis[a] = ComputeStats(std::move(era[a]));
  }
  return result;
}

}  // namespace robossis::calibration
