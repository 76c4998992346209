#include "calibration/trajectory.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "src/core/csv.h"
#include "src/core/files.h"
#include "src/core/pose.h"
#include "src/core/parse.h"
#include "src/core/units.h"

namespace robossis::calibration {

namespace {

std::vector<std::string_view> Split(std::string_view line, bool whitespace_too) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i <= line.size()) {
    std::size_t j = i;
    while (j < line.size() && line[j] != ',' && !(whitespace_too && (line[j] == ' ' || line[j] == '\t'))) ++j;
    const std::string_view field = TrimField(line.substr(i, j - i));
    if (!whitespace_too || !field.empty()) out.push_back(field);
    i = j + 1;
  }
  return out;
}

template <typename Fn>
void ForEachLine(const std::string& text, Fn fn) {
  std::size_t pos = 0, number = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ++number;
    fn(line, number);
    pos = end + 1;
  }
}

bool IsCommentOrBlank(std::string_view line) {
  const std::string_view t = TrimField(line);
  return t.empty() || t.front() == '#';
}

std::string Where(const std::string& source, std::size_t line) {
  return source + " line " + std::to_string(line) + ": ";
}

// Time stamps are bounded so that a huge stamp or span cannot make an evaluation loop for hours.
void CheckTime(double t, const PoseTrajectory& so_far, const std::string& source, std::size_t line) {
  if (!(std::fabs(t) <= kMaxTrajectoryTimeS)) {
    throw std::runtime_error(Where(source, line) + "time " + std::to_string(t) + " s; expected |t| <= " +
                             std::to_string(kMaxTrajectoryTimeS) + " s");
  }
  if (!so_far.empty() && t - so_far.t_s.front() > kMaxTrajectorySpanS) {
    throw std::runtime_error(Where(source, line) + "time " + std::to_string(t) + " s is " +
                             std::to_string(t - so_far.t_s.front()) + " s after the first sample; expected a span of "
                             "at most " + std::to_string(kMaxTrajectorySpanS) + " s");
  }
}

std::string ReadTrajectoryFile(const std::filesystem::path& path) {
  std::string text = ReadBoundedFile(path, kMaxTrajectoryFileBytes, "trajectory file");
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);  // UTF-8 byte-order mark
  return text;
}

}  // namespace

void PoseTrajectory::Add(double t, const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation) {
  Eigen::Quaterniond qn = orientation.normalized();
  if (!q.empty() && q.back().dot(qn) < 0) qn.coeffs() = -qn.coeffs();  // same rotation, continuous sign
  t_s.push_back(t);
  p.push_back(position);
  q.push_back(qn);
}

Eigen::Isometry3d PoseTrajectory::Pose(std::size_t i) const {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q[i].toRotationMatrix();
  X.translation() = p[i];
  return X;
}

bool InterpolatePose(const PoseTrajectory& trajectory, double t, Eigen::Vector3d& p, Eigen::Quaterniond& q) {
  const std::vector<double>& ts = trajectory.t_s;
  if (ts.empty() || !(t >= ts.front()) || !(t <= ts.back())) return false;
  std::size_t hi = static_cast<std::size_t>(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin());
  if (hi >= ts.size()) hi = ts.size() - 1;
  const std::size_t lo = hi == 0 ? 0 : hi - 1;
  const double span = ts[hi] - ts[lo];
  const double s = span > 0 ? (t - ts[lo]) / span : 0.0;
  p = (1 - s) * trajectory.p[lo] + s * trajectory.p[hi];
  q = trajectory.q[lo].slerp(s, trajectory.q[hi]);
  return true;
}

