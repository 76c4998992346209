#pragma once
// Recorded or scripted HC trajectories for the motion transfer: the CSV format, the built-in scenarios (a hand at
// ~20 mm/s with the "breakage" of Fig. 8), and the arrival model of a USB link (dropouts, repeats, late samples,
// stalls). Not real-time code.

#include <filesystem>
#include <string>
#include <vector>

#include "haptics/transfer/incremental_mapping.h"
#include "src/core/pose.h"

namespace robossis::transfer {

// One row: the hand's true time stamp, when the sample reached the controller, the pose, and the clutch.
struct HcRecord {
  double time_s = 0;
  double arrival_s = 0;  // >= time_s; samples are delivered in arrival order
  Vector6d pose_mm_deg = Vector6d::Zero();  // x_mm, y_mm, z_mm, roll_deg, pitch_deg, yaw_deg (HC base frame)
  bool clutch = true;
  HcSample ToSample() const;
};

struct HcTrajectory {
  std::string name;
  std::string description;
  std::vector<HcRecord> records;        // in arrival order, as delivered (with breakage)
  std::vector<HcRecord> clean_records;  // the hand's true motion at 1 kHz (for the delay), in time order
};

// CSV with a header: time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg[,clutch][,arrival_s] (any column order; an
// unknown or repeated column is an error), read by the strict src/core/csv.h reader: exactly one cell per column,
// time_s in [0, kMaxHcTimeS] and never decreasing (equal stamps are allowed: a repeated sample), arrival_s within
// kMaxHcArrivalDelayS after time_s, |x|,|y|,|z| <= kMaxEdgePositionMm, |angles| <= kMaxEdgeAngleDeg, 2 to kMaxHcRows
// rows. Throws std::runtime_error "FILE line N, column C (name): got 'V'; expected ...". The bounds keep a
// transfer run to minutes, checked before it starts.
inline constexpr double kMaxHcTimeS = 600.0;
inline constexpr double kMaxHcArrivalDelayS = 10.0;
inline constexpr std::size_t kMaxHcRows = 1'000'000;
HcTrajectory ReadHcCsv(const std::filesystem::path& file);

// Built-in scenarios: "fig8" (a hand at ~20 mm/s with dropouts, repeats, late samples and a USB stall, as in Fig. 8),
// "smooth" (the same hand motion, clean), "slow" (5 mm/s, below the cap), "rotation" (3 deg/s twist with a drift),
// "clutch" (fig8 with a clutch release and re-engage). Throws std::invalid_argument for an unknown name.
HcTrajectory MakeScenario(const std::string& name);
std::vector<std::string> ScenarioNames();

}  // namespace robossis::transfer
