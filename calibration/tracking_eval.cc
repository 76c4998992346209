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

// Gauss-Newton on (offset, drift) with the registration fixed: predicted ring positions against the reference
// interpolated at the aligned times (rotation residuals weighted as in the registration).
ClockModel RefineClock(const RigidBodyTrack& track, const PoseTrajectory& reference, const HandEyeResult& reg,
                       ClockModel clock, bool estimate_drift, double w, const std::vector<std::uint8_t>& excluded) {
  // Predicted ring poses (independent of the clock).
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < track.size(); ++i) {
    if (track.present[i] && !excluded[i]) idx.push_back(i);
  }
  const std::size_t max_frames = 20000;  // evenly subsampled on long takes
  std::vector<std::size_t> use;
  for (std::size_t k = 0; k < std::min(idx.size(), max_frames); ++k) {
    use.push_back(idx.size() <= max_frames ? idx[k] : idx[k * (idx.size() - 1) / (max_frames - 1)]);
  }
  std::vector<Eigen::Isometry3d> pred;
  const Eigen::Isometry3d X_MB_inv = reg.X_MB.inverse();
  for (std::size_t i : use) {
    Eigen::Isometry3d X_TB = Eigen::Isometry3d::Identity();
    X_TB.linear() = track.q_TB[i].toRotationMatrix();
    X_TB.translation() = track.p_TB[i];
    pred.push_back(reg.X_FT * X_TB * X_MB_inv);
  }
  const double t_mid = track.t_s.empty() ? 0.0 : 0.5 * (track.t_s.front() + track.t_s.back());
  auto residual = [&](const ClockModel& c, std::size_t k, Eigen::Matrix<double, 6, 1>& r) {
    Eigen::Vector3d p;
    Eigen::Quaterniond q;
    if (!InterpolatePose(reference, c.ToReference(track.t_s[use[k]]), p, q)) return false;
    r.head<3>() = pred[k].translation() - p;
    r.tail<3>() = w * RotationVector(pred[k].linear() * q.toRotationMatrix().transpose());
    return true;
  };
  for (int iter = 0; iter < 10; ++iter) {
    // Parameters: offset and (drift about the middle of the take, so the two are decorrelated).
    const int np = estimate_drift ? 2 : 1;
    Eigen::Matrix2d JtJ = Eigen::Matrix2d::Zero();
    Eigen::Vector2d Jtr = Eigen::Vector2d::Zero();
    const double h_off = 1e-4;  // s: a central difference over the interpolation, larger than the sample jitter
    for (std::size_t k = 0; k < use.size(); ++k) {
      Eigen::Matrix<double, 6, 1> r0, rp, rm;
      if (!residual(clock, k, r0)) continue;
      Eigen::Matrix<double, 6, 2> J = Eigen::Matrix<double, 6, 2>::Zero();
      ClockModel cp = clock, cm = clock;
      cp.offset_s += h_off;
      cm.offset_s -= h_off;
      if (!residual(cp, k, rp) || !residual(cm, k, rm)) continue;
      J.col(0) = (rp - rm) / (2 * h_off);
      // d t_ref / d drift = t_mocap; drift is parameterized about t_mid: offset' = offset - drift * t_mid.
      J.col(1) = J.col(0) * (track.t_s[use[k]] - t_mid);
      JtJ.noalias() += J.transpose() * J;
      Jtr.noalias() += J.transpose() * r0;
    }
    Eigen::Vector2d step = Eigen::Vector2d::Zero();
    if (np == 2) {
      step = JtJ.ldlt().solve(-Jtr);
    } else if (JtJ(0, 0) > 0) {
      step[0] = -Jtr[0] / JtJ(0, 0);
    }
    if (!step.allFinite()) break;
    step[0] = std::clamp(step[0], -0.05, 0.05);  // one iteration moves at most 50 ms
    clock.offset_s += step[0] - step[1] * t_mid;
    clock.drift += step[1];
    if (std::abs(step[0]) < 1e-7 && std::abs(step[1]) < 1e-10) break;
  }
  return clock;
}

}  // namespace

TrackingEvalResult EvaluateTracking(const RigidBodyTrack& track, const PoseTrajectory& reference,
                                    const TrackingEvalOptions& options) {
  TrackingEvalResult result;
  result.frames_total = track.size();
  result.pose_source = track.source;
  result.quaternion_sign_flips = track.quaternion_sign_flips;
  result.frame_jumps = track.frame_jumps;
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
  for (int round = 0; round < std::max(1, options.alternations); ++round) {
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
    clock = RefineClock(track, reference, reg, clock, options.estimate_drift,
                        options.hand_eye.rotation_weight_m_per_rad, excluded);
  }
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
  flag_flips(MakePairs(track, reference, clock, excluded, nullptr));  // on every frame, before the final fit
  const Pairs pairs = MakePairs(track, reference, clock, excluded, &result.excluded);
  if (pairs.index.size() < 10) throw std::runtime_error("too few frames left after alignment");
  reg = CalibrateTrackerToBase(pairs.X_FM, pairs.X_TB, options.hand_eye);
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
