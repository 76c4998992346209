#pragma once
// The follower (RSR) as the rest of the workbench sees it: a drive with a life cycle (enable, disable, home, fault
// reset), joint commands in, measured joints, pose, efforts and a fault code out. Served by the Bullet simulation,
// the pulse recorder and the real motor drives (LinuxCNC HAL), all behind this one interface.
//
// What a driver needs, and why each call is here: drives are powered (Enable) and unpowered (Disable, which holds
// the brakes or the current position); incremental encoders and open-loop steppers need a reference (Home); a latched
// drive fault needs an explicit acknowledgement (ResetFault).
//
// Homing is the operator's explicit action, never a side effect of Enable (the follower's state machine refuses an
// enable while unhomed). What Home() means depends on MeasuresJoints(): a back end that measures its joints'
// absolute position (the Bullet simulation's physics, the pulse recorder whose command is its position, an absolute
// encoder) references itself from that measurement and reports homed from its start; one that does not (step/
// direction drives counting their own steps) starts unhomed after every start, and its Home() is the operator's
// declaration "the robot stands at its home pose now". Service() is the back end's periodic work at the follower's servo rate
// (exchange HAL pins, take the simulated robot's newest measurement), called by the follower unit after Command().

#include <cstdint>

#include <Eigen/Geometry>

#include "robot/rsr_kinematics.h"

namespace robossis::rt {
class PeriodicTask;
}  // namespace robossis::rt

namespace robossis::robot {

// A set-point for the actuated joints (eq. 13 order), with the velocity feed-forward of eq. 15.
struct RsrJointCommand {
  double time_s = 0;
  RsrJointVector q = RsrJointVector::Zero();
  RsrJointVector q_dot = RsrJointVector::Zero();
};

// The back end's fault condition. The follower unit's state machine latches it (FAULT until a reset); a back end
// whose hardware latches its own faults clears them in ResetFault().
enum class FollowerFault : std::uint8_t {
  kNone,
  kJointLimit,      // a measured joint reached a stroke, rotary or spherical-cone limit
  kDrive,           // a drive reported a fault (or hit its force/torque limit, in the simulation)
  kFeedbackLost,    // no position feedback from the drives (a dead HAL component, a lost link to the drives)
  kFollowingError,  // the measured joints left the command by more than the back end tolerates
  kUnstable,        // the simulation diverged
  kExternal,        // a fault input raised outside the program (the HAL fault pin, an external E-stop chain)
};
const char* ToString(FollowerFault fault);

// What the follower measures.
struct RsrFollowerState {
  double time_s = 0;  // when this was measured, on the back end's clock (the simulation: its physics time)
  RsrJointVector q = RsrJointVector::Zero();                // actuated joints, eq. 13 order
  Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();  // moving-ring pose (measured, or FK of q)
  RsrJointVector effort = RsrJointVector::Zero();           // rotary torques (N·m), linear forces (N)
  bool enabled = false;                                     // drives powered and following commands
  bool homed = false;                                       // joint positions referenced
  FollowerFault fault = FollowerFault::kNone;               // the back end's current fault condition
  // The external wrench on the ring over the step that made this measurement, [force at P; moment about P] in F
  // (the frame and point of the statics, and of the wrench the follower estimates from the efforts): the load the
  // efforts above held. Only a simulation knows it, because it applies that load itself; hardware leaves it unknown.
  bool true_wrench_known = false;
  Vector6d true_wrench_F = Vector6d::Zero();
  bool faulted() const noexcept { return fault != FollowerFault::kNone; }
};

// Real-time interface: every call is allocation-free and never throws.
class Follower {
 public:
  virtual ~Follower() = default;
  // Powers the drives; false (and nothing changes) while a fault is latched or the back end refuses.
  virtual bool Enable() noexcept = 0;
  // Unpowers the drives; they hold where they are.
  virtual void Disable() noexcept = 0;
  // References the joints: from the measurement where MeasuresJoints(), else at the present position, which the
  // operator declares to be the home pose. False (nothing changes) while the back end cannot reference yet.
  virtual bool Home() noexcept = 0;
  // True if the back end measures its joints' absolute position (then it is homed from its start); false for
  // open-loop drives, whose position is only the count of the steps they were sent (homed by the operator).
  virtual bool MeasuresJoints() const noexcept = 0;
  // Clears the back end's latched fault if its cause is gone; false otherwise. The drives stay disabled.
  virtual bool ResetFault() noexcept = 0;
  // The joint set-point; ignored unless enabled.
  virtual void Command(const RsrJointCommand& command) noexcept = 0;
  // Periodic work of the back end up to runtime time now_s (physics steps, pin exchange).
  virtual void Service(double now_s) noexcept = 0;
  virtual RsrFollowerState State() const noexcept = 0;

  // A back end whose robot runs beside the controller at a rate of its own (the simulated robot) names its task
  // here; the runtime ticks it on a loop of its own (rt::RunRealTime, rt::RunSimulated), as real drives and a real
  // robot run beside the control loop. Back ends without one (hardware, the pulse recorder) return no task.
  struct Plant {
    rt::PeriodicTask* task = nullptr;
    std::int64_t period_ns = 0;
  };
  virtual Plant plant() noexcept { return {}; }
};

}  // namespace robossis::robot
