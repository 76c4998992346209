#pragma once
// One tracked body from a Motive export, read in a single streaming pass; and the take's overview for
// `robossis mocap inspect`.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "calibration/motive_csv.h"
#include "calibration/trajectory.h"

namespace robossis::calibration {

// The pose of one rigid body in the tracker frame T, frame by frame. Missing frames (occlusion, empty cells) are
// kept with present = 0 so gaps stay visible; they never become zeros.
struct RigidBodyTrack {
  std::string name;
  std::string source;               // how the pose was obtained: "rigid body" or "markers (n)"
  double rate_hz = 0;
  std::vector<std::int64_t> frame;  // Motive frame numbers (may jump)
  std::vector<double> t_s;          // frame / export rate
  std::vector<Eigen::Vector3d> p_TB;     // m (undefined where !present)
  std::vector<Eigen::Quaterniond> q_TB;  // sign-continuous over present frames
  std::vector<std::uint8_t> present;
  std::vector<double> mean_marker_error_m;  // NaN where absent
  int quaternion_sign_flips = 0;    // q → -q between consecutive present frames (harmless; undone on load)
  int frame_jumps = 0;              // frame number increased by more than 1 between rows
  double marker_fit_rms_m = 0;      // when built from markers: RMS residual of the per-frame rigid fits
  // An excerpt: fewer rows than the header's 'Total Exported Frames' (frames_in_header; -1 when absent).
  bool complete = true;
  std::int64_t frames_in_header = -1;

  std::size_t size() const { return frame.size(); }
  std::size_t frames_present() const;
};

// Reads the rigid body called `name`. If the export has no such rigid body but has markers named "name:..." or
// "name_..." (labeled markers of an asset), the pose is fitted to them (≥ 3 visible markers per frame), in a body
// frame defined by the first frame where all of them are visible. Throws std::runtime_error naming the file and
// the rigid bodies it does contain when neither exists.
RigidBodyTrack ReadRigidBodyTrack(const std::filesystem::path& path, const std::string& name);
RigidBodyTrack ReadRigidBodyTrack(MotiveReader& reader, const std::string& name);

// Present frames only, as a trajectory (time = frame / export rate).
PoseTrajectory PresentPoses(const RigidBodyTrack& track);

struct GapSummary {
  std::int64_t frames_present = 0;
  std::int64_t gaps = 0;               // runs of missing frames (empty cells or skipped frame numbers)
  std::int64_t longest_gap_frames = 0;
};

struct MotiveTakeSummary {
  MotiveHeader header;
  std::int64_t frames = 0;       // data rows
  std::int64_t first_frame = 0, last_frame = 0;
  std::int64_t frame_jumps = 0;
  // An excerpt: fewer rows than the header's 'Total Exported Frames' (frames_in_header; -1 when absent).
  bool complete = true;
  std::int64_t frames_in_header = -1;
  struct RigidBody {
    std::string name;
    GapSummary gaps;
    int rigid_body_markers = 0;
    double mean_marker_error_mean_m = 0;  // over frames that have it; NaN if never
  };
  std::vector<RigidBody> rigid_bodies;
  int markers = 0;             // "Marker" assets (labeled and unlabeled)
  int rigid_body_markers = 0;  // "Rigid Body Marker" assets
};

// Streams the whole file once.
MotiveTakeSummary InspectMotiveTake(const std::filesystem::path& path);
MotiveTakeSummary InspectMotiveTake(MotiveReader& reader);

}  // namespace robossis::calibration
