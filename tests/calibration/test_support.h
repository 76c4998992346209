#pragma once
// Shared helpers for the calibration tests: a smooth 6-DOF test motion and the path of the real Motive exports.

#include <cmath>
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

inline std::string WriteTake(const PoseTrajectory& traj, const SyntheticTrackerOptions& options) {
  std::ostringstream out;
  WriteSyntheticMotiveCsv(traj, options, out);
  return out.str();
}

}  // namespace robossis::calibration::testing
