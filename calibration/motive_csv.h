#pragma once
// OptiTrack Motive CSV exports (format 1.2x, i.e. 1.21 to 1.25), read as a stream.
//
// Layout (seen in real exports, tests/calibration/data/README.md): row 1 is a key/value list (Format Version,
// Export Frame Rate, Rotation Type, Length Units, ...); then a blank row; then header rows identified by position:
// type, name, ID, ..., quantity, and the axis row that starts with "Frame". Each data row is one frame. Empty cells
// are missing data (occlusion), never zero. Values are converted to SI when read (metres, radians).
// Cells are split by the project's strict CSV splitter (src/core/csv.h: quotes, "" inside quotes, a byte-order mark);
// a column named twice (same type, name, ID, quantity and axis), a non-empty cell beyond the header's columns, and
// frames or Time cells that do not increase are errors.

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

namespace robossis::calibration {

// Largest export read (read whole, through the project's one opener). An hour at 240 Hz of one rigid body with its
// four markers and four labelled markers is 305 MB (bench_calibration's take), so three hours of such a take fit.
inline constexpr std::uintmax_t kMaxMotiveFileBytes = std::uintmax_t{1} << 30;  // 1 GiB

// Plausibility bounds of an export's values (assumptions, not Motive's): a tracked position within 1000 m of the
// origin (any capture volume is tens of metres); a quaternion's norm within 1e-3 of 1 (Motive writes six decimals,
// a norm off by more is not a rotation); the Time cell within half a frame, or the 1 ms Motive rounds Time to, of
// frame / export rate (else the rate or the file was edited).
inline constexpr double kMaxMotivePositionM = 1000.0;
inline constexpr double kMotiveQuaternionNormTolerance = 1e-3;
inline constexpr double kMotiveTimeToleranceFrames = 0.5;
inline constexpr double kMotiveTimeRoundingS = 1e-3;
// Largest frame number or frame count read (an assumption: whole numbers below 2^53 are exact in a double, and
// 9e15 frames at 1 kHz are 285 000 years).
inline constexpr double kMaxMotiveFrame = 9.0e15;

inline constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

// How Motive wrote orientation. Euler types are Motive's rotation orders, angles in degrees in the file.
enum class MotiveRotationType { kQuaternion, kXYZ, kXZY, kYXZ, kYZX, kZXY, kZYX };

std::string_view RotationTypeName(MotiveRotationType type);

// Rotation from three Euler angles (rad) given in the file's column order X, Y, Z, for a Motive rotation order.
// Assumption (Motive's documentation does not spell out the composition): the order names intrinsic rotations
// applied left to right, e.g. XYZ → R = Rx(x)·Ry(y)·Rz(z), as in the NatNet samples' EulOrdXYZr.
Eigen::Matrix3d RotationFromMotiveEuler(MotiveRotationType type, const Eigen::Vector3d& xyz_rad);
// Inverse of RotationFromMotiveEuler (one of the two solutions).
Eigen::Vector3d MotiveEulerFromRotation(MotiveRotationType type, const Eigen::Matrix3d& R);

struct MotiveHeader {
  std::string format_version;  // e.g. "1.23"
  std::string take_name;
  double capture_rate_hz = 0;
  double export_rate_hz = 0;
  MotiveRotationType rotation_type = MotiveRotationType::kQuaternion;
  std::string length_units;    // "Meters", "Millimeters" or "Centimeters"
  double length_scale_to_m = 1;  // multiply file lengths by this
  std::int64_t total_exported_frames = -1;  // -1 if absent
  int header_lines = 0;                     // lines before the first data row
};

// A rigid body's columns (indices into a data row; -1 if the export lacks the column).
struct MotiveRigidBodyColumns {
  std::string name;
  std::string id;
  int rotation[4] = {-1, -1, -1, -1};  // X, Y, Z, W (quaternion) or X, Y, Z Euler angles (W = -1)
  int position[3] = {-1, -1, -1};
  int mean_marker_error = -1;          // "Mean Marker Error" (1.23+) or "Error Per Marker" (1.21)
  std::vector<int> marker_indices;     // into MotiveLayout::rigid_body_markers
};

// A marker's columns: a rigid-body marker (the solved position of one marker of a rigid body's definition)
// or a marker (labeled or unlabeled point cloud).
struct MotiveMarkerColumns {
  std::string name;
  std::string id;
  int position[3] = {-1, -1, -1};
  int marker_quality = -1;  // rigid-body markers only
};

struct MotiveLayout {
  std::vector<MotiveRigidBodyColumns> rigid_bodies;
  std::vector<MotiveMarkerColumns> rigid_body_markers;
  std::vector<MotiveMarkerColumns> markers;
  int frame_column = 0;
  int time_column = -1;
  int num_columns = 0;
  int other_asset_columns = 0;  // skeleton bones and other types, not read