// The header names choose the columns (metres or millimetres; a quaternion or Euler angles in rad or deg); the
// strict CSV reader then checks the whole file against that header: quotes and a byte-order mark, no name twice,
// exactly one finite number per column in every row, time increasing strictly within the bounds.
PoseTrajectory ParseTrajectoryCsv(const std::string& text, const std::string& source_name) {
  // The header is the first line that is neither blank nor a '#' comment (after a byte-order mark).
  std::vector<std::string> names;
  std::size_t header_line = 0;
  bool have_header = false;
  ForEachLine(text, [&](std::string_view line, std::size_t number) {
    if (have_header || IsCommentOrBlank(line)) return;
    if (number == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
    try {
      names = SplitCsvRecord(line, source_name + " line " + std::to_string(number));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(e.what());
    }
    header_line = number;
    have_header = true;
  });
  if (!have_header) throw std::runtime_error(source_name + ": empty; expected a header row and samples");
  auto has = [&](const char* n) { return std::find(names.begin(), names.end(), n) != names.end(); };
  auto first_of = [&](std::initializer_list<const char*> options) -> std::string {
    for (const char* n : options) {
      if (has(n)) return n;
    }
    return "";
  };
  const std::string here = Where(source_name, header_line);
  // Each quantity from one column set: two sets (t_s and time_s, x_m and x_mm, a quaternion and roll/pitch/yaw)
  // may disagree, and reading one of them silently would hide it.
  auto refuse_conflicts = [&](const char* quantity, std::initializer_list<std::initializer_list<const char*>> sets) {
    std::vector<std::string> present;
    for (const auto& set : sets) {
      for (const char* n : set) {
        if (has(n)) {
          present.push_back(n);
          break;
        }
      }
    }
    if (present.size() > 1) {
      std::string list;
      for (const std::string& n : present) list += (list.empty() ? "'" : "' and '") + n;
      throw std::runtime_error(here + "conflicting " + quantity + " columns " + list +
                               "'; expected one set of " + quantity + " columns");
    }
  };
  refuse_conflicts("time", {{"t_s"}, {"time_s"}, {"timestamp_s"}});
  refuse_conflicts("position", {{"x_m", "y_m", "z_m"}, {"x_mm", "y_mm", "z_mm"}});
  refuse_conflicts("orientation", {{"qw", "qx", "qy", "qz"},
                                   {"roll_rad", "pitch_rad", "yaw_rad"},
                                   {"roll_deg", "pitch_deg", "yaw_deg"}});
  const std::string t_name = first_of({"t_s", "time_s", "timestamp_s"});
  if (t_name.empty()) throw std::runtime_error(here + "no time column (t_s, time_s or timestamp_s)");
  const bool mm = !has("x_m") && has("x_mm");
  const double p_scale = mm ? kMmToM : 1.0;
  std::vector<std::string> p_names = mm ? std::vector<std::string>{"x_mm", "y_mm", "z_mm"}
                                        : std::vector<std::string>{"x_m", "y_m", "z_m"};
  for (const std::string& n : p_names) {
    if (!has(n.c_str())) {
      throw std::runtime_error(here + "no position column '" + n + "' (expected x_m,y_m,z_m or x_mm,y_mm,z_mm)");
    }
  }
  const bool quaternion = has("qw");
  const bool deg = has("roll_deg");
  const double e_scale = deg ? kDegToRad : 1.0;
  std::vector<std::string> r_names = quaternion ? std::vector<std::string>{"qw", "qx", "qy", "qz"}
                                     : deg      ? std::vector<std::string>{"roll_deg", "pitch_deg", "yaw_deg"}
                                                : std::vector<std::string>{"roll_rad", "pitch_rad", "yaw_rad"};
  for (const std::string& n : r_names) {
    if (!has(n.c_str())) {
      throw std::runtime_error(here + (quaternion ? "no column '" + n + "'"
                                                  : std::string("no orientation columns (expected qw,qx,qy,qz or "
                                                                "roll/pitch/yaw in _rad or _deg)")));
    }
  }
  CsvSpec spec;
  spec.what = "trajectory CSV";
  spec.columns = {t_name};
  spec.columns.insert(spec.columns.end(), p_names.begin(), p_names.end());
  spec.columns.insert(spec.columns.end(), r_names.begin(), r_names.end());
  for (const std::string& n : names) {
    if (std::find(spec.columns.begin(), spec.columns.end(), n) == spec.columns.end()) spec.optional_columns.push_back(n);
  }
  spec.any_order = true;  // other columns are carried along unread; a name twice is still an error
  spec.comment_lines = true;
  spec.max_bytes = kMaxTrajectoryFileBytes;
  spec.max_rows = kMaxTrajectoryFileBytes / 16;  // a row is at least "t,x,y,z,a,b,c\n": the byte bound binds first
  spec.time_column = t_name;
  spec.min_time = -kMaxTrajectoryTimeS;
  spec.max_time = kMaxTrajectoryTimeS;
  const NumericCsv csv = ParseNumericCsv(text, source_name, spec);

  const int t_col = csv.Column(t_name);
  int p_col[3], r_col[4] = {-1, -1, -1, -1};
  for (int k = 0; k < 3; ++k) p_col[k] = csv.Column(p_names[k]);
  for (std::size_t k = 0; k < r_names.size(); ++k) r_col[k] = csv.Column(r_names[k]);
  PoseTrajectory out;
  for (const CsvRow& row : csv.rows) {
    const std::vector<double>& v = row.values;
    const double t = v[t_col];
    CheckTime(t, out, source_name, static_cast<std::size_t>(row.line));
    const Eigen::Vector3d p(v[p_col[0]] * p_scale, v[p_col[1]] * p_scale, v[p_col[2]] * p_scale);
    Eigen::Quaterniond q;
    if (quaternion) {
      q = Eigen::Quaterniond(v[r_col[0]], v[r_col[1]], v[r_col[2]], v[r_col[3]]);
      if (!(q.norm() > 0.5 && q.norm() < 1.5)) {
        throw std::runtime_error(Where(source_name, static_cast<std::size_t>(row.line)) + "quaternion norm " +
                                 std::to_string(q.norm()) + " is not 1");
      }
    } else {
      q = Eigen::Quaterniond(RotationFromRpy(Eigen::Vector3d(v[r_col[0]], v[r_col[1]], v[r_col[2]]) * e_scale));
    }
    out.Add(t, p, q);
  }
  if (out.size() < 2) throw std::runtime_error(source_name + ": fewer than 2 samples; nothing to interpolate");
  return out;
}

PoseTrajectory ReadTrajectoryCsv(const std::filesystem::path& path) {
  return ParseTrajectoryCsv(ReadTrajectoryFile(path), path.string());
}

std::string FormatTrajectoryCsv(const PoseTrajectory& trajectory) {
  std::string out = "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
  char buf[256];
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const Eigen::Quaterniond& q = trajectory.q[i];
    const Eigen::Vector3d& p = trajectory.p[i];
    std::snprintf(buf, sizeof buf, "%.9f,%.9f,%.9f,%.9f,%.12f,%.12f,%.12f,%.12f\n", trajectory.t_s[i], p.x(), p.y(),
                  p.z(), q.w(), q.x(), q.y(), q.z());
    out += buf;
  }
  return out;
}

