#pragma once
// Shared helpers for the calibration tests: a smooth 6-DOF test motion and the path of the real Motive exports.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>
#include <filesystem>
#include <sstream>
#include <string>

#include "calibration/synthetic_tracker.h"
#include "calibration/trajectory.h"
#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::calibration::testing {

inline std::filesystem::path DataFile(const std::string& name) {
  return std::filesystem::path(ROBOSSIS_MOCAP_TEST_DATA) / name;
}

// Smooth, non-periodic motion of the ring about (0, 0, 284 mm): ±20 mm, ±8° about every axis, 100 Hz.
inline PoseTrajectory TestMotion(double duration_s, double rate_hz = 100.0) {
  PoseTrajectory traj;
  const double f[6] = {0.11, 0.13, 0.17, 0.19, 0.23, 0.07};
  for (int k = 0; k <= static_cast<int>(duration_s * rate_hz); ++k) {
    const double t = k / rate_hz;
    const double env = 0.5 * (1 - std::cos(2 * kPi * t / duration_s));
    double s[6];
    for (int j = 0; j < 6; ++j) s[j] = env * (0.7 * std::sin(2 * kPi * f[j] * t) + 0.3 * std::sin(2 * kPi * 2.7 * f[j] * t + j));
    const Eigen::Vector3d p(0.020 * s[0], 0.020 * s[1], 0.284 + 0.012 * s[2]);
    const Eigen::Matrix3d R = RotationFromRpy(DegToRad(8.0) * Eigen::Vector3d(s[3], s[4], s[5]));
    traj.Add(t, p, Eigen::Quaterniond(R));
  }
  return traj;
}

// A moving ring as a bench test drives it: each axis a sum of three sinusoids of seeded random frequency
// (0.05-0.4 Hz) and phase, so it reverses direction many times, under 2 s ramps at both ends; positions scaled to
// an RMS speed of rms_speed_m_s, rotations up to about ±rotation_deg about each axis. Sampled at rate_hz.
inline PoseTrajectory BenchMotion(std::uint32_t seed, double duration_s, double rate_hz, double rms_speed_m_s,
                                  double rotation_deg) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> freq(0.05, 0.4), phase(0, 2 * kPi);
  double f[6][3], ph[6][3];
  for (int j = 0; j < 6; ++j) {
    for (int k = 0; k < 3; ++k) {
      f[j][k] = freq(gen);
      ph[j][k] = phase(gen);
    }
  }
  const int n = static_cast<int>(duration_s * rate_hz);
  std::vector<std::array<double, 6>> s(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) {
    const double t = i / rate_hz;
    const double ramp = std::min({1.0, t / 2.0, (duration_s - t) / 2.0});
    const double env = ramp * ramp * (3 - 2 * ramp);
    for (int j = 0; j < 6; ++j) {
      double v = 0;
      for (int k = 0; k < 3; ++k) v += std::sin(2 * kPi * f[j][k] * t + ph[j][k]) / 3;
      s[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = env * v;
    }
  }
  double sum_v2 = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double v = (s[i + 1][j] - s[i][j]) * rate_hz;
      sum_v2 += v * v;
    }
  }
  const double scale = rms_speed_m_s / std::sqrt(sum_v2 / n);
  PoseTrajectory traj;
  for (int i = 0; i <= n; ++i) {
    const auto& v = s[static_cast<std::size_t>(i)];
    traj.Add(i / rate_hz, Eigen::Vector3d(scale * v[0], scale * v[1], 0.284 + scale * v[2]),
             Eigen::Quaterniond(RotationFromRpy(DegToRad(rotation_deg) * Eigen::Vector3d(v[3], v[4], v[5]))));
  }
  return traj;
}

// The tracker of the clock's acceptance: 240 Hz, 0.1 mm position noise (σ = bound / 3), 6
// occlusions, an unknown placement and marker offset, the given clock.
inline SyntheticTrackerOptions ClockTakeTracker(std::uint32_t seed, double offset_s, double drift) {
  SyntheticTrackerOptions o;
  o.rate_hz = 240;
  o.position_noise_bound_m = 0.3e-3;
  o.X_TF = PoseFromMmDeg((Vector6d() << 350, -420, 1650, 178, -3, 35).finished());
  o.X_MB = PoseFromMmDeg((Vector6d() << 12, -8, 30, 2, -1, 40).finished());
  o.clock_offset_s = offset_s;
  o.clock_drift = drift;
  o.occlusion_gaps = 6;
  o.write_markers = false;
  o.seed = seed;
  return o;
}

inline std::string WriteTake(const PoseTrajectory& traj, const SyntheticTrackerOptions& options) {
  std::ostringstream out;
  WriteSyntheticMotiveCsv(traj, options, out);
  return out.str();
}

}  // namespace robossis::calibration::testing
