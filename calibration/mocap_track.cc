#include "calibration/mocap_track.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include "calibration/registration.h"

namespace robossis::calibration {

std::size_t RigidBodyTrack::frames_present() const {
  std::size_t n = 0;
  for (std::uint8_t v : present) n += v;
  return n;
}

namespace {

// Labeled markers belonging to an asset called `name` (Motive writes "name:MarkerN"; 1.21 writes "name_N").
std::vector<const MotiveMarkerColumns*> MarkersOf(const MotiveLayout& layout, const std::string& name) {
  std::vector<const MotiveMarkerColumns*> out;
  for (const auto* list : {&layout.markers, &layout.rigid_body_markers}) {
    if (!out.empty()) break;
    for (const MotiveMarkerColumns& m : *list) {
      if (m.name.size() > name.size() && m.name.compare(0, name.size(), name) == 0 &&
          (m.name[name.size()] == ':' || m.name[name.size()] == '_')) {
        out.push_back(&m);
      }
    }
  }
  return out;
}

void AppendPose(RigidBodyTrack& track, const Eigen::Isometry3d& X) {
  Eigen::Quaterniond q(X.linear());
  q.normalize();
  for (std::size_t i = track.present.size() - 1; i-- > 0;) {  // previous present frame (excluding this one)
    if (track.present[i]) {
      if (track.q_TB[i].dot(q) < 0) {
        q.coeffs() = -q.coeffs();
        ++track.quaternion_sign_flips;
      }
      break;
    }
    if (track.present.size() - i > 1000000) break;
  }
  track.p_TB.back() = X.translation();
  track.q_TB.back() = q;
  track.present.back() = 1;
}

}  // namespace

RigidBodyTrack ReadRigidBodyTrack(const std::filesystem::path& path, const std::string& name) {
  MotiveReader reader(path);
  return ReadRigidBodyTrack(reader, name);
}

RigidBodyTrack ReadRigidBodyTrack(MotiveReader& reader, const std::string& name) {
  const MotiveLayout& layout = reader.layout();
  RigidBodyTrack track;
  track.name = name;
  track.rate_hz = reader.header().export_rate_hz;
  const int rb = layout.FindRigidBody(name);
  std::vector<const MotiveMarkerColumns*> markers;
  if (rb < 0) {
    markers = MarkersOf(layout, name);
    if (markers.size() < 3) {
      throw std::runtime_error(reader.source_name() + ": no rigid body named '" + name +
                               "' (and fewer than 3 markers named '" + name + ":...'); the take has rigid bodies " +
                               layout.RigidBodyNames());
    }
    track.source = "markers (" + std::to_string(markers.size()) + ")";
  } else {
    track.source = "rigid body";
  }
  if (reader.header().total_exported_frames > 0 && reader.header().total_exported_frames < 50000000) {
    const auto n = static_cast<std::size_t>(reader.header().total_exported_frames);
    track.frame.reserve(n);
    track.t_s.reserve(n);
    track.p_TB.reserve(n);
    track.q_TB.reserve(n);
    track.present.reserve(n);
    track.mean_marker_error_m.reserve(n);
  }
  // Marker mode: the first pass keeps the marker positions (they are all this track needs), then fits poses.
  std::vector<std::vector<Eigen::Vector3d>> marker_positions;
  std::vector<std::vector<std::uint8_t>> marker_seen;
  MotiveRow row;
  std::int64_t previous = -1;
  const bool quaternion_file = reader.header().rotation_type == MotiveRotationType::kQuaternion;
  Eigen::Vector4d previous_q = Eigen::Vector4d::Zero();
  bool have_previous_q = false;
  int file_sign_flips = 0;
  while (reader.ReadFrame(row)) {
    if (previous >= 0 && row.frame > previous + 1) ++track.frame_jumps;
    previous = row.frame;
    track.frame.push_back(row.frame);
    track.t_s.push_back(row.time_s);
    track.p_TB.emplace_back(Eigen::Vector3d::Zero());
    track.q_TB.emplace_back(Eigen::Quaterniond::Identity());
    track.present.push_back(0);
    if (rb >= 0) {
      const int error_col = layout.rigid_bodies[rb].mean_marker_error;
      track.mean_marker_error_m.push_back(row.Length(error_col));
      if (const std::optional<Eigen::Isometry3d> X = reader.RigidBodyPose(row, rb)) {
        AppendPose(track, *X);
        if (quaternion_file) {  // count sign changes of the file's own quaternions (the pose matrix hides them)
          const MotiveRigidBodyColumns& c = layout.rigid_bodies[rb];
          const Eigen::Vector4d q(row.Number(c.rotation[0]), row.Number(c.rotation[1]), row.Number(c.rotation[2]),
                                  row.Number(c.rotation[3]));
          if (have_previous_q && q.dot(previous_q) < 0) ++file_sign_flips;
          previous_q = q;
          have_previous_q = true;
        }
      }
    } else {
      track.mean_marker_error_m.push_back(kMissing);
      marker_positions.emplace_back(markers.size(), Eigen::Vector3d::Zero());
      marker_seen.emplace_back(markers.size(), 0);
      for (std::size_t m = 0; m < markers.size(); ++m) {
        if (const std::optional<Eigen::Vector3d> p = reader.MarkerPosition(row, *markers[m])) {
          marker_positions.back()[m] = *p;
          marker_seen.back()[m] = 1;
        }
      }
    }
  }
  if (track.size() == 0) throw std::runtime_error(reader.source_name() + ": no data rows after the header");
  if (rb >= 0 && quaternion_file) track.quaternion_sign_flips = file_sign_flips;
  track.complete = reader.complete();
  track.frames_in_header = reader.header().total_exported_frames;
  if (rb < 0) {
    // Body frame: origin at the markers' centroid in the first complete frame, axes parallel to the tracker's.
    std::size_t ref = track.size();
    for (std::size_t i = 0; i < track.size() && ref == track.size(); ++i) {
      bool all = true;
      for (std::uint8_t s : marker_seen[i]) all = all && s;
      if (all) ref = i;
    }
    if (ref == track.size()) {
      throw std::runtime_error(reader.source_name() + ": the markers of '" + name +
                               "' are never all visible in one frame; cannot define the body frame");
    }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : marker_positions[ref]) centroid += p;
    centroid /= static_cast<double>(markers.size());
    std::vector<Eigen::Vector3d> layout_B;
    for (const Eigen::Vector3d& p : marker_positions[ref]) layout_B.push_back(p - centroid);
    double sum_sq = 0;
    std::size_t fitted_points = 0;
    std::vector<Eigen::Vector3d> from, to;
    for (std::size_t i = 0; i < track.size(); ++i) {
      from.clear();
      to.clear();
      for (std::size_t m = 0; m < markers.size(); ++m) {
        if (marker_seen[i][m]) {
          from.push_back(layout_B[m]);
          to.push_back(marker_positions[i][m]);
        }
      }
      if (from.size() < 3) continue;
      const RigidFit fit = FitRigidTransform(from, to);
      sum_sq += fit.rms_m * fit.rms_m * static_cast<double>(from.size());
      fitted_points += from.size();
      track.present[i] = 0;
      // AppendPose writes into the last element: temporarily use the frame's slot.
      Eigen::Quaterniond q(fit.X.linear());
      q.normalize();
      for (std::size_t j = i; j-- > 0;) {
        if (track.present[j]) {
          if (track.q_TB[j].dot(q) < 0) {
            q.coeffs() = -q.coeffs();
            ++track.quaternion_sign_flips;
          }
          break;
        }
      }
      track.p_TB[i] = fit.X.translation();
      track.q_TB[i] = q;
      track.present[i] = 1;
      track.mean_marker_error_m[i] = fit.rms_m;
    }
    track.marker_fit_rms_m = fitted_points > 0 ? std::sqrt(sum_sq / static_cast<double>(fitted_points)) : 0.0;
  }
  return track;
}

