#pragma once
// Timed pose sequences (commanded, simulated or tracked), their file formats, and interpolation between samples.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace robossis::calibration {

// Poses X_AB(t) of one body B in one frame A, with strictly increasing times (s).
struct PoseTrajectory {
  std::vector<double> t_s;
  std::vector<Eigen::Vector3d> p;     // m
  std::vector<Eigen::Quaterniond> q;  // unit quaternions, made sign-continuous on load

  std::size_t size() const { return t_s.size(); }
  bool empty() const { return t_s.empty(); }
  void Add(double t, const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation);
  Eigen::Isometry3d Pose(std::size_t i) const;
  double duration_s() const { return empty() ? 0.0 : t_s.back() - t_s.front(); }
};

// Pose at time t by linear interpolation of the position and spherical interpolation (slerp) of the orientation
// between the two bracketing samples. Returns false if t is outside [t_front, t_back].
bool InterpolatePose(const PoseTrajectory& trajectory, double t, Eigen::Vector3d& p, Eigen::Quaterniond& q);

// The project's trajectory CSV (written by the motion transfer, the simulation and the GUI): a header row naming
// the columns, then one row per sample; lines starting with '#' are comments. Columns, by name:
//   time:        t_s | time_s | timestamp_s
//   position:    x_m,y_m,z_m | x_mm,y_mm,z_mm
//   orientation: qw,qx,qy,qz | roll_rad,pitch_rad,yaw_rad | roll_deg,pitch_deg,yaw_deg (R = Rz(yaw)Ry(pitch)Rx(roll))
// Other columns are ignored; a column name twice, or a row with more or fewer cells than the header, is an error.
// A UTF-8 byte-order mark is skipped. Throws std::runtime_error naming the file, line and field.
// Bounds, checked before any work: files up to kMaxTrajectoryFileBytes; time stamps within ±kMaxTrajectoryTimeS (Unix
// epoch seconds fit, as TUM datasets use them) and spanning at most kMaxTrajectorySpanS.
inline constexpr std::uintmax_t kMaxTrajectoryFileBytes = 256u << 20;
inline constexpr double kMaxTrajectoryTimeS = 1e10;
inline constexpr double kMaxTrajectorySpanS = 1e6;  // ~11.6 days: longer than any recorded session

PoseTrajectory ReadTrajectoryCsv(const std::filesystem::path& path);
PoseTrajectory ParseTrajectoryCsv(const std::string& text, const std::string& source_name);

// Writes the project's CSV: t_s,x_m,y_m,z_m,qw,qx,qy,qz (full precision).
std::string FormatTrajectoryCsv(const PoseTrajectory& trajectory);

// TUM RGB-D trajectory format: "timestamp tx ty tz qx qy qz qw" (s, m), '#' comments, separated by spaces. A comma
// is an error: a headerless comma-separated file has no stated column order (qw first or last?), so it is refused
// rather than guessed.
PoseTrajectory ReadTum(const std::filesystem::path& path);
PoseTrajectory ParseTum(const std::string& text, const std::string& source_name);
std::string FormatTum(const PoseTrajectory& trajectory);

// Either format, chosen by content: a first non-comment line with letters is a CSV header, otherwise TUM.
PoseTrajectory ReadReferenceTrajectory(const std::filesystem::path& path);

}  // namespace robossis::calibration
