#pragma once
// A simulated OptiTrack session: writes a genuine Motive CSV export (format 1.21 or 1.23 layout) of a rigid body
// attached to the moving ring, following any trajectory, with the imperfections of a real recording. The ground
// truth it was made from is returned, for tests and the demo.

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "calibration/motive_csv.h"
#include "calibration/trajectory.h"

namespace robossis::calibration {

struct SyntheticTrackerOptions {
  double rate_hz = 120.0;  // OptiTrack Flex 13 (paper §VII-A) runs at 120 Hz
  // Paper §VII-A: "residual within ±0.08 mm and ±0.03°". Read as bounds of a zero-mean Gaussian with
  // σ = bound / 3, truncated at the bound (assumption: the paper gives no distribution).
  double position_noise_bound_m = 0.08e-3;
  double rotation_noise_bound_rad = 0.03 * 3.14159265358979323846 / 180.0;
  double marker_noise_bound_m = 0.08e-3;  // per-marker position noise (same assumption)
  // Unknown to the evaluator: the robot base F in the tracker frame T, and the marker body B in the ring frame M.
  Eigen::Isometry3d X_TF = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d X_MB = Eigen::Isometry3d::Identity();
  // Clock: t_reference = (1 + drift) · t_mocap + offset, with t_mocap = frame / rate.
  double clock_offset_s = 0;
  double clock_drift = 0;
  // Recording starts this long before the trajectory's first sample and ends this long after its last (the ring
  // rests at the end poses meanwhile).
  double lead_in_s = 1.0, lead_out_s = 1.0;
  // Occlusions: this many gaps, each of a uniformly drawn length in [gap_min_s, gap_max_s], in which the rigid body
  // and its markers are empty. The middle 90 % of the take is cut into occlusion_gaps equal slots and each gap lies
  // inside its own slot with at least one visible frame after it, so gaps never touch or merge: the file has
  // exactly occlusion_gaps gaps (at most MaxOcclusionGaps).
  int occlusion_gaps = 0;
  double gap_min_s = 0.02, gap_max_s = 0.3;
  // File flavour.
  std::string format_version = "1.23";  // "1.21" writes the 1.21 header (unlabelled rows, "Error Per Marker")
  MotiveRotationType rotation_type = MotiveRotationType::kQuaternion;
  bool millimetres = false;
  bool crlf = true;
  std::string rigid_body_name = "MovingRing";  // see MotiveAssetNameProblem
  // Marker layout in the body frame B (m). Default: four markers on a 70 mm radius, one raised (asymmetric, so
  // the rigid body is unambiguous).
  std::vector<Eigen::Vector3d> markers_B = {{0.07, 0.0, 0.0}, {0.0, 0.07, 0.01}, {-0.07, 0.0, 0.0},
                                            {0.0, -0.05, 0.03}};
  bool write_markers = true;  // also write the "Marker" (labeled point cloud) columns
  std::uint32_t seed = 42;
};

struct SyntheticRecording {
  std::int64_t frames = 0;
  std::int64_t frames_occluded = 0;
  std::int64_t first_frame = 0;
  int gaps = 0;
};

// Why `name` cannot be written as a rigid body name, or empty if it can. The name is written as a bare cell of the
// header and of the asset rows, so it must be 1 to kMaxMotiveAssetNameLength bytes with no comma, double quote or
// control character (a cell separator, a quoting character, a line break) and no leading or trailing space (a
// reader trims cells). Motive's own asset names satisfy this.
inline constexpr std::size_t kMaxMotiveAssetNameLength = 64;
std::string MotiveAssetNameProblem(const std::string& name);

// The frames a recording of `trajectory` with these options has, and the most occlusion gaps that fit in it.
std::int64_t SyntheticFrameCount(const PoseTrajectory& trajectory, const SyntheticTrackerOptions& options);
int MaxOcclusionGaps(const PoseTrajectory& trajectory, const SyntheticTrackerOptions& options);

// Streams the CSV to `out`. `trajectory` is the ring pose X_FM(t) the tracker observes (commanded or simulated).
// Throws std::invalid_argument, before writing anything, for options it cannot honour: a name
// MotiveAssetNameProblem refuses, more gaps than MaxOcclusionGaps, bad gap lengths or rate.
SyntheticRecording WriteSyntheticMotiveCsv(const PoseTrajectory& trajectory, const SyntheticTrackerOptions& options,
                                           std::ostream& out);

}  // namespace robossis::calibration