  // Index of the rigid body with this name, or -1.
  int FindRigidBody(std::string_view name) const;
  std::string RigidBodyNames() const;  // "a, b" for messages
};

// One data row, its cells split by the project's strict CSV splitter (quotes removed, blanks trimmed).
class MotiveRow {
 public:
  std::int64_t frame = 0;
  double time_s = 0;  // frame / export rate (the reliable clock)
  // The cell as SI value (lengths scaled by the header's units, angles untouched), or NaN when empty or absent
  // (an occlusion). Throws std::runtime_error naming the file, line and column for a cell that is neither empty
  // nor a finite number ('nan', 'abc', 'inf').
  double Number(int column) const;
  double Length(int column) const { return Number(column) * length_scale_; }
  bool Empty(int column) const;
  std::size_t line_number = 0;

 private:
  friend class MotiveReader;
  std::string line_;
  std::vector<std::string> fields_;
  std::string source_name_;
  double length_scale_ = 1;
};

// Streams a Motive export: the header is parsed on construction, frames one by one afterwards.
// Throws std::runtime_error naming the file, the line and what was expected.
class MotiveReader {
 public:
  explicit MotiveReader(const std::filesystem::path& path);
  // From text already in memory (tests, fuzzing); `source_name` is used in messages.
  MotiveReader(std::string text, std::string source_name);

  const MotiveHeader& header() const { return header_; }
  const MotiveLayout& layout() const { return layout_; }
  const std::string& source_name() const { return source_name_; }

  // Reads the next data row; false at the end of the file. Throws on a malformed row (with its line number), and at
  // the end of a file holding more rows than its header's 'Total Exported Frames'.
  bool ReadFrame(MotiveRow& row);
  // Rows read so far. After the last, complete() is false for an excerpt: fewer rows than the header's
  // 'Total Exported Frames' (public exports are often the first frames of a take with the header left as it was).
  std::int64_t frames_read() const { return frames_read_; }
  bool complete() const { return header_.total_exported_frames < 0 || frames_read_ >= header_.total_exported_frames; }

  // A rigid body's pose in the tracker frame, if every needed cell is present. Quaternions are normalized.
  std::optional<Eigen::Isometry3d> RigidBodyPose(const MotiveRow& row, int rigid_body) const;
  std::optional<Eigen::Vector3d> MarkerPosition(const MotiveRow& row, const MotiveMarkerColumns& marker) const;

 private:
  void ParseHeader();
  bool NextLine(std::string& line);
  double CheckedLength(const MotiveRow& row, int column) const;  // Length, bounded by kMaxMotivePositionM

  std::string source_name_;
  std::string memory_;
  std::size_t memory_pos_ = 0;
  std::size_t line_number_ = 0;
  bool line_unterminated_ = false;  // the last line read had no newline (end of a possibly truncated file)
  MotiveHeader header_;
  MotiveLayout layout_;
  std::int64_t previous_frame_ = std::numeric_limits<std::int64_t>::min();
  std::int64_t frames_read_ = 0;
  double previous_time_cell_ = -std::numeric_limits<double>::infinity();
};

}  // namespace robossis::calibration
