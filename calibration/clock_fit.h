#pragma once
// The tracker's clock and the registration in one fit: tracker→base X_FT, marker→ring X_MB, the clock offset at the
// middle of the take and, where the data asks for it, the drift, by Levenberg-Marquardt on whitened residuals of
// the tracked ring pose against a continuous-time reference (ReferenceCurve). It reports the measurand with a
// 95 % interval (block bootstrap beside the fit's curvature), the Cramér-Rao bound of the offset, the drift model
// choice (BIC) and a warning when the motion cannot fix the offset.

#include <cstdint>
#include <string>
#include <vector>

#include "calibration/mocap_track.h"
#include "calibration/reference_curve.h"
#include "calibration/registration.h"
#include "calibration/time_alignment.h"
#include "calibration/trajectory.h"

namespace robossis::calibration {

struct ClockFitOptions {
  bool allow_drift = true;  // false: the constant-offset model only (--no-drift)
  // Frames used, evenly subsampled above this, to bound the cost of long takes (the bound then counts these only).
  // Assumption: 30,000 frames, two minutes at 240 Hz.
  std::size_t max_frames = 30000;
  int max_iterations = 30;
  // Block bootstrap: replicates of the linearized fit (one Gauss-Newton step from the solution on the resampled
  // blocks, so a replicate costs a 14x14 solve). 400 replicates put the standard error of a bootstrap standard
  // deviation at 1/sqrt(2*400) = 3.5 %.
  int bootstrap_replicates = 400;
  std::uint32_t seed = 1;
  // Blocks: at least n^(1/3) frames (the rate that minimizes the error of a block-bootstrap variance, Hall, Horowitz
  // and Jing 1995) and at least twice the lag at which the offset's score stops being correlated (autocorrelation
  // below decorrelated_below), so that blocks are nearly independent. Blocks never span an occlusion.
  double decorrelated_below = 0.1;
  // Identifiability: the share of the offset's information not shared with the transforms (and drift). Below this
  // the motion cannot tell an offset from a rotation of the tracker (constant speed about one axis, a ring standing
  // still): warning, and the interval becomes the search window. Assumption: 1 %, where the offset's standard
  // deviation is ten times what the motion's speed alone would give.
  double min_offset_information_share = 0.01;
  double unidentified_half_width_s = 2.0;  // the coarse search's window (TrackingEvalOptions::offset_window_s)
  // Coverage factor of the expanded uncertainty (GUM: k = 2, about 95 % for a normal distribution).
  double coverage_factor = 2.0;
};

// One source of the offset's uncertainty budget (GUM): a standard uncertainty and how it was evaluated.
struct UncertaintySource {
  std::string name;
  std::string evaluation;  // "A" (statistics of this take) or "B" (other information)
  double standard_uncertainty_s = 0;
  std::string note;
};

struct ClockFitResult {
  // The measurand: the clock offset at the take's middle, t_reference − t_mocap at t_mocap = t_mid_s (through the
  // ring's motion, so any lag of the ring behind the command log is part of it).
  double t_mid_s = 0;
  double offset_mid_s = 0;
  ClockModel clock;  // t_reference = (1 + drift) t_mocap + offset (offset at t_mocap = 0, drift 0 when not selected)
  bool drift_considered = false;  // the drift model was fitted and tested (ClockFitOptions::allow_drift)
  bool drift_selected = false;
  double drift = 0;           // of the drift model (whether selected or not)
  double drift_bound = 0;     // |drift| ≤ this (k = 2) from the drift model
  double drift_ci[2] = {0, 0};
  double delta_bic = 0;       // BIC(no drift) − BIC(drift): positive selects drift
  // The offset's standard uncertainties (s): from the fit's curvature (white residuals) and the block bootstrap.
  double offset_sigma_curvature_s = 0, offset_sigma_bootstrap_s = 0;
  double offset_ci_s[2] = {0, 0};  // offset_mid ± k u_c (or the search window when not identifiable)
  double expanded_uncertainty_s = 0;
  double coverage_factor = 2;  // k of the expanded uncertainty and of the intervals (ClockFitOptions)
  double crb_s = 0;           // Cramér-Rao bound of a delay: 1/sqrt(Σ |v/σ_p|² + |ω/σ_r|²) over the frames used
  double crb_position_only_s = 0;  // σ_p / sqrt(Σ |v|²)
  double offset_information_share = 0;
  bool identifiable = true;
  std::string warning;        // empty unless the offset is not identifiable
  std::vector<UncertaintySource> budget;
  // The fit.
  Eigen::Isometry3d X_FT = Eigen::Isometry3d::Identity(), X_MB = Eigen::Isometry3d::Identity();
  double sigma_position_m = 0, sigma_rotation_rad = 0;  // whitening scales (RMS residual per component)
  std::size_t frames = 0, blocks = 0;
  double block_s = 0;
  int iterations = 0;
};

// The fit's model of one tracked frame, exposed so that its analytic Jacobian can be checked against finite
// differences. Parameters are perturbed on the right: X_FT · exp(δ[0..5]) (rotation, translation),
// X_MB · exp(δ[6..11]), offset_mid_s + δ[12], drift + δ[13].
struct ClockFitParameters {
  Eigen::Isometry3d X_FT = Eigen::Isometry3d::Identity(), X_MB = Eigen::Isometry3d::Identity();
  double offset_mid_s = 0, drift = 0;
};
ClockFitParameters PerturbClockFitParameters(const ClockFitParameters& x, const Eigen::Matrix<double, 14, 1>& d);
// The residual of a tracked body pose X_TB at mocap time t_s (ring pose predicted through X_FT and X_MB, minus the
// reference at t_s + offset_mid_s + drift (t_s − t_mid_s): position m, rotation vector rad) and, when J is given,
// its Jacobian (first order in the residual rotation). False outside the reference.
bool ClockFitResidual(const ReferenceCurve& reference, const ClockFitParameters& x, double t_mid_s, double t_s,
                      const Eigen::Isometry3d& X_TB, Eigen::Matrix<double, 6, 1>& r, Eigen::Matrix<double, 6, 14>* J);

// `excluded` (one per track frame, may be empty) drops frames (orientation flips). `start`: the registration and
// the coarse clock (offset only) to start from. Throws std::runtime_error when too few frames overlap the reference.
ClockFitResult FitClockAndRegistration(const RigidBodyTrack& track, const std::vector<std::uint8_t>& excluded,
                                       const PoseTrajectory& reference, const HandEyeResult& start,
                                       const ClockModel& start_clock, const ClockFitOptions& options = {});

}  // namespace robossis::calibration
