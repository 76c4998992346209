#pragma once
// The Bullet simulation as a robot beside the controller: its physics steps on a loop of its own, at its own rate
// (sim.yaml's physics.step_hz), never inside the follower unit's 10 kHz tick, as real drives and a real robot run
// beside a real control loop. The follower unit reaches it through robot::Follower as it reaches any back end.
//
// The two sides meet only through rt::Snapshot records and atomics:
//   follower side (the follower unit's thread): Enable / Disable / ResetFault / Command / Service / State. The
//     drives' enable and the fault latch live here, as a drive's enable pin and its fault acknowledgement do, so
//     State() answers at once; Command() publishes the newest joint command; Service() takes the plant's newest
//     measurement and latches a fault it reports.
//   plant side (its loop): Tick() applies the enable, takes the newest command and steps the physics up to the
//     tick's time. After a late tick (a stall of its thread) the physics makes up the missed steps in that one tick,
//     the drives following the commands at their own times (RsrSimulation::DriveTargetAt), so that a stall of the
//     simulation is not a jump of the robot. Further behind than max_catch_up_s, the physics skips the excess
//     (nothing moves meanwhile; counted in skipped_s()).
//
// Real time: every call on both sides is noexcept, allocation-free and lock-free (tests/sim/simulated_plant_test.cc).

#include <atomic>
#include <cstdint>
#include <memory>

#include "robot/follower.h"
#include "robot/sim/rsr_simulation.h"
#include "src/core/rt/periodic_task.h"
#include "src/core/rt/snapshot.h"

namespace robossis::sim {

// How far behind its clock the physics makes up its steps [assumed]: half a second of 1 kHz steps is ~30 ms of
// CPU on this machine's 2 cores, and a stall that long already trips the follower's watchdog.
inline constexpr double kPlantMaxCatchUpS = 0.5;

class SimulatedPlant final : public robot::Follower, public rt::PeriodicTask {
 public:
  // Takes the simulation as it is (enabled or not, at its time and pose); its physics time must be on the
  // runtime clock the plant's loop ticks on. Throws std::invalid_argument on a null simulation.
  explicit SimulatedPlant(std::unique_ptr<RsrSimulation> simulation, double max_catch_up_s = kPlantMaxCatchUpS);

  // robot::Follower (the follower unit's thread).
  bool Enable() noexcept override;
  void Disable() noexcept override;
  bool Home() noexcept override { return true; }  // absolute feedback: homed from the start
  bool MeasuresJoints() const noexcept override { return true; }
  bool ResetFault() noexcept override;
  void Command(const robot::RsrJointCommand& command) noexcept override;
  void Service(double now_s) noexcept override;
  robot::RsrFollowerState State() const noexcept override;
  Plant plant() noexcept override { return {this, period_ns_}; }

  // rt::PeriodicTask (the plant's loop): the physics up to now_ns.
  void Tick(std::int64_t now_ns) noexcept override;

  std::int64_t period_ns() const noexcept { return period_ns_; }
  // Simulated time skipped, not stepped, because the physics fell more than max_catch_up_s behind (any thread).
  double skipped_s() const noexcept { return 1e-9 * static_cast<double>(skipped_ns_.load(std::memory_order_relaxed)); }

 private:
  std::unique_ptr<RsrSimulation> simulation_;
  double max_catch_up_s_;
  std::int64_t period_ns_;
  // Between the sides.
  rt::Snapshot<robot::RsrJointCommand> command_;
  rt::Snapshot<robot::RsrFollowerState> measured_;
  std::atomic<bool> enable_wanted_;
  std::atomic<std::int64_t> skipped_ns_{0};
  // Follower side.
  bool enabled_;
  robot::FollowerFault latched_ = robot::FollowerFault::kNone;
  robot::RsrFollowerState state_;
  std::uint64_t measured_version_ = 0;
  // Plant side.
  bool plant_enabled_;
  std::uint64_t command_version_ = 0;
};

}  // namespace robossis::sim