PoseTrajectory ParseTum(const std::string& text, const std::string& source_name) {
  PoseTrajectory out;
  ForEachLine(text, [&](std::string_view line, std::size_t number) {
    if (IsCommentOrBlank(line)) return;
    if (line.find(',') != std::string_view::npos) {
      // A headerless comma-separated file is not TUM: its column order (which quaternion convention?) is unknown.
      throw std::runtime_error(Where(source_name, number) +
                               "commas in a TUM line; TUM is space-separated 'timestamp tx ty tz qx qy qz qw', and a "
                               "CSV needs a header row naming its columns (t_s,x_m,y_m,z_m,qw,qx,qy,qz)");
    }
    const std::vector<std::string_view> f = Split(line, true);
    if (f.size() != 8) {
      throw std::runtime_error(Where(source_name, number) + "expected 8 values 'timestamp tx ty tz qx qy qz qw', got " +
                               std::to_string(f.size()));
    }
    double v[8];
    for (int k = 0; k < 8; ++k) {
      if (!TryParseNumber(f[k], &v[k])) {
        throw std::runtime_error(Where(source_name, number) + "value " + std::to_string(k + 1) + " is '" +
                                 std::string(f[k].substr(0, 30)) + "'; expected a number");
      }
    }
    CheckTime(v[0], out, source_name, number);
    if (!out.empty() && !(v[0] > out.t_s.back())) {
      throw std::runtime_error(Where(source_name, number) + "timestamp " + std::string(f[0].substr(0, 30)) +
                               " does not increase (previous " + std::to_string(out.t_s.back()) + " s)");
    }
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (!(q.norm() > 0.5 && q.norm() < 1.5)) {
      throw std::runtime_error(Where(source_name, number) + "quaternion norm is not 1");
    }
    out.Add(v[0], Eigen::Vector3d(v[1], v[2], v[3]), q);
  });
  if (out.size() < 2) throw std::runtime_error(source_name + ": fewer than 2 poses; nothing to interpolate");
  return out;
}

PoseTrajectory ReadTum(const std::filesystem::path& path) { return ParseTum(ReadTrajectoryFile(path), path.string()); }

std::string FormatTum(const PoseTrajectory& trajectory) {
  std::string out = "# timestamp tx ty tz qx qy qz qw (s, m; TUM RGB-D format)\n";
  char buf[256];
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const Eigen::Quaterniond& q = trajectory.q[i];
    const Eigen::Vector3d& p = trajectory.p[i];
    std::snprintf(buf, sizeof buf, "%.9f %.9f %.9f %.9f %.12f %.12f %.12f %.12f\n", trajectory.t_s[i], p.x(), p.y(),
                  p.z(), q.x(), q.y(), q.z(), q.w());
    out += buf;
  }
  return out;
}

PoseTrajectory ReadReferenceTrajectory(const std::filesystem::path& path) {
  const std::string text = ReadTrajectoryFile(path);
  bool csv = false;
  bool decided = false;
  ForEachLine(text, [&](std::string_view line, std::size_t) {
    if (decided || IsCommentOrBlank(line)) return;
    csv = std::any_of(line.begin(), line.end(), [](char c) { return std::isalpha(static_cast<unsigned char>(c)) &&
                                                                    c != 'e' && c != 'E'; });
    decided = true;
  });
  return csv ? ParseTrajectoryCsv(text, path.string()) : ParseTum(text, path.string());
}

}  // namespace robossis::calibration
