#include "calibration/synthetic_tracker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::calibration {

namespace {

double TruncatedGaussian(std::mt19937& gen, double bound) {
  if (bound <= 0) return 0;
  std::normal_distribution<double> normal(0.0, bound / 3.0);
  for (;;) {
    const double v = normal(gen);
    if (std::abs(v) <= bound) return v;
  }
}

Eigen::Vector3d NoiseVector(std::mt19937& gen, double bound) {
  return {TruncatedGaussian(gen, bound), TruncatedGaussian(gen, bound), TruncatedGaussian(gen, bound)};
}

}  // namespace

SyntheticRecording WriteSyntheticMotiveCsv(const PoseTrajectory& trajectory, const SyntheticTrackerOptions& o,
                                           std::ostream& out) {
  if (trajectory.size() < 2) throw std::invalid_argument("synthetic tracker: the trajectory needs ≥ 2 poses");
  if (!(o.rate_hz > 0)) throw std::invalid_argument("synthetic tracker: rate_hz must be positive");
  std::mt19937 gen{o.seed};
  const bool v121 = o.format_version.rfind("1.21", 0) == 0;
  const bool quaternion = o.rotation_type == MotiveRotationType::kQuaternion;
  const double scale = o.millimetres ? 1e3 : 1.0;
  const char* eol = o.crlf ? "\r\n" : "\n";
  const std::size_t nm = o.markers_B.size();

  // Frames: those whose reference time falls in [start - lead_in, end + lead_out].
  const double t_ref_begin = trajectory.t_s.front() - o.lead_in_s;
  const double t_ref_end = trajectory.t_s.back() + o.lead_out_s;
  const double k_begin_d = std::ceil((t_ref_begin - o.clock_offset_s) / (1.0 + o.clock_drift) * o.rate_hz - 1e-9);
  const double k_end_d = std::floor((t_ref_end - o.clock_offset_s) / (1.0 + o.clock_drift) * o.rate_hz + 1e-9);
  SyntheticRecording rec;
  rec.first_frame = static_cast<std::int64_t>(std::max(0.0, k_begin_d));
  const std::int64_t last = static_cast<std::int64_t>(k_end_d);
  if (last <= rec.first_frame) {
    throw std::invalid_argument("synthetic tracker: the clock offset leaves no frame with a non-negative number");
  }
  rec.frames = last - rec.first_frame + 1;

  // Occlusion gaps, as frame ranges.
  std::vector<std::pair<std::int64_t, std::int64_t>> gaps;
  std::uniform_real_distribution<double> where(0.05, 0.95), length(o.gap_min_s, o.gap_max_s);
  for (int g = 0; g < o.occlusion_gaps; ++g) {
    const std::int64_t start = rec.first_frame + static_cast<std::int64_t>(where(gen) * static_cast<double>(rec.frames));
    const std::int64_t len = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::lround(length(gen) * o.rate_hz)));
    gaps.emplace_back(start, std::min(last, start + len - 1));
  }
  std::sort(gaps.begin(), gaps.end());
  rec.gaps = 0;
  for (std::size_t g = 0; g < gaps.size(); ++g) {  // merge overlaps so the count is the true number of runs
    if (g == 0 || gaps[g].first > gaps[rec.gaps - 1].second + 1) {
      gaps[rec.gaps++] = gaps[g];
    } else {
      gaps[rec.gaps - 1].second = std::max(gaps[rec.gaps - 1].second, gaps[g].second);
    }
  }
  gaps.resize(rec.gaps);

  // Header.
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "Format Version,%s,Take Name,Synthetic %s,%sCapture Frame Rate,%.6f,Export Frame Rate,%.6f,"
                "Capture Start Time,2026-01-01 12.00.00.000 PM,Total Frames in Take,%lld,Total Exported Frames,%lld,"
                "Rotation Type,%s,Length Units,%s,Coordinate Space,Global%s%s",
                o.format_version.c_str(), o.rigid_body_name.c_str(), v121 ? "" : "Take Notes,,", o.rate_hz,
                o.rate_hz, static_cast<long long>(rec.frames), static_cast<long long>(rec.frames),
                std::string(RotationTypeName(o.rotation_type)).c_str(), o.millimetres ? "Millimeters" : "Meters", eol,
                eol);
  out << buf;
  const std::string id = "\"0A1B2C3D4E5F60718293A4B5C6D7E8F9\"";
  std::string type = v121 ? "," : ",Type", name = v121 ? "," : ",Name", ids = v121 ? "," : ",ID", qty = ",",
              axis = v121 ? "Frame,Time" : "Frame,Time (Seconds)";
  auto add = [&](const std::string& t, const std::string& n, const std::string& q, const std::string& a) {
    type += "," + t;
    name += "," + n;
    ids += "," + id;
    qty += "," + q;
    axis += "," + a;
  };
  const int nrot = quaternion ? 4 : 3;
  for (int k = 0; k < nrot; ++k) add("Rigid Body", o.rigid_body_name, "Rotation", std::string(1, "XYZW"[k]));
  for (int k = 0; k < 3; ++k) add("Rigid Body", o.rigid_body_name, "Position", std::string(1, "XYZ"[k]));
  add("Rigid Body", o.rigid_body_name, v121 ? "Error Per Marker" : "Mean Marker Error", "");
  for (std::size_t m = 0; m < nm; ++m) {
    const std::string mname = v121 ? o.rigid_body_name + "_" + std::to_string(m + 1)
                                   : o.rigid_body_name + ":Marker" + std::to_string(m + 1);
    for (int k = 0; k < 3; ++k) add("Rigid Body Marker", mname, "Position", std::string(1, "XYZ"[k]));
    add("Rigid Body Marker", mname, "Marker Quality", "");
  }
  if (o.write_markers) {
    for (std::size_t m = 0; m < nm; ++m) {
      const std::string mname = o.rigid_body_name + ":Marker" + std::to_string(m + 1);
      for (int k = 0; k < 3; ++k) add("Marker", mname, "Position", std::string(1, "XYZ"[k]));
    }
  }
  out << type << eol << name << eol << ids << eol << qty << eol << axis << eol;

  // Frames.
  const Eigen::Isometry3d X_BM = o.X_MB.inverse();
  (void)X_BM;
  std::size_t gap_index = 0;
  std::string line;
  Eigen::Vector3d p;
  Eigen::Quaterniond q;
  for (std::int64_t frame = rec.first_frame; frame <= last; ++frame) {
    const double t_m = static_cast<double>(frame) / o.rate_hz;
    const double t_ref = std::clamp((1.0 + o.clock_drift) * t_m + o.clock_offset_s, trajectory.t_s.front(),
                                    trajectory.t_s.back());
    InterpolatePose(trajectory, t_ref, p, q);
    Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();
    X_FM.linear() = q.toRotationMatrix();
    X_FM.translation() = p;
    const Eigen::Isometry3d X_TB_true = o.X_TF * X_FM * o.X_MB;
    while (gap_index < gaps.size() && gaps[gap_index].second < frame) ++gap_index;
    const bool occluded = gap_index < gaps.size() && gaps[gap_index].first <= frame;
    std::snprintf(buf, sizeof buf, "%lld,%.6f", static_cast<long long>(frame), t_m);
    line = buf;
    if (occluded) {
      ++rec.frames_occluded;
      const int cells = nrot + 3 + 1 + static_cast<int>(nm) * 4 + (o.write_markers ? static_cast<int>(nm) * 3 : 0);
      line.append(static_cast<std::size_t>(cells), ',');
      line += eol;
      out << line;
      continue;
    }
    // Solved rigid body: true pose with tracker noise.
    Eigen::Isometry3d X_TB = X_TB_true;
    X_TB.translation() += NoiseVector(gen, o.position_noise_bound_m);
    const Eigen::Vector3d dw = NoiseVector(gen, o.rotation_noise_bound_rad);
    X_TB.linear() = RotationFromVector(dw) * X_TB.linear();
    Eigen::Quaterniond qb(X_TB.linear());
    if (frame % 97 == 0) qb.coeffs() = -qb.coeffs();  // Motive's sign is arbitrary: exercise it
    if (quaternion) {
      std::snprintf(buf, sizeof buf, ",%.6f,%.6f,%.6f,%.6f", qb.x(), qb.y(), qb.z(), qb.w());
    } else {
      const Eigen::Vector3d e = MotiveEulerFromRotation(o.rotation_type, X_TB.linear()) * kRadToDeg;
      std::snprintf(buf, sizeof buf, ",%.6f,%.6f,%.6f", e.x(), e.y(), e.z());
    }
    line += buf;
    const Eigen::Vector3d pt = X_TB.translation() * scale;
    std::vector<Eigen::Vector3d> observed(nm);
    double err = 0;
    for (std::size_t m = 0; m < nm; ++m) {
      observed[m] = X_TB_true * o.markers_B[m] + NoiseVector(gen, o.marker_noise_bound_m);
      err += (observed[m] - X_TB * o.markers_B[m]).norm();
    }
    err /= static_cast<double>(std::max<std::size_t>(nm, 1));
    std::snprintf(buf, sizeof buf, ",%.6f,%.6f,%.6f,%.6f", pt.x(), pt.y(), pt.z(), err * scale);
    line += buf;
    std::uniform_real_distribution<double> quality(0.85, 1.0);
    for (std::size_t m = 0; m < nm; ++m) {
      const Eigen::Vector3d solved = X_TB * o.markers_B[m] * scale;
      std::snprintf(buf, sizeof buf, ",%.6f,%.6f,%.6f,%.6f", solved.x(), solved.y(), solved.z(), quality(gen));
      line += buf;
    }
    if (o.write_markers) {
      for (std::size_t m = 0; m < nm; ++m) {
        const Eigen::Vector3d v = observed[m] * scale;
        std::snprintf(buf, sizeof buf, ",%.6f,%.6f,%.6f", v.x(), v.y(), v.z());
        line += buf;
      }
    }
    line += eol;
    out << line;
  }
  return rec;
}

}  // namespace robossis::calibration
