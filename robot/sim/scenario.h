#pragma once
// Scenarios of the Bullet simulation: the paper's Fig. 7 sinusoid in all six DOF (§IV) and a fracture
// reduction against muscle traction. The commanded ring pose goes through the RSR inverse kinematics (eq. 5–8) into
// joint commands for a robot::Follower (the simulation); the ring pose measured in Bullet is compared with the
// commanded one, and the actuator efforts with the Jacobian statics (Q = -J^-T W, eq. 15).

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "robot/rsr_model.h"
#include "robot/sim/bone_fragments.h"
#include "robot/sim/muscle_traction.h"
#include "robot/sim/rsr_simulation.h"
#include "robot/sim/sim_config.h"

namespace robossis::sim {

enum class ScenarioKind { kSinusoid, kReduction };
const char* ToString(ScenarioKind kind);
// "sinusoid" | "reduction"; throws std::invalid_argument naming --scenario otherwise.
ScenarioKind ParseScenarioKind(const std::string& text);

struct ScenarioParams {
  ScenarioKind kind = ScenarioKind::kSinusoid;
  double load_n = 0;         // traction force (paper: up to 517 N); 0 = unloaded
  double load_nm = 0;        // traction torque (paper: up to 74 N·m)
  double duration_s = 30;    // simulated time
  double record_hz = 100;    // trajectory rows per simulated second
  bool gravity = true;
};
// Throws std::invalid_argument naming the parameter (--load-n, --load-nm, --duration-s) and the expected range.
void ValidateScenarioParams(const ScenarioParams& params, const SimConfig& config);

// A commanded ring pose as a function of time.
class PoseTrajectory {
 public:
  virtual ~PoseTrajectory() = default;
  virtual Eigen::Isometry3d Pose(double t) const = 0;
};

// Fig. 7 analogue: every DOF a sinusoid of its own period about a centre pose, amplitudes ramped in smoothly.
class SinusoidTrajectory final : public PoseTrajectory {
 public:
  SinusoidTrajectory(const Eigen::Isometry3d& X_FM_center, const SinusoidConfig& config);
  Eigen::Isometry3d Pose(double t) const override;
  const Eigen::Isometry3d& center() const { return center_; }

 private:
  Eigen::Isometry3d center_;
  SinusoidConfig config_;
};

// Fracture reduction: displaced → distracted (beyond full length) → aligned at that length → approach to the final
// gap → hold. Each phase is a minimum-jerk move of the distal fragment about the fracture site.
class ReductionTrajectory final : public PoseTrajectory {
 public:
  ReductionTrajectory(const Eigen::Isometry3d& X_FM_aligned, const Eigen::Vector3d& site_F,
                      const ReductionConfig& config, double duration_s);
  Eigen::Isometry3d Pose(double t) const override;
  Eigen::Isometry3d Waypoint(int k) const;  // 0 displaced, 1 distracted, 2 aligned + clearance, 3 final

 private:
  Eigen::Isometry3d X_aligned_;
  Eigen::Vector3d site_;
  ReductionConfig config_;
  double duration_s_;
  std::array<Eigen::Vector3d, 4> offset_{};
  std::array<Eigen::Quaterniond, 4> rotation_{};
};

// One recorded row.
struct ScenarioSample {
  double time_s = 0;
  Vector6d pose_cmd_mm_deg = Vector6d::Zero();
  Vector6d pose_meas_mm_deg = Vector6d::Zero();
  double translation_error_m = 0;
  double rotation_error_rad = 0;
  robot::RsrJointVector q_cmd = robot::RsrJointVector::Zero();
  robot::RsrJointVector q_meas = robot::RsrJointVector::Zero();
  robot::RsrJointVector effort = robot::RsrJointVector::Zero();   // simulated drives
  robot::RsrJointVector effort_statics = robot::RsrJointVector::Zero();  // -J^-T W at the measured pose
  double traction_axial_n = 0;
  double traction_torque_nm = 0;
  double penetration_m = 0;
  SimStepStatus status = SimStepStatus::kOk;
};

struct ScenarioSummary {
  double max_translation_error_mm = 0;
  double mean_translation_error_mm = 0;
  double max_rotation_error_deg = 0;
  double mean_rotation_error_deg = 0;
  double max_actuator_force_n = 0;
  double max_actuator_torque_nm = 0;
  double realtime_factor = 0;  // simulated time / CPU time of the stepping thread (Command + Step + State)
  // Beyond the headline keys:
  double realtime_factor_wall = 0;  // simulated time / wall-clock time (lower when other processes share the core)
  double simulated_s = 0;
  double wall_s = 0;
  double cpu_s = 0;
  long steps = 0;
  bool actuator_limit_reached = false;
  long actuator_limit_steps = 0;
  double first_actuator_limit_time_s = -1;
  std::string actuator_limit_message;  // which drive, when; empty if none
  bool joint_limit_reached = false;
  double max_spherical_cone_deg = 0;
  bool spherical_limit_exceeded = false;
  double max_penetration_mm = 0;
  double penetration_tolerance_mm = 0;
  long contact_steps = 0;
  double peak_traction_n = 0;
  double peak_traction_torque_nm = 0;
  // Statics check (J^-T): max over steps without contact of max_i|Q_sim - Q_statics| / max_i|Q_statics| (a floor
  // of 1% of the drive limit keeps unloaded runs meaningful).
  double statics_linear_rel_error = 0;
  double statics_rotary_rel_error = 0;
  long statics_steps = 0;
  double max_loop_error_m = 0;
  bool unstable = false;
  double ring_mass_kg = 0;
};

struct ScenarioResult {
  ScenarioParams params;
  std::vector<ScenarioSample> samples;
  ScenarioSummary summary;
};

// The generalized force (a wrench at P, in F) of gravity on the three arms' moving parts, by the principle of
// virtual work: -dV/dxi of their potential energy, with xi the ring twist (central differences). Used with the
// ring's own weight and the traction in the J^-T statics of the whole mechanism.
Vector6d ArmGravityWrench(const robot::RsrModel& model, const MassConfig& masses, const Eigen::Vector3d& g_F,
                          const Eigen::Isometry3d& X_FM);

// The pose the scenario starts in, its trajectory and its calibrated traction (exposed for the tests).
struct ScenarioSetup {
  std::unique_ptr<PoseTrajectory> trajectory;
  MuscleTraction traction;
};
ScenarioSetup MakeScenarioSetup(const robot::RsrModel& model, const SimConfig& config, const BoneFragments& fragments,
                                const ScenarioParams& params);

// Runs one scenario. Throws std::invalid_argument for bad parameters or a trajectory that leaves the workspace
// (naming the time and the violated limit). `progress` (optional) gets the fraction done.
ScenarioResult RunScenario(const robot::RsrModel& model, const SimConfig& config, const BoneFragments& fragments,
                           const ScenarioParams& params, const std::function<void(double)>& progress = {});

// The trajectory as CSV (mm, deg, N, N·m; one row per recorded sample, header first).
std::string TrajectoryCsv(const ScenarioResult& result);

}  // namespace robossis::sim
