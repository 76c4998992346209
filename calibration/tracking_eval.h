#pragma once
// Tracking-accuracy evaluation (paper §VII-A, Fig. 14): a tracked rigid body against a commanded trajectory.
// Steps: coarse clock offset by speed correlation → registration (tracker→robot base, marker→ring offset) →
// one fit of both transforms with the clock offset and drift (calibration/clock_fit.h) → orientation-flip exclusion
// → errors.

#include <string>
#include <vector>

#include "calibration/clock_fit.h"
#include "calibration/mocap_track.h"
#include "calibration/registration.h"
#include "calibration/time_alignment.h"
#include "calibration/trajectory.h"

namespace robossis::calibration {

struct ErrorStats {
  double mean = 0, median = 0, rmse = 0, std = 0, max = 0, p95 = 0;
  std::size_t count = 0;
};

// Statistics of a sample (absolute values are the caller's business). p95 and median interpolate linearly
// between order statistics. Empty input gives zeros with count 0.
ErrorStats ComputeStats(std::vector<double> values);

struct TrackingEvalOptions {
  // A frame whose orientation differs from the registered command by more than this is a marker-labelling flip
  // and is excluded. Assumption: 10°, two orders of magnitude above the paper's 0.07° mean error.
  double flip_threshold_rad = 0.174533;
  // If set, the clock offset is searched only within offset_s ± offset_window_s (an approximate offset known from
  // the set-up; needed when the motion repeats itself and the speed profiles match at several offsets).
  bool offset_given = false;
  double offset_s = 0;
  double offset_window_s = 2.0;
  HandEyeOptions hand_eye;
  SpeedCorrelationOptions correlation;
  ClockFitOptions clock_fit;  // the one fit of transforms and clock (drift allowed unless clock_fit.allow_drift)
  // Plausibility: a registration whose residual exceeds these fails the evaluation, because a rigid transform that
  // fits this badly means the data is not what it claims (length units off by 1000, another rotation order or
  // type, another rigid body or reference). Assumption: 2 mm and 5°, four times the worst residual of an optical
  // tracker on a rigid ring (Motive: ~0.1-0.5 mm); a take in metres labelled millimetres leaves ~4.6 mm.
  double max_registration_rms_m = 0.002;
  double max_registration_rms_rad = 0.0872665;
};

struct ExclusionCounts {
  std::size_t missing = 0;            // rigid body not solved in the frame (occlusion, empty cells)
  std::size_t outside_reference = 0;  // frame time outside the command log after alignment
  std::size_t orientation_flip = 0;   // orientation jump beyond flip_threshold_rad
  std::size_t total() const { return missing + outside_reference + orientation_flip; }
};

struct TrackingEvalResult {
  ClockModel clock;
  ClockFitResult clock_fit;  // the clock's measurand, interval, bound, drift choice and the fit
  double speed_correlation = 0;
  HandEyeResult registration;
  // Per used frame, in the robot base frame F (SI):
  std::vector<double> t_reference_s;
  std::vector<Eigen::Isometry3d> X_FM_reference;  // commanded, interpolated (lerp + slerp)
  std::vector<Eigen::Isometry3d> X_FM_tracked;    // measured ring pose through the registration
  std::vector<Eigen::Vector3d> translation_error_m;  // tracked - reference, axes of F
  std::vector<Eigen::Vector3d> rotation_error_rad;   // rotation vector of R_tracked R_reference^T, axes of F
  ErrorStats translation, rotation;                  // of the norms (m, rad)
  ErrorStats translation_axis[3], rotation_axis[3];  // of |component|
  ExclusionCounts excluded;
  std::size_t frames_total = 0;
  // Data quality of the recording.
  GapSummary gaps;
  int quaternion_sign_flips = 0;
  int frame_jumps = 0;
  bool complete = true;              // false for an excerpt (fewer rows than the header's count)
  std::int64_t frames_in_header = -1;
  ErrorStats mean_marker_error;  // m, over frames that carry it
  std::string pose_source;
};

// Throws std::runtime_error when the data cannot be evaluated (too few frames, no overlap, degenerate motion).
TrackingEvalResult EvaluateTracking(const RigidBodyTrack& track, const PoseTrajectory& reference,
                                    const TrackingEvalOptions& options = {});

}  // namespace robossis::calibration
