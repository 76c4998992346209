#pragma once
// The RSR in Bullet (double precision, Featherstone multibody): fixed ring, three arms (active rotary joint theta_i,
// passive joint psi_i, prismatic actuator d_i), the spherical joints closing the loop on the moving ring, which
// carries the distal femur fragment against muscle traction and contact with the fixed proximal fragment.
//
// Served through robot::Follower: joint commands in (eq. 13 order), measured joints, ring pose and actuator efforts
// out, and with each measurement the external wrench the simulation applied to the ring over its step (the muscles':
// RsrFollowerState::true_wrench_F, what a real robot cannot report). No Bullet type appears in this header: Bullet's
// raw new/delete objects live in the implementation, wrapped once, and everything is converted to Eigen there.
//
// Real-time: Command(), State() and Step() are noexcept and do not throw; Command() and State() never allocate.

#include <memory>
#include <optional>

#include "robot/follower.h"
#include "robot/rsr_model.h"
#include "robot/sim/bone_fragments.h"
#include "robot/sim/muscle_traction.h"
#include "robot/sim/sim_config.h"

namespace robossis::sim {

// A step counts as due this long before its end [assumed]: above the rounding of the summed step times (an hour of
// 1 kHz steps drifts by at most ~1.5 µs, typically by ns), and short enough that the physics is never ahead of its
// clock by more than 0.1 µm of motion at 100 mm/s.
inline constexpr double kStepDueToleranceS = 1e-6;

enum class SimStepStatus { kOk, kActuatorLimit, kJointLimit, kUnstable };
const char* ToString(SimStepStatus status);

// Per-step diagnostics beyond the follower state.
struct SimDiagnostics {
  double time_s = 0;
  TractionSample traction;                 // the wrench the muscles applied this step
  Eigen::Vector3d v_P_F = Eigen::Vector3d::Zero();  // measured ring velocity (at P) and angular velocity, in F
  Eigen::Vector3d w_F = Eigen::Vector3d::Zero();
  bool linear_saturated[3] = {false, false, false};   // the drive hit its force limit this step
  bool rotary_saturated[3] = {false, false, false};   // the drive hit its torque limit this step
  bool joint_limit_active = false;         // a stroke or rotary end stop carried load this step
  double max_penetration_m = 0;            // deepest fragment interpenetration this step (0 if apart)
  int contact_points = 0;
  bool contact_loaded = false;             // the fragments touched or their contact carried an impulse this step
  double max_loop_error_m = 0;             // largest gap at the three spherical joints (loop closure)
  double max_cone_rad = 0;                 // largest spherical-joint cone angle (limit: model limits)
};

struct SimOptions {
  bool with_bone = true;             // fragments (mass on the ring, contact) present
  bool with_traction = true;         // muscle elements applied
  bool gravity = true;               // config.physics.gravity_mps2, else none
};

class RsrSimulation final : public robot::Follower {
 public:
  // Builds the mechanism at X_FM_start (must be feasible), at rest, with the drives holding it there.
  // `traction` is copied (already calibrated); pass nullptr for none. Throws std::invalid_argument on an infeasible
  // start pose and std::runtime_error if the Bullet model does not reproduce the kinematics.
  RsrSimulation(const robot::RsrModel& model, const SimConfig& config, const BoneFragments* fragments,
                const MuscleTraction* traction, const Eigen::Isometry3d& X_FM_start, const SimOptions& options = {});
  ~RsrSimulation() override;
  RsrSimulation(const RsrSimulation&) = delete;
  RsrSimulation& operator=(const RsrSimulation&) = delete;

  // robot::Follower. The simulation starts enabled and homed at its start pose (the offline studies command it
  // directly); disabled, its drives hold the joints where they are. The command is extrapolated with its velocity
  // to the end of each step (at most config.physics.command_extrapolation_max_s past its time stamp); a step that
  // ends before the newest command's time stamp (the physics catching up after a late step) targets the straight
  // path from the previous step's target to that command, at the step's time. Service() makes the steps that end
  // by now_s (never one ending later: the physics does not run ahead of its clock). The fault code is the last
  // step's condition, or after Service() the first fault of the steps it made.
  bool Enable() noexcept override;
  void Disable() noexcept override;
  bool Home() noexcept override { return true; }  // the physics' joint positions: homed from the start
  bool MeasuresJoints() const noexcept override { return true; }
  bool ResetFault() noexcept override;
  void Command(const robot::RsrJointCommand& command) noexcept override;
  void Service(double now_s) noexcept override;
  robot::RsrFollowerState State() const noexcept override;

  // Advances the physics by one step of 1/step_hz.
  SimStepStatus Step() noexcept;
  // Moves the simulated time forward to time_s without stepping the physics (nothing moves meanwhile, velocities
  // kept): for a simulation that fell too far behind real time to catch up. Earlier times are ignored.
  void SkipTo(double time_s) noexcept;

  const SimDiagnostics& diagnostics() const { return diagnostics_; }
  double time_s() const { return time_s_; }
  double step_s() const { return step_s_; }
  double ring_mass_kg() const;  // ring + distal fragment
  Eigen::Vector3d ring_com_M() const;  // its centre of mass, in M

 private:
  struct Bullet;  // every Bullet object, owned (RAII)
  std::unique_ptr<Bullet> bullet_;
  robot::RsrModel model_;
  SimConfig config_;
  SimOptions options_;
  std::optional<MuscleTraction> traction_;
  double step_s_ = 1e-3;
  double time_s_ = 0;
  robot::RsrJointCommand command_;  // the newest command
  robot::RsrJointCommand target_;   // the drives' target at the end of the last step
  robot::RsrFollowerState state_;
  SimDiagnostics diagnostics_;
  void Measure() noexcept;
  robot::RsrJointCommand DriveTargetAt(double t_s) const noexcept;
};

}  // namespace robossis::sim
