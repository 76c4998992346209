#include "haptics/transfer/hc_trajectory.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>

#include "src/core/units.h"

namespace robossis::transfer {

HcSample HcRecord::ToSample() const {
  HcSample s;
  s.time_s = time_s;
  const Eigen::Isometry3d X = PoseFromMmDeg(pose_mm_deg);
  s.p_OH = X.translation();
  s.R_OH = X.linear();
  return s;
}

namespace {

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) {
    const auto b = cell.find_first_not_of(" \t\r");
    const auto e = cell.find_last_not_of(" \t\r");
    cells.push_back(b == std::string::npos ? std::string() : cell.substr(b, e - b + 1));
  }
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

double ParseCell(const std::string& text, const std::string& where, const std::string& column) {
  double value = 0;
  std::size_t used = 0;
  bool ok = !text.empty();
  if (ok) {
    try {
      value = std::stod(text, &used);
    } catch (const std::exception&) {
      ok = false;
    }
  }
  if (!ok || used != text.size() || !std::isfinite(value)) {
    throw std::runtime_error(where + ": '" + column + "' is '" + text + "'; expected a finite number");
  }
  return value;
}

// Minimum-jerk blend from 0 to 1 over [t0, t0 + T].
double MinJerk(double t, double t0, double T) {
  const double s = std::clamp((t - t0) / T, 0.0, 1.0);
  return s * s * s * (10 - 15 * s + 6 * s * s);
}

// The hand of Fig. 8: back and forth along x (60 mm in 3 s: ~20 mm/s on average, 37.5 mm/s peak), a sideways
// drift, a 2 deg twist, and a small physiological tremor (8–11 Hz, ~0.05 mm).
Vector6d Fig8Hand(double t) {
  Vector6d x;
  x[0] = 60.0 * (MinJerk(t, 0.5, 3.0) - MinJerk(t, 4.5, 3.0)) + 0.04 * std::sin(2 * kPi * 9.0 * t);
  x[1] = 15.0 * (MinJerk(t, 1.0, 3.0) - MinJerk(t, 5.0, 3.0)) + 0.03 * std::sin(2 * kPi * 10.7 * t + 1.0);
  x[2] = 5.0 * MinJerk(t, 2.0, 4.0) + 0.02 * std::sin(2 * kPi * 8.3 * t + 2.0);
  x[3] = 0;
  x[4] = 0;
  x[5] = 2.0 * (MinJerk(t, 0.5, 3.0) - MinJerk(t, 4.5, 3.0));
  return x;
}

Vector6d SlowHand(double t) {
  Vector6d x = Vector6d::Zero();
  x[0] = 20.0 * (MinJerk(t, 0.5, 6.0) - MinJerk(t, 7.0, 6.0));  // peak 6.25 mm/s
  return x;
}

Vector6d RotationHand(double t) {
  Vector6d x = Vector6d::Zero();
  x[0] = 20.0 * MinJerk(t, 0.5, 5.0);
  x[5] = 10.0 * (MinJerk(t, 0.5, 5.0) - MinJerk(t, 6.0, 3.0));  // peak 3.75 deg/s out, 6.25 deg/s back
  x[4] = 3.0 * MinJerk(t, 1.0, 4.0);
  return x;
}

std::vector<HcRecord> Sample(Vector6d (*hand)(double), double duration_s) {
  std::vector<HcRecord> out;
  const int n = static_cast<int>(std::lround(duration_s * 1000.0));
  out.reserve(n + 1);
  for (int k = 0; k <= n; ++k) {
    HcRecord r;
    r.time_s = k * 1e-3;  // [paper] 1 kHz
    r.arrival_s = r.time_s;
    r.pose_mm_deg = hand(r.time_s);
    out.push_back(r);
  }
  return out;
}

// The breakage of Fig. 8: dropouts (lost samples), freezes (the driver repeats the last pose), late samples and one
// USB stall whose samples arrive in a burst when it ends. Seeded: every run is the same.
std::vector<HcRecord> Break(const std::vector<HcRecord>& clean, double stall_start_s, double stall_length_s) {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<HcRecord> out;
  out.reserve(clean.size());
  double drop_until = -1, freeze_until = -1;
  Vector6d frozen = Vector6d::Zero();
  for (const HcRecord& c : clean) {
    HcRecord r = c;
    if (r.time_s > 0.2 && r.time_s > drop_until && r.time_s > freeze_until) {
      const double x = u(gen);
      if (x < 1.0 / 700) drop_until = r.time_s + 0.010 + 0.050 * u(gen);          // ~1.4 per s, 10–60 ms
      else if (x < 2.0 / 700) { freeze_until = r.time_s + 0.010 + 0.030 * u(gen); frozen = r.pose_mm_deg; }
    }
    if (r.time_s <= drop_until) continue;
    if (r.time_s <= freeze_until) r.pose_mm_deg = frozen;
    if (u(gen) < 0.005) r.arrival_s += 0.002 + 0.003 * u(gen);  // late: overtaken by newer samples
    if (r.time_s >= stall_start_s && r.time_s < stall_start_s + stall_length_s) {
      r.arrival_s = stall_start_s + stall_length_s;  // stalled in the USB stack, then delivered in a burst
    }
    out.push_back(r);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const HcRecord& a, const HcRecord& b) { return a.arrival_s < b.arrival_s; });
  return out;
}

}  // namespace

