// The HAL follower against a real LinuxCNC HAL: the shipped software-stepgen file loaded, the follower as its
// userspace component, driven by the project's actuation (eq. 15-17) on an eq. 9 move. Each test starts HAL and
// stops it (HalSession), even when it fails; the follower is destroyed first (halrun -U would signal it).

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <tuple>

#include <gtest/gtest.h>

#include "haptics/transfer/timed_move.h"
#include "robot/actuation/actuator.h"
#include "robot/drivers/hal_follower.h"
#include "src/core/config.h"
#include "robot/drivers/hal_names.h"
#include "src/core/rt/clock.h"
#include "src/core/units.h"
#include "tests/drivers/hal_session.h"
#include "tests/drivers/servo_thread.h"
#include "tests/support/alloc_counter.h"

namespace robossis::drivers {
namespace {

using robot::FollowerFault;
using testing::HalSession;
using testing::ServoThread;

std::filesystem::path DataDir() { return DefaultDataDir(); }
HalConfig LoadHalConfig() { return HalConfig::FromYaml(DataDir() / "config" / "hal.yaml"); }
actuation::ActuationConfig LoadActuationConfig() {
  return actuation::ActuationConfig::FromYaml(DataDir() / "config" / "actuation.yaml");
}

// Homes and enables once the servo thread has shown that HAL runs (Home() refuses until the feedback is alive).
void HomeAndEnable(ServoThread& servo) {
  ASSERT_TRUE(ServoThread::Eventually([&] { return servo.With([](HalFollower& f) { return f.Home(); }); }));
  ASSERT_TRUE(servo.With([](HalFollower& f) { return f.Enable(); }));
}

bool StepgenEnabled(int motor) { return HalSession::GetBit("stepgen." + std::to_string(motor) + ".enable"); }

robot::RsrFollowerState StateOf(ServoThread& servo) {
  return servo.With([](HalFollower& f) { return f.State(); });
}

class HalFollowerTest : public ::testing::Test {
 protected:
  void SetUp() override { session_ = std::make_unique<HalSession>(DataDir() / "hal" / "robossis-stepgen.hal"); }
  void TearDown() override { session_.reset(); }

