// Stalls of the loops, on the simulated clock: the follower unit over the Bullet robot on its own loop
// (sim::SimulatedPlant, as `robossis teleop --follower sim` runs it), a leader moving at the caps, and 100 ms in
// which the follower's loop (or every loop) does not run. The robot never faults, never jumps, and its measured
// speed stays within the caps.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "src/teleop/follower_unit.h"
#include "src/teleop/in_process_link.h"
#include "tests/teleop/bullet_plant_fixture.h"
#include "tests/teleop/follower_fixture.h"

namespace robossis::teleop {
namespace {

constexpr std::int64_t kTickNs = 100'000;  // the follower's 10 kHz
constexpr double kCapMps = 0.1;            // the raised caps of the demo's real-clock run (100 mm/s)

struct StallRun {
  bool enabled_throughout = true;
  std::string left_enabled;  // the first state other than enabled, and why, for the failure message
  double max_measured_speed_mps = 0;  // over the plant's measurement times
  double max_command_step_m = 0;      // the commanded pose's largest move in one follower tick
  double travelled_m = 0;
};

class FollowerStallTest : public ::testing::Test, protected ShippedFollowerSetup {
 protected:
  // `follower_stalled(t)` / `plant_stalled(t)`: that loop's thread does not run at time t.
  StallRun Run(const std::function<bool(std::int64_t)>& follower_stalled,
               const std::function<bool(std::int64_t)>& plant_stalled) {
    FollowerConfig config = ShippedFollowerConfig();
    config.setpoint.caps.max_linear_speed_m_s = kCapMps;
    config.setpoint.max_linear_accel_m_s2 = 1.0;
    rt::SimulatedClock clock;
    InProcessLink link(clock);
    sim::SimulatedPlant plant = UnloadedBulletPlant(model_, home_);
    FollowerUnit unit(model_, actuation_, config, plant, link, clock);
    SendEnable(link);

    // The leader moves along x at the cap within the acceleration cap: 0.2 s up to the cap, 0.3 s at it, 0.2 s down
    // (50 mm), from 0.05 s. The stalls fall in the cruise.
    const auto leader = [](double t_s, double& x, double& v) {
      const double a = 0.5, t1 = 0.2, t2 = 0.5, t3 = 0.7;  // m/s², and the phases' ends after the start
      const double u = std::clamp(t_s - 0.05, 0.0, t3);
      const double x1 = 0.5 * a * t1 * t1, x2 = x1 + kCapMps * (t2 - t1);
      if (u < t1) x = 0.5 * a * u * u, v = a * u;
      else if (u < t2) x = x1 + kCapMps * (u - t1), v = kCapMps;
      else x = x2 + kCapMps * (u - t2) - 0.5 * a * (u - t2) * (u - t2), v = kCapMps - a * (u - t2);
    };
    StallRun run;
    std::uint64_t sequence = 0;
    robot::RsrFollowerState previous = plant.State();
    Eigen::Isometry3d previous_cmd = unit.commanded_pose();
    for (std::int64_t t = kTickNs; t <= 1'000'000'000; t += kTickNs) {
      clock.SetNs(t);
      if (t % 1'000'000 == 0) {
        double x = 0, v = 0;
        leader(1e-9 * static_cast<double>(t), x, v);
        const Eigen::Vector3d p = home_.translation() + Eigen::Vector3d(x, 0, 0);
        SetPointMessage m;
        m.sequence = ++sequence;
        m.leader_session = 1;
        m.stamp_ns = t;
        m.p_FM = {p.x(), p.y(), p.z()};
        m.twist_F = {v, 0, 0, 0, 0, 0};
        m.flags = kSetPointPresence;
        link.SendSetPoint(m);
      }
      if (!follower_stalled(t)) {
        unit.Tick();
        if (t > 40'000'000 && unit.state() != OperatingState::kEnabled && run.enabled_throughout) {
          run.enabled_throughout = false;
          run.left_enabled = std::string(ToString(unit.state())) + " (" + ToString(unit.reason()) + ", back end " +
                             robot::ToString(plant.State().fault) + ") at " + std::to_string(1e-9 * t) + " s";
        }
        run.max_command_step_m = std::max(
            run.max_command_step_m, (unit.commanded_pose().translation() - previous_cmd.translation()).norm());
        previous_cmd = unit.commanded_pose();
        const robot::RsrFollowerState s = plant.State();
        if (s.time_s > previous.time_s) {
          const double v =
              (s.X_FM.translation() - previous.X_FM.translation()).norm() / (s.time_s - previous.time_s);
          run.max_measured_speed_mps = std::max(run.max_measured_speed_mps, v);
          previous = s;
        }
      }
      if (t % plant.period_ns() == 0 && !plant_stalled(t)) plant.Tick(t);
    }
    run.travelled_m = (plant.State().X_FM.translation() - home_.translation()).norm();
    return run;
  }
};

bool Never(std::int64_t) { return false; }
// 100 ms while the leader moves at the cap.
bool InTheStall(std::int64_t t) { return t > 300'000'000 && t <= 400'000'000; }

// No fault, the measured speed within the cap, no commanded step longer than max_tick_interval_s of motion at the
// cap (after a stall, too), and the set-points' 50 mm reached in the end (caught up within the caps).
void ExpectFollowedWithinTheCaps(const StallRun& run, const FollowerConfig& config) {
  EXPECT_TRUE(run.enabled_throughout) << run.left_enabled;
  EXPECT_LE(run.max_measured_speed_mps, 1.01 * kCapMps);
  EXPECT_LE(run.max_command_step_m, kCapMps * config.watchdog.max_tick_interval_s * 1.0001);
  EXPECT_NEAR(run.travelled_m, 0.05, 0.001);
}

TEST_F(FollowerStallTest, WithoutAStallTheRobotFollowsAtTheCap) {
  const StallRun run = Run(Never, Never);
  ExpectFollowedWithinTheCaps(run, ShippedFollowerConfig());
  EXPECT_GT(run.max_measured_speed_mps, 0.9 * kCapMps);
}

TEST_F(FollowerStallTest, AHundredMillisecondStallOfTheFollowerLoopNeitherFaultsNorJumps) {
  ExpectFollowedWithinTheCaps(Run(InTheStall, Never), ShippedFollowerConfig());
}

TEST_F(FollowerStallTest, AHundredMillisecondStallOfEveryLoopNeitherFaultsNorJumps) {
  ExpectFollowedWithinTheCaps(Run(InTheStall, InTheStall), ShippedFollowerConfig());
}

TEST_F(FollowerStallTest, AHundredMillisecondStallOfThePlantAloneIsMadeUpWithoutAFault) {
  ExpectFollowedWithinTheCaps(Run(Never, InTheStall), ShippedFollowerConfig());
}

// A loaded machine's scheduling: stalls of 0.2 to 20 ms, one every 5 to 50 ms, through the whole motion (a fixed
// seed: the same stalls every run).
class ScheduledStalls {
 public:
  explicit ScheduledStalls(std::uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_int_distribution<std::int64_t> gap(5'000'000, 50'000'000), length(200'000, 20'000'000);
    for (std::int64_t t = gap(random); t < 1'000'000'000; t += gap(random)) {
      const std::int64_t end = t + length(random);
      stalls_.push_back({t, end});
      t = end;
    }
  }
  bool operator()(std::int64_t t) const {
    return std::any_of(stalls_.begin(), stalls_.end(), [t](const auto& s) { return t > s.first && t <= s.second; });
  }

 private:
  std::vector<std::pair<std::int64_t, std::int64_t>> stalls_;
};

TEST_F(FollowerStallTest, AScheduleOfShortStallsOfTheFollowerLoopKeepsTheCaps) {
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE(seed);
    ExpectFollowedWithinTheCaps(Run(ScheduledStalls(seed), Never), ShippedFollowerConfig());
  }
}

TEST_F(FollowerStallTest, AScheduleOfShortStallsOfEveryLoopKeepsTheCaps) {
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE(seed);
    const ScheduledStalls stalls(seed);
    ExpectFollowedWithinTheCaps(Run(stalls, stalls), ShippedFollowerConfig());
  }
}

TEST_F(FollowerStallTest, AScheduleOfShortStallsOfThePlantKeepsTheCaps) {
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE(seed);
    ExpectFollowedWithinTheCaps(Run(Never, ScheduledStalls(seed)), ShippedFollowerConfig());
  }
}

}  // namespace
}  // namespace robossis::teleop
