#include "haptics/transfer/hc_trajectory.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "src/core/csv.h"
#include "src/core/parse.h"
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
  const std::string name = file.filename().string();
  CsvSpec spec;
  spec.columns = {"time_s", "x_mm", "y_mm", "z_mm", "roll_deg", "pitch_deg", "yaw_deg"};
  spec.optional_columns = {"clutch", "arrival_s"};
  spec.any_order = true;
  spec.what = "HC trajectory CSV";
  spec.time_column = "time_s";
  spec.allow_equal_times = true;  // a repeated sample
  spec.min_time = 0.0;
  spec.max_time = kMaxHcTimeS;
  spec.min_rows = 2;
  spec.max_rows = kMaxHcRows;
  spec.max_abs = PoseColumnBounds();
  const NumericCsv csv = ReadNumericCsv(file, spec);
  const char* pose_columns[] = {"x_mm", "y_mm", "z_mm", "roll_deg", "pitch_deg", "yaw_deg"};
  const int time = csv.Column("time_s"), clutch = csv.Column("clutch"), arrival = csv.Column("arrival_s");
  HcTrajectory t;
  t.name = name;
  t.description = "recorded HC trajectory " + name;
  for (const CsvRow& row : csv.rows) {
    const std::string where = file.string() + " line " + std::to_string(row.line);
    HcRecord r;
    r.time_s = row.values[time];
    for (int i = 0; i < 6; ++i) {
      const int column = csv.Column(pose_columns[i]);
      r.pose_mm_deg[i] = row.values[column];
    }
    r.arrival_s = arrival >= 0 ? row.values[arrival] : r.time_s;
    if (clutch >= 0) {
      const double c = row.values[clutch];
      if (c != 0 && c != 1) {
        std::ostringstream msg;
        msg << where << ", column " << clutch + 1 << " (clutch): got '" << c << "'; expected 0 or 1";
        throw std::runtime_error(msg.str());
      }
      r.clutch = c == 1;
    }
    if (!(r.arrival_s >= r.time_s && r.arrival_s <= r.time_s + kMaxHcArrivalDelayS)) {
      std::ostringstream msg;
      msg << where << ", column " << arrival + 1 << " (arrival_s): got '" << r.arrival_s << "'; expected a time in ["
          << r.time_s << ", " << r.time_s + kMaxHcArrivalDelayS << "] (time_s to " << kMaxHcArrivalDelayS
          << " s after it: a sample arrives after it is taken)";
      throw std::runtime_error(msg.str());
    }
    t.records.push_back(r);
  }
  // Repeated stamps are repeated samples; a file of nothing else has no motion in time (the transfer would drop all
  // but one sample as late and move nothing).
  if (t.records.back().time_s == t.records.front().time_s) {
    throw std::runtime_error(file.string() + ": every time_s is " + FormatNumber(t.records.front().time_s) +
                             "; expected samples spread over time (equal stamps are allowed for a repeated sample, "
                             "not for all of them)");
  }
  // The clean reference (for the delay) is the file in time order; delivery follows arrival order.
  t.clean_records = t.records;
  std::stable_sort(t.records.begin(), t.records.end(),
                   [](const HcRecord& a, const HcRecord& b) { return a.arrival_s < b.arrival_s; });
  return t;
}

}  // namespace robossis::transfer