std::vector<std::string> ScenarioNames() { return {"fig8", "smooth", "slow", "rotation", "clutch"}; }

HcTrajectory MakeScenario(const std::string& name) {
  HcTrajectory t;
  t.name = name;
  if (name == "fig8" || name == "smooth" || name == "clutch") {
    t.clean_records = Sample(&Fig8Hand, 8.5);
    if (name == "smooth") {
      t.description = "hand along x at ~20 mm/s (37.5 mm/s peak), sideways drift, 2 deg twist, tremor; clean 1 kHz";
      t.records = t.clean_records;
    } else {
      t.description = "the same hand with Fig. 8's breakage: dropouts of 10-60 ms, frozen samples, late samples and "
                      "a 200 ms USB stall at 5.0 s";
      t.records = Break(t.clean_records, 5.0, 0.2);
    }
    if (name == "clutch") {
      t.description += "; clutch released from 2.0 s to 3.0 s";
      for (HcRecord& r : t.records) r.clutch = !(r.time_s >= 2.0 && r.time_s < 3.0);
    }
  } else if (name == "slow") {
    t.description = "hand along x at 5 mm/s peak (below the cap), clean: the pure filter delay";
    t.clean_records = Sample(&SlowHand, 13.5);
    t.records = t.clean_records;
  } else if (name == "rotation") {
    t.description = "twist of 10 deg (3.75 deg/s peak) and back (6.25 deg/s), 3 deg tilt, 20 mm drift, with breakage";
    t.clean_records = Sample(&RotationHand, 9.5);
    t.records = Break(t.clean_records, 4.0, 0.15);
  } else {
    std::string known;
    for (const std::string& n : ScenarioNames()) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("--scenario: unknown scenario '" + name + "'; expected one of " + known);
  }
  return t;
}

HcTrajectory ReadHcCsv(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open the HC trajectory file");
  const std::string name = file.filename().string();
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(name + ": empty file; expected a header line");
  const std::vector<std::string> header = SplitCsv(line);
  std::map<std::string, std::size_t> column;
  for (std::size_t i = 0; i < header.size(); ++i) column[header[i]] = i;
  const char* required[] = {"time_s", "x_mm", "y_mm", "z_mm", "roll_deg", "pitch_deg", "yaw_deg"};
  for (const char* key : required) {
    if (!column.count(key)) {
      throw std::runtime_error(name + " line 1: missing column '" + key +
                               "'; expected time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg[,clutch][,arrival_s]");
    }
  }
  const bool has_clutch = column.count("clutch") > 0;
  const bool has_arrival = column.count("arrival_s") > 0;
  HcTrajectory t;
  t.name = name;
  t.description = "recorded HC trajectory " + name;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> cells = SplitCsv(line);
    const std::string where = name + " line " + std::to_string(line_number);
    if (cells.size() < header.size()) {
      throw std::runtime_error(where + ": " + std::to_string(cells.size()) + " cells; expected " +
                               std::to_string(header.size()) + " as in the header");
    }
    HcRecord r;
    r.time_s = ParseCell(cells[column["time_s"]], where, "time_s");
    for (int i = 0; i < 6; ++i) r.pose_mm_deg[i] = ParseCell(cells[column[required[i + 1]]], where, required[i + 1]);
    r.arrival_s = has_arrival ? ParseCell(cells[column["arrival_s"]], where, "arrival_s") : r.time_s;
    if (has_clutch) {
      const double c = ParseCell(cells[column["clutch"]], where, "clutch");
      if (c != 0 && c != 1) throw std::runtime_error(where + ": 'clutch' is '" + cells[column["clutch"]] +
                                                     "'; expected 0 or 1");
      r.clutch = c == 1;
    }
    if (!t.records.empty() && r.time_s < t.records.back().time_s) {
      std::ostringstream msg;
      msg << where << ": 'time_s' " << r.time_s << " is before the previous sample's " << t.records.back().time_s
          << "; samples must be in time order";
      throw std::runtime_error(msg.str());
    }
    if (r.arrival_s < r.time_s) {
      throw std::runtime_error(where + ": 'arrival_s' is before 'time_s'; a sample cannot arrive before it is taken");
    }
    t.records.push_back(r);
  }
  if (t.records.size() < 2) throw std::runtime_error(name + ": fewer than 2 samples; nothing to transfer");
  // The clean reference (for the delay) is the file in time order; delivery follows arrival order.
  t.clean_records = t.records;
  std::stable_sort(t.records.begin(), t.records.end(),
                   [](const HcRecord& a, const HcRecord& b) { return a.arrival_s < b.arrival_s; });
  return t;
}

}  // namespace robossis::transfer