  const robot::RsrModel model_ = robot::RsrModel::Default();
  const rt::MonotonicClock clock_;
  std::unique_ptr<HalSession> session_;
};

TEST_F(HalFollowerTest, StepCountsMatchEq17AndFeedbackFollowsTheCommand) {
  const actuation::ActuationConfig act_config = LoadActuationConfig();
  HalFollower follower(model_, LoadHalConfig());

  // An eq. 9 move of all six DOF: every motor moves by more than 50 steps.
  transfer::TimedMoveRequest request;
  request.delta_p_F = Eigen::Vector3d(MmToM(-8), MmToM(-6), MmToM(10));
  request.delta_rot_F = Eigen::Vector3d(0.10, -0.12, 0.08);
  request.start_time_s = 0.1;
  const Eigen::Isometry3d& X_home = model_.geometry().X_FM_home;
  const transfer::TimedMove move(X_home, request, 2.0);
  actuation::Actuator actuator(model_, act_config, X_home, 0);
  // The actuation's tick: transfer.yaml's rate, its one place.
  const double dt =
      1.0 / transfer::TransferConfig::FromYaml(DataDir() / "config" / "transfer.yaml").rates.actuation_rate_hz;

  std::atomic<double> t0{std::numeric_limits<double>::infinity()};
  std::int64_t tick = 0;
  std::array<double, actuation::kNumMotors> worst_lag_steps{};  // |feedback - command| during the move, steps
  ServoThread servo(follower, clock_, [&](HalFollower& f, double now) {
    // The 10 kHz actuation ticks up to now (the follower unit runs them on its own thread).
    for (; (tick + 1) * dt <= now - t0; ++tick) {
      const transfer::RsrSetPoint sp = move.Evaluate((tick + 1) * dt);
      actuator.Tick((tick + 1) * dt, sp.X_FM, sp.velocity);
    }
    if (tick == 0) return;  // the move has not started: nothing to command yet
    actuation::CommandFollower(actuator.output(), f);
    for (int m = 0; m < actuation::kNumMotors; ++m) {
      const double lag = std::abs(f.State().q[m] - actuator.q()[m]) * act_config.motors[m].steps_per_unit;
      worst_lag_steps[m] = std::max(worst_lag_steps[m], lag);
    }
  });
  HomeAndEnable(servo);
  t0 = clock_.NowS();
  // The move played to its end and every stepgen at its eq. 17 count: waited for, since a loaded machine makes the
  // move's wall-clock time longer, never its outcome.
  const auto at_the_end = [&] {
    const auto [played, steps] = servo.With(
        [&](HalFollower&) { return std::make_pair(tick * dt >= move.end_time_s(), actuator.output().steps); });
    if (!played) return false;
    for (int m = 0; m < actuation::kNumMotors; ++m)
      if (std::abs(HalSession::GetNumber("stepgen." + std::to_string(m) + ".counts") - steps[m]) > 1.0) return false;
    return true;
  };
  ServoThread::Eventually(at_the_end, 60);

  const robot::RsrFollowerState state = StateOf(servo);
  ASSERT_EQ(state.fault, FollowerFault::kNone) << ToString(state.fault);
  ASSERT_TRUE(state.enabled);
  const auto [steps, q_cmd, lag] = servo.With(
      [&](HalFollower&) { return std::make_tuple(actuator.output().steps, actuator.q(), worst_lag_steps); });
  for (int m = 0; m < actuation::kNumMotors; ++m) {
    EXPECT_GT(std::abs(steps[m]), 50) << "motor " << m << " barely moved: the move tests nothing";
    RecordProperty("eq17_steps_motor_" + std::to_string(m), std::to_string(steps[m]));
    const double counts = HalSession::GetNumber("stepgen." + std::to_string(m) + ".counts");
    EXPECT_LE(std::abs(counts - static_cast<double>(steps[m])), 1.0)
        << "motor " << m << ": LinuxCNC " << counts << " steps, eq. 17 " << steps[m];
    // The position feedback follows the command: the measured joint is the commanded one within a step.
    EXPECT_LE(std::abs(state.q[m] - q_cmd[m]) * act_config.motors[m].steps_per_unit, 1.0) << "motor " << m;
    // And it followed during the move: a coarse bound (half of the motor's motion), not a timing one.
    EXPECT_LT(lag[m], 0.5 * std::abs(static_cast<double>(steps[m]))) << "motor " << m;
    RecordProperty("worst_lag_steps_motor_" + std::to_string(m), std::to_string(lag[m]));
  }
}

TEST_F(HalFollowerTest, RaisedFaultPinFaultsTheFollowerWithinOneServoPeriod) {
  const HalConfig config = LoadHalConfig();
  const std::string fault_signal = SignalName(config.component_name, UnitPin::kFault);
  HalFollower follower(model_, config);
  ServoThread servo(follower, clock_);
  HomeAndEnable(servo);
  ASSERT_TRUE(ServoThread::Eventually([] { return StepgenEnabled(0); }));

  // The fault pin is linked to its signal; a HAL user (or the E-stop chain) raises the signal.
  HalSession::Halcmd("sets " + fault_signal + " 1");
  servo.Mark();  // the first Service() that starts after the rise, i.e. within one servo period of the loop
  ASSERT_TRUE(ServoThread::Eventually([&] { return servo.StateAfterMark().has_value(); }));
  const std::optional<robot::RsrFollowerState> after = servo.StateAfterMark();
  EXPECT_EQ(after->fault, FollowerFault::kExternal) << ToString(after->fault);
  EXPECT_FALSE(after->enabled);
  EXPECT_TRUE(ServoThread::Eventually([] { return !StepgenEnabled(0); })) << "the drive was not cut";
  EXPECT_FALSE(servo.With([](HalFollower& f) { return f.Enable(); }));
  EXPECT_FALSE(servo.With([](HalFollower& f) { return f.ResetFault(); })) << "the cause is still there";

  HalSession::Halcmd("sets " + fault_signal + " 0");
  EXPECT_TRUE(ServoThread::Eventually([&] { return servo.With([](HalFollower& f) { return f.ResetFault(); }); }));
  EXPECT_TRUE(servo.With([](HalFollower& f) { return f.Enable(); }));
}

TEST_F(HalFollowerTest, StoppedHalThreadsAreLostFeedback) {
  const HalConfig config = LoadHalConfig();
  HalFollower follower(model_, config);
  ServoThread servo(follower, clock_);
  HomeAndEnable(servo);
  HalSession::Halcmd("stop");
  // At least feedback_timeout_s of the loop's time without feedback; however long that takes here.
  ServoThread::Eventually([&] { return StateOf(servo).fault != FollowerFault::kNone; });
  EXPECT_EQ(StateOf(servo).fault, FollowerFault::kFeedbackLost) << ToString(StateOf(servo).fault);
  EXPECT_FALSE(StateOf(servo).enabled);
  EXPECT_FALSE(servo.With([](HalFollower& f) { return f.ResetFault(); }));

  HalSession::Halcmd("start");
  EXPECT_TRUE(ServoThread::Eventually([&] { return servo.With([](HalFollower& f) { return f.ResetFault(); }); }));
  EXPECT_TRUE(servo.With([](HalFollower& f) { return f.Enable(); }));
}

TEST_F(HalFollowerTest, StalledFollowerHasItsDrivesCutByHalsWatchdog) {
  const HalConfig config = LoadHalConfig();
  HalFollower follower(model_, config);
  ServoThread servo(follower, clock_);
  HomeAndEnable(servo);
  ASSERT_TRUE(ServoThread::Eventually([] { return StepgenEnabled(3); }));

  // Stall the servo loop (hold its lock) until HAL's watchdog cuts the drive: at least its timeout, which is more
  // than the gap after which the follower knows it may have been cut (half of it). Then, with the lock still held,
  // the follower's next Service() latches the cut (the enabled pin goes low) and the operator resets and enables at
  // once: the low level and the enable are microseconds apart, well inside one servo period. HAL's watchdog re-arms
  // only on a rising edge that it sees, so the follower must not raise the enabled pin before the watchdog has seen
  // it low; a follower that did stayed cut for good.
  FollowerFault latched = FollowerFault::kNone;
  const bool enabled = servo.With([&](HalFollower& f) {
    if (!ServoThread::Eventually([] { return !StepgenEnabled(3); })) return false;
    f.Service(clock_.NowS());
    latched = f.State().fault;
    return f.ResetFault() && f.Enable();
  });
  EXPECT_EQ(latched, FollowerFault::kDrive) << "the follower must know its drives were cut";
  ASSERT_TRUE(enabled) << "HAL's watchdog did not cut the drive, or the follower refused the enable";
  EXPECT_TRUE(ServoThread::Eventually([] { return StepgenEnabled(3); })) << "HAL's watchdog was not re-armed";
  EXPECT_TRUE(HalSession::GetBit("robossis.enabled"));
}

TEST_F(HalFollowerTest, ComponentLeavesHalWhenTheFollowerStops) {
  const HalConfig config = LoadHalConfig();
  {
    HalFollower follower(model_, config);
    ServoThread servo(follower, clock_);
    HomeAndEnable(servo);
    EXPECT_NE(HalSession::Halcmd("list comp").find(config.component_name), std::string::npos);
  }
  EXPECT_EQ(HalSession::Halcmd("list comp").find(config.component_name), std::string::npos)
      << HalSession::Halcmd("show comp");
  EXPECT_TRUE(ServoThread::Eventually([] { return !StepgenEnabled(0); })) << "the drives must be disabled";
  // The name is free again: a restarted follower joins under it.
  HalFollower again(model_, config);
  EXPECT_FALSE(again.State().enabled);
}

TEST_F(HalFollowerTest, CommandAndServiceAllocateNothing) {
  HalFollower follower(model_, LoadHalConfig());
  {
    ServoThread servo(follower, clock_);
    HomeAndEnable(servo);
  }
  robot::RsrJointCommand command;
  command.q = follower.q_home();
  command.q[3] += MmToM(0.01);
  robossis::testing::AllocationCounter counter;
  for (int k = 0; k < 200; ++k) {
    follower.Command(command);
    follower.Service(clock_.NowS());
    (void)follower.State();
  }
  EXPECT_EQ(counter.count(), 0u);
}

TEST(HalFollowerSetupTest, HalFileWithoutTheFollowersSignalsIsANamedErrorAndLeavesNothing) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "robossis-threads-only.hal";
  {
    std::ofstream out(file);
    out << "loadrt threads name1=servo-thread period1=1000000\nstart\n";
  }
  HalSession session(file);
  const robot::RsrModel model = robot::RsrModel::Default();
  try {
    HalFollower follower(model, LoadHalConfig());
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("robossis-j0-pos-cmd"), std::string::npos) << e.what();
  }
  EXPECT_EQ(HalSession::Halcmd("list comp").find("robossis"), std::string::npos);
  std::filesystem::remove(file);
}

TEST(HalSessionTest, AFileThatFailsIsAnErrorNamingTheLineAndLeavesNoComponent) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "robossis-unknown-component.hal";
  {
    std::ofstream out(file);
    out << "loadrt threads name1=servo-thread period1=1000000\nloadrt robossis_no_such_component\n";
  }
  try {
    HalSession session(file);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string() + ":2:"), std::string::npos) << e.what();
  }
  HalSession::PrepareEnvironment();
  EXPECT_EQ(HalSession::Halcmd("list comp").find("threads"), std::string::npos);
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace robossis::drivers
