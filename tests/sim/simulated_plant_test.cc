// The Bullet simulation as a plant on a loop of its own (sim::SimulatedPlant): the follower side answers at once and
// the robot moves only on the plant's ticks; a stall of the plant is made up along the commands, not jumped; a fault
// latches until acknowledged; both sides allocate nothing.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>

#include "robot/rsr_kinematics.h"
#include "robot/sim/simulated_plant.h"
#include "sim_fixture.h"
#include "tests/support/alloc_counter.h"

namespace robossis::sim {
namespace {

using testing::Data;

constexpr std::int64_t kTickNs = 100'000;  // the follower unit's 10 kHz tick
constexpr double kSpeedMps = 0.05;         // the ring's commanded speed along z

Eigen::Isometry3d Home() { return Data().model.geometry().X_FM_home; }

std::unique_ptr<SimulatedPlant> MakePlant(double max_catch_up_s = kPlantMaxCatchUpS) {
  SimOptions options;
  options.with_bone = false;
  options.with_traction = false;
  return std::make_unique<SimulatedPlant>(
      std::make_unique<RsrSimulation>(Data().model, Data().config, nullptr, nullptr, Home(), options),
      max_catch_up_s);
}

// The joints of the ring moved kSpeedMps · t along z from home, with their rates, stamped t.
robot::RsrJointCommand RampCommand(double t_s) {
  const auto joints = [](double t) {
    Eigen::Isometry3d X = Home();
    X.translation().z() += kSpeedMps * t;
    const robot::RsrIkResult ik = robot::CalcInverseKinematics(Data().model, X);
    EXPECT_TRUE(ik.feasible);
    return robot::RsrJointVector(ik.joints.actuated());
  };
  robot::RsrJointCommand command;
  command.time_s = t_s;
  command.q = joints(t_s);
  command.q_dot = (joints(t_s + 1e-4) - command.q) / 1e-4;
  return command;
}

struct RampRun {
  robot::RsrFollowerState last;
  double max_speed_mps = 0;  // over the plant's measurement times
  bool any_fault = false;
};

// Follower ticks at 10 kHz commanding the ramp for duration_s; the plant ticks every 1 ms unless `stalled` says
// its thread was not running at that instant.
RampRun DriveRamp(SimulatedPlant& plant, double duration_s, const std::function<bool(std::int64_t)>& stalled) {
  RampRun run;
  robot::RsrFollowerState previous = plant.State();
  for (std::int64_t t = kTickNs; t <= std::llround(duration_s * 1e9); t += kTickNs) {
    const double t_s = 1e-9 * static_cast<double>(t);
    plant.Command(RampCommand(t_s));
    plant.Service(t_s);
    const robot::RsrFollowerState s = plant.State();
    run.any_fault = run.any_fault || s.faulted();
    if (s.time_s > previous.time_s) {
      const double v = (s.X_FM.translation() - previous.X_FM.translation()).norm() / (s.time_s - previous.time_s);
      run.max_speed_mps = std::max(run.max_speed_mps, v);
      previous = s;
    }
    if (t % plant.period_ns() == 0 && !stalled(t)) plant.Tick(t);
  }
  run.last = plant.State();
  return run;
}

TEST(SimulatedPlantTest, TheRobotMovesOnlyOnThePlantsOwnTicks) {
  auto plant = MakePlant();
  const robot::RsrFollowerState start = plant->State();
  plant->Command(RampCommand(0.01));
  plant->Service(0.01);
  EXPECT_EQ(plant->State().time_s, start.time_s) << "Service() must not step the physics";
  EXPECT_EQ(plant->plant().task, plant.get());
  EXPECT_EQ(plant->plant().period_ns, 1'000'000);
  plant->Tick(10'000'000);
  plant->Service(0.01);
  EXPECT_NEAR(plant->State().time_s, 0.01, 1e-12);
  EXPECT_GT(plant->State().X_FM.translation().z(), start.X_FM.translation().z());
}

TEST(SimulatedPlantTest, TheDrivesEnableAtOnceOnTheFollowerSideAndHoldWhenDisabled) {
  auto plant = MakePlant();
  plant->Disable();
  EXPECT_FALSE(plant->State().enabled);
  const double z0 = plant->State().X_FM.translation().z();
  plant->Command(RampCommand(0.01));  // ignored: the drives are off
  plant->Tick(10'000'000);
  plant->Service(0.01);
  EXPECT_NEAR(plant->State().X_FM.translation().z(), z0, 1e-6);
  ASSERT_TRUE(plant->Enable());
  EXPECT_TRUE(plant->State().enabled);
}

TEST(SimulatedPlantTest, AStallOfThePlantIsMadeUpAlongTheCommandsNotJumped) {
  // The plant's thread misses 100 ms; the follower keeps commanding the ramp at 10 kHz meanwhile. The late tick
  // steps the missed physics with the drives following the commands at their own times: no drive fault, the speed
  // over the measurements stays the commanded one, and the robot ends where an unstalled run ends.
  auto steady = MakePlant();
  const RampRun reference = DriveRamp(*steady, 0.3, [](std::int64_t) { return false; });
  auto stalled = MakePlant();
  const RampRun run = DriveRamp(*stalled, 0.3, [](std::int64_t t) { return t > 100'000'000 && t < 200'000'000; });
  EXPECT_FALSE(reference.any_fault);
  EXPECT_FALSE(run.any_fault);
  EXPECT_LE(run.max_speed_mps, 1.01 * kSpeedMps);
  EXPECT_LE(reference.max_speed_mps, 1.01 * kSpeedMps);
  EXPECT_NEAR(run.last.time_s, reference.last.time_s, 1e-9);
  EXPECT_LT((run.last.X_FM.translation() - reference.last.X_FM.translation()).norm(), 1e-5);
  EXPECT_EQ(stalled->skipped_s(), 0.0);
}

TEST(SimulatedPlantTest, ACommandReachedForInOneStepFaultsTheDrive) {
  // What the catch-up avoids: the newest command of a 100 ms stall (5 mm of ramp) asked for in one physics step.
  SimOptions options;
  options.with_bone = false;
  options.with_traction = false;
  RsrSimulation simulation(Data().model, Data().config, nullptr, nullptr, Home(), options);
  robot::RsrJointCommand command = RampCommand(0.1);
  command.time_s = simulation.time_s() + simulation.step_s();
  simulation.Command(command);
  EXPECT_EQ(simulation.Step(), SimStepStatus::kActuatorLimit);
  EXPECT_EQ(simulation.State().fault, robot::FollowerFault::kDrive);
}

TEST(SimulatedPlantTest, FurtherBehindThanTheCatchUpLimitTheExcessIsSkipped) {
  auto plant = MakePlant(0.05);
  plant->Tick(2'000'000'000);  // 2 s after the last step: 1.95 s skipped, 50 steps made up
  plant->Service(2.0);
  EXPECT_NEAR(plant->skipped_s(), 1.95, 1e-6);
  EXPECT_NEAR(plant->State().time_s, 2.0, 1e-9);
  EXPECT_FALSE(plant->State().faulted());
}

TEST(SimulatedPlantTest, AFaultLatchesUntilResetAndThenTheDrivesEnableAgain) {
  auto plant = MakePlant();
  robot::RsrJointCommand jump = RampCommand(0.1);
  jump.time_s = 0.001;
  plant->Command(jump);
  plant->Tick(1'000'000);
  plant->Service(0.001);
  ASSERT_EQ(plant->State().fault, robot::FollowerFault::kDrive);
  EXPECT_FALSE(plant->State().enabled);
  EXPECT_FALSE(plant->Enable()) << "refused while the fault is latched";
  plant->Disable();
  plant->Tick(2'000'000);  // the drives hold: the step is clean, the latch stays
  plant->Service(0.002);
  EXPECT_EQ(plant->State().fault, robot::FollowerFault::kDrive);
  ASSERT_TRUE(plant->ResetFault());
  EXPECT_FALSE(plant->State().faulted());
  ASSERT_TRUE(plant->Enable());
  plant->Tick(3'000'000);
  plant->Service(0.003);
  EXPECT_FALSE(plant->State().faulted());
  EXPECT_TRUE(plant->State().enabled);
}

TEST(SimulatedPlantTest, BothSidesAllocateNothing) {
  auto plant = MakePlant();
  robot::Follower& follower = *plant;
  for (std::int64_t t = 1'000'000; t <= 20'000'000; t += 1'000'000) plant->Tick(t);  // Bullet sizes its buffers
  const robot::RsrJointCommand hold = RampCommand(0.0);
  robossis::testing::AllocationCounter counter;
  for (std::int64_t t = 21'000'000; t <= 60'000'000; t += kTickNs) {
    robot::RsrJointCommand command = hold;
    command.time_s = 1e-9 * static_cast<double>(t);
    follower.Command(command);
    follower.Service(command.time_s);
    ASSERT_FALSE(follower.State().faulted());
    if (t % plant->period_ns() == 0) plant->Tick(t);
  }
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace robossis::sim
