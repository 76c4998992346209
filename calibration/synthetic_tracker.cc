#include "calibration/synthetic_tracker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
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

// The recorded frame numbers [first, last]: those whose reference time falls in [start - lead_in, end + lead_out].
struct FrameRange {
  std::int64_t first = 0, last = -1;
  std::int64_t count() const { return last - first + 1; }
};

FrameRange Frames(const PoseTrajectory& trajectory, const SyntheticTrackerOptions& o) {
  if (trajectory.size() < 2) throw std::invalid_argument("synthetic tracker: the trajectory needs ≥ 2 poses");
  if (!(o.rate_hz > 0) || !std::isfinite(o.rate_hz)) {
    throw std::invalid_argument("synthetic tracker: rate_hz must be positive and finite");
  }
  const double t_ref_begin = trajectory.t_s.front() - o.lead_in_s;
  const double t_ref_end = trajectory.t_s.back() + o.lead_out_s;
  const double k_begin_d = std::ceil((t_ref_begin - o.clock_offset_s) / (1.0 + o.clock_drift) * o.rate_hz - 1e-9);
  const double k_end_d = std::floor((t_ref_end - o.clock_offset_s) / (1.0 + o.clock_drift) * o.rate_hz + 1e-9);
  FrameRange r;
  r.first = static_cast<std::int64_t>(std::max(0.0, k_begin_d));
  r.last = static_cast<std::int64_t>(k_end_d);
  if (r.last <= r.first) {
    throw std::invalid_argument("synthetic tracker: the clock offset leaves no frame with a non-negative number");
  }
  return r;
}

// Gap lengths in frames (at least one).
std::int64_t GapFrames(double seconds, double rate_hz) {
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(std::lround(seconds * rate_hz)));
}

// The span the gaps are placed in: the middle 90 % of the take, [begin, begin + length).
struct GapSpan {
  std::int64_t begin = 0, length = 0;
};
GapSpan GapSpanOf(const FrameRange& frames) {
  const auto n = static_cast<double>(frames.count());
  const std::int64_t begin = frames.first + static_cast<std::int64_t>(std::ceil(0.05 * n));
  const std::int64_t end = frames.first + static_cast<std::int64_t>(std::floor(0.95 * n));
  return {begin, std::max<std::int64_t>(0, end - begin)};
}

// Each gap needs its longest length plus one visible frame after it, so neighbours never touch.
int MaxGapsIn(const GapSpan& span, const SyntheticTrackerOptions& o) {
  const std::int64_t per_gap = GapFrames(o.gap_max_s, o.rate_hz) + 1;
  return static_cast<int>(std::min<std::int64_t>(span.length / per_gap, std::numeric_limits<int>::max()));
}

void CheckGapOptions(const SyntheticTrackerOptions& o) {
  if (!(o.gap_min_s > 0) || !(o.gap_max_s >= o.gap_min_s) || !std::isfinite(o.gap_max_s)) {
    throw std::invalid_argument("synthetic tracker: the gap lengths must satisfy 0 < gap_min_s <= gap_max_s (finite)");
  }
  if (o.occlusion_gaps < 0) throw std::invalid_argument("synthetic tracker: occlusion_gaps must be ≥ 0");
}

}  // namespace

std::string MotiveAssetNameProblem(const std::string& name) {
  if (name.empty()) return "is empty";
  if (name.size() > kMaxMotiveAssetNameLength) {
    return "is " + std::to_string(name.size()) + " bytes long (at most " + std::to_string(kMaxMotiveAssetNameLength) +
           ")";
  }
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (c == ',') return "contains a comma";
    if (c == '"') return "contains a double quote";
    if (u < 0x20 || u == 0x7f) return "contains a control character (line break, tab, ...)";
  }
  if (name.front() == ' ' || name.back() == ' ') return "starts or ends with a space";
  return "";
}

std::int64_t SyntheticFrameCount(const PoseTrajectory& trajectory, const SyntheticTrackerOptions& o) {
  return Frames(trajectory, o).count();
}

int MaxOcclusionGaps(const PoseTrajectory& trajectory, const SyntheticTrackerOptions& o) {
  CheckGapOptions(o);
  return MaxGapsIn(GapSpanOf(Frames(trajectory, o)), o);
}

SyntheticRecording WriteSyntheticMotiveCsv(const PoseTrajectory& trajectory, const SyntheticTrackerOptions& o,
                                           std::ostream& out) {
  const FrameRange frames = Frames(trajectory, o);
  CheckGapOptions(o);
  if (const std::string problem = MotiveAssetNameProblem(o.rigid_body_name); !problem.empty()) {
    throw std::invalid_argument("synthetic tracker: rigid body name '" + o.rigid_body_name + "' " + problem);
  }
  const GapSpan span = GapSpanOf(frames);
  const int max_gaps = MaxGapsIn(span, o);
  if (o.occlusion_gaps > max_gaps) {
    throw std::invalid_argument("synthetic tracker: " + std::to_string(o.occlusion_gaps) +
                                " occlusion gaps do not fit in " + std::to_string(frames.count()) +
                                " frames (at most " + std::to_string(max_gaps) + ")");
  }
  std::mt19937 gen{o.seed};
  const bool v121 = o.format_version.rfind("1.21", 0) == 0;
  const bool quaternion = o.rotation_type == MotiveRotationType::kQuaternion;
  const double scale = o.millimetres ? 1e3 : 1.0;
  const char* eol = o.crlf ? "\r\n" : "\n";
  const std::size_t nm = o.markers_B.size();
  SyntheticRecording rec;
  rec.first_frame = frames.first;
  const std::int64_t last = frames.last;
  rec.frames = frames.count();

  // Occlusion gaps, as frame ranges: gap g in slot g of the span, at a drawn place that leaves a visible frame
  // before the next slot.
  std::vector<std::pair<std::int64_t, std::int64_t>> gaps;
  std::uniform_real_distribution<double> where(0.0, 1.0), length(o.gap_min_s, o.gap_max_s);
  for (int g = 0; g < o.occlusion_gaps; ++g) {
    const std::int64_t slot_begin = span.begin + span.length * g / o.occlusion_gaps;
    const std::int64_t slot_end = span.begin + span.length * (g + 1) / o.occlusion_gaps;  // exclusive
    const double u = where(gen);
    const std::int64_t len = std::min(GapFrames(length(gen), o.rate_hz), slot_end - slot_begin - 1);
    const std::int64_t room = slot_end - slot_begin - 1 - len;  // free start positions beyond the first
    const std::int64_t start = slot_begin + static_cast<std::int64_t>(u * static_cast<double>(room + 1));
    gaps.emplace_back(start, start + len - 1);
  }
  rec.gaps = static_cast<int>(gaps.size());

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
