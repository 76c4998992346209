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

PoseTrajectory ParseTrajectoryCsv(const std::string& text, const std::string& source_name) {
  PoseTrajectory out;
  std::map<std::string, int> col;
  bool have_header = false;
  int t_col = -1, p_col[3] = {-1, -1, -1}, q_col[4] = {-1, -1, -1, -1}, e_col[3] = {-1, -1, -1};
  double p_scale = 1, e_scale = 1;
  std::size_t ncols = 0;
  ForEachLine(text, [&](std::string_view line, std::size_t number) {
    if (IsCommentOrBlank(line)) return;
    const std::vector<std::string_view> f = Split(line, false);
    if (!have_header) {
      for (std::size_t i = 0; i < f.size(); ++i) {
        const auto [it, inserted] = col.emplace(std::string(f[i]), static_cast<int>(i));
        if (!inserted) {
          throw std::runtime_error(Where(source_name, number) + "column name '" + it->first + "' appears twice (columns " +
                                   std::to_string(it->second + 1) + " and " + std::to_string(i + 1) + ")");
        }
      }
      ncols = f.size();
      auto find = [&](std::initializer_list<const char*> names) {
        for (const char* n : names) {
          if (col.count(n)) return col[n];
        }
        return -1;
      };
      t_col = find({"t_s", "time_s", "timestamp_s"});
      if (t_col < 0) throw std::runtime_error(Where(source_name, number) + "no time column (t_s, time_s or timestamp_s)");
      const char* axes_m[3] = {"x_m", "y_m", "z_m"};
      const char* axes_mm[3] = {"x_mm", "y_mm", "z_mm"};
      const bool mm = !col.count("x_m") && col.count("x_mm");
      p_scale = mm ? kMmToM : 1.0;
      for (int k = 0; k < 3; ++k) {
        p_col[k] = find({mm ? axes_mm[k] : axes_m[k]});
        if (p_col[k] < 0) {
          throw std::runtime_error(Where(source_name, number) + "no position column '" + (mm ? axes_mm[k] : axes_m[k]) +
                                   "' (expected x_m,y_m,z_m or x_mm,y_mm,z_mm)");
        }
      }
      if (col.count("qw")) {
        const char* qn[4] = {"qw", "qx", "qy", "qz"};
        for (int k = 0; k < 4; ++k) {
          q_col[k] = find({qn[k]});
          if (q_col[k] < 0) throw std::runtime_error(Where(source_name, number) + "no column '" + qn[k] + "'");
        }
      } else {
        const bool deg = col.count("roll_deg") > 0;
        const char* en_rad[3] = {"roll_rad", "pitch_rad", "yaw_rad"};
        const char* en_deg[3] = {"roll_deg", "pitch_deg", "yaw_deg"};
        e_scale = deg ? kDegToRad : 1.0;
        for (int k = 0; k < 3; ++k) {
          e_col[k] = find({deg ? en_deg[k] : en_rad[k]});
          if (e_col[k] < 0) {
            throw std::runtime_error(Where(source_name, number) +
                                     "no orientation columns (expected qw,qx,qy,qz or roll/pitch/yaw in _rad or _deg)");
          }
        }
      }
      have_header = true;
      return;
    }
    if (f.size() != ncols) {
      throw std::runtime_error(Where(source_name, number) + "expected exactly " + std::to_string(ncols) +
                               " cells, one per header column, got " + std::to_string(f.size()));
    }
    auto num = [&](int c) {
      double v = 0;
      if (!TryParseNumber(f[c], &v)) {
        throw std::runtime_error(Where(source_name, number) + "column '" +
                                 [&] {
                                   for (const auto& [n, i] : col) {
                                     if (i == c) return n;
                                   }
                                   return std::string("?");
                                 }() +
                                 "' is '" + std::string(f[c].substr(0, 30)) + "'; expected a number");
      }
      return v;
    };
    const double t = num(t_col);
    CheckTime(t, out, source_name, number);
    if (!out.empty() && !(t > out.t_s.back())) {
      throw std::runtime_error(Where(source_name, number) + "time " + std::to_string(t) +
                               " s does not increase (previous " + std::to_string(out.t_s.back()) + " s)");
    }
    const Eigen::Vector3d p(num(p_col[0]) * p_scale, num(p_col[1]) * p_scale, num(p_col[2]) * p_scale);
    Eigen::Quaterniond q;
    if (q_col[0] >= 0) {
      q = Eigen::Quaterniond(num(q_col[0]), num(q_col[1]), num(q_col[2]), num(q_col[3]));
      if (!(q.norm() > 0.5 && q.norm() < 1.5)) {
        throw std::runtime_error(Where(source_name, number) + "quaternion norm " + std::to_string(q.norm()) +
                                 " is not 1");
      }
    } else {
      q = Eigen::Quaterniond(RotationFromRpy(
          Eigen::Vector3d(num(e_col[0]), num(e_col[1]), num(e_col[2])) * e_scale));
    }
    out.Add(t, p, q);
  });
  if (!have_header) throw std::runtime_error(source_name + ": empty; expected a header row and samples");
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