PoseTrajectory PresentPoses(const RigidBodyTrack& track) {
  PoseTrajectory out;
  for (std::size_t i = 0; i < track.size(); ++i) {
    if (track.present[i]) out.Add(track.t_s[i], track.p_TB[i], track.q_TB[i]);
  }
  return out;
}

MotiveTakeSummary InspectMotiveTake(const std::filesystem::path& path) {
  MotiveReader reader(path);
  return InspectMotiveTake(reader);
}

MotiveTakeSummary InspectMotiveTake(MotiveReader& reader) {
  MotiveTakeSummary s;
  s.header = reader.header();
  const MotiveLayout& layout = reader.layout();
  s.markers = static_cast<int>(layout.markers.size());
  s.rigid_body_markers = static_cast<int>(layout.rigid_body_markers.size());
  const std::size_t nrb = layout.rigid_bodies.size();
  s.rigid_bodies.resize(nrb);
  std::vector<std::int64_t> current_gap(nrb, 0), error_count(nrb, 0);
  std::vector<double> error_sum(nrb, 0);
  for (std::size_t r = 0; r < nrb; ++r) {
    s.rigid_bodies[r].name = layout.rigid_bodies[r].name;
    s.rigid_bodies[r].rigid_body_markers = static_cast<int>(layout.rigid_bodies[r].marker_indices.size());
  }
  auto close_gap = [&](std::size_t r) {
    if (current_gap[r] > 0) {
      ++s.rigid_bodies[r].gaps.gaps;
      s.rigid_bodies[r].gaps.longest_gap_frames = std::max(s.rigid_bodies[r].gaps.longest_gap_frames, current_gap[r]);
      current_gap[r] = 0;
    }
  };
  MotiveRow row;
  std::int64_t previous = -1;
  while (reader.ReadFrame(row)) {
    if (s.frames == 0) s.first_frame = row.frame;
    s.last_frame = row.frame;
    const std::int64_t skipped = previous >= 0 ? row.frame - previous - 1 : 0;
    if (skipped > 0) ++s.frame_jumps;
    previous = row.frame;
    ++s.frames;
    for (std::size_t r = 0; r < nrb; ++r) {
      current_gap[r] += skipped;  // frames absent from the file are missing for every asset
      if (reader.RigidBodyPose(row, static_cast<int>(r))) {
        close_gap(r);
        ++s.rigid_bodies[r].gaps.frames_present;
        const double e = row.Length(layout.rigid_bodies[r].mean_marker_error);
        if (!std::isnan(e)) {
          error_sum[r] += e;
          ++error_count[r];
        }
      } else {
        ++current_gap[r];
      }
    }
  }
  s.complete = reader.complete();
  s.frames_in_header = reader.header().total_exported_frames;
  for (std::size_t r = 0; r < nrb; ++r) {
    close_gap(r);
    s.rigid_bodies[r].mean_marker_error_mean_m =
        error_count[r] > 0 ? error_sum[r] / static_cast<double>(error_count[r]) : kMissing;
  }
  return s;
}

}  // namespace robossis::calibration
