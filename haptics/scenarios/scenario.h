#pragma once
// Scripted motions of the user's hand for the rendering comparison. The hand target is given in RSR space (the
// commanded ring pose X_FM the hand is heading for); the closed loop maps it to the HC through HcToRsrMap.
//
//   push-edges  the paper's Fig. 11: from 20 mm (6°) inside each workspace edge — beyond the point clouds' reach —
//               push at 10 mm/s (1°/s) to 20 mm (3°) beyond it, hold 1 s, come back. Edges: ±x, ±y, ±z, ±roll,
//               ±pitch, ±yaw about home.
//   explore     the paper's Fig. 12: slide along the translational boundary in the x–y plane at 10 mm/s, pressed
//               8 mm beyond it, then along the tilt boundary at 1°/s, pressed 3° beyond it.
//   strike      a fast strike at 100 mm/s into the +x edge, 25 mm beyond, with a firm grip (pop-through).
//   FILE.csv    replay of a recorded trajectory: header t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg, one row per
//               sample, the RSR pose commanded by the HC (absolute, frame F); the hand follows it.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "haptics/device/device_sim.h"
#include "robot/rsr_model.h"

namespace robossis::haptics {

struct Episode {
  std::string label;
  double duration_s = 0;
  Eigen::Isometry3d X_FM_start = Eigen::Isometry3d::Identity();
  // The RSR pose that the HC's workspace centre maps to during this episode (the clutch of eq. 10), chosen so the
  // hand stays well inside the sigma.7's workspace.
  Eigen::Isometry3d X_FM_anchor = Eigen::Isometry3d::Identity();
  std::function<Eigen::Isometry3d(double t)> target_FM;  // hand target at time t since the episode start
  HandParams hand;
  // A push along one axis from the reference pose (Fig. 11): signed distance to the true boundary along it.
  bool is_push = false;
  bool rotational = false;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  double boundary_s = 0;  // m (or rad) from X_FM_reference along axis where the true boundary is crossed
  Eigen::Isometry3d X_FM_reference = Eigen::Isometry3d::Identity();
};

struct Scenario {
  std::string name;
  std::vector<Episode> episodes;
  double duration_s() const;
};

std::vector<std::string> KnownScenarios();  // push-edges, explore, strike

// A named scenario (fast: fewer edges and shorter paths, for tests and `demo --fast`), or a CSV replay if `name`
// ends in .csv. Throws std::invalid_argument for an unknown name, std::runtime_error for a bad file (naming the
// line and the column).
Scenario MakeScenario(const std::string& name, const robot::RsrModel& model, const HandParams& hand,
                      double strike_stiffness_n_per_m, bool fast);
// A trajectory CSV: header t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg, t_s strictly increasing in
// [0, kMaxTrajectoryTimeS], at least 2 and at most kMaxTrajectoryRows rows (read by the strict src/core/csv.h reader).
// The bounds keep a replay to minutes of simulation, checked before it starts.
inline constexpr double kMaxTrajectoryTimeS = 600.0;
inline constexpr std::size_t kMaxTrajectoryRows = 1'000'000;
Scenario LoadTrajectoryCsv(const std::filesystem::path& file, const HandParams& hand);

// Distance from X_reference along `axis` (translation, m) or about it (world-frame rotation, rad) to the first
// infeasible pose, by marching and bisection; `max` if none.
double ReachAlongAxis(const robot::RsrModel& model, const Eigen::Isometry3d& X_reference, const Eigen::Vector3d& axis,
                      bool rotational, double max);

// Signed distance (m or rad) of X to the true boundary along a push episode's axis, with the OTHER coordinates at
// X's own values: for a translational push, the reach along the axis is taken at X's orientation (the hand may have
// turned); for a rotational push, at X's position. Negative inside. Bisection near the episode's boundary_s.
double SignedDistanceAlongPush(const robot::RsrModel& model, const Episode& episode, const Eigen::Isometry3d& X_FM);

}  // namespace robossis::haptics
