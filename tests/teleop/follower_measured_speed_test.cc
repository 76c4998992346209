// The speed cap held by the robot, on the simulated clock with a loaded machine's timing: the follower unit over the
// Bullet robot on its own loop (sim::SimulatedPlant, as `robossis teleop --follower sim` runs it), the loops waking
// late by a random amount and stalling now and then, the set-points arriving in bursts as DDS delivers them, and the
// leader moving at the cap. The measured speed over 10 ms (the session summary's figure) stays within 1.01 × the
// cap; the test also prints the speed of each pose the chain holds (commanded pose, commanded joints, measured
// joints, the ring body), so that a failure says where the excess comes from.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "robot/rsr_kinematics.h"
#include "src/teleop/follower_unit.h"
#include "src/teleop/in_process_link.h"
#include "src/teleop/leader_unit.h"
#include "src/teleop/session_summary.h"
#include "tests/teleop/bullet_plant_fixture.h"
#include "tests/teleop/follower_fixture.h"

namespace robossis::teleop {
namespace {

constexpr double kCapMps = 0.1;                          // the demo's real-clock cap: 100 mm/s
constexpr double kWindowS = 0.01;                        // the session summary's window (100 follower ticks)
constexpr std::int64_t kFollowerPeriodNs = 100'000;
constexpr std::int64_t kLeaderPeriodNs = 1'000'000;
constexpr std::int64_t kRunNs = 2'800'000'000;  // two legs out and back
constexpr double kJudgedFromS = 0.05;  // after the enable and the first set-points

// The leader at the linear cap: 50 mm along x and back, twice (each way 0.2 s up to the cap at 0.5 m/s², 0.3 s at
// it, 0.2 s down), with the ring still (as the fast hand's set-points run at the cap along one axis).
struct LeaderPath {
  Eigen::Isometry3d home;
  void At(double t_s, Eigen::Isometry3d& X, Vector6d& twist) const {
    const double a = 0.5, t1 = 0.2, t2 = 0.5, t3 = 0.7;  // m/s², and the phases' ends after the start of a leg
    const double x1 = 0.5 * a * t1 * t1, x2 = x1 + kCapMps * (t2 - t1), x3 = x2 + x1;
    const double leg_t = std::fmod(t_s, t3);
    const bool back = std::fmod(t_s, 2 * t3) >= t3;
    const double u = std::clamp(leg_t, 0.0, t3);
    double x = 0, v = 0;
    if (u < t1) x = 0.5 * a * u * u, v = a * u;
    else if (u < t2) x = x1 + kCapMps * (u - t1), v = kCapMps;
    else x = x2 + kCapMps * (u - t2) - 0.5 * a * (u - t2) * (u - t2), v = kCapMps - a * (u - t2);
    if (back) x = x3 - x, v = -v;
    X = home;
    X.translation().x() += x;
    twist << v, 0, 0, 0, 0, 0;
  }
};

// When each loop runs on a loaded 2-core machine [assumed, from the two-process real-clock runs' loop records]: the
// follower wakes 2-40 µs late and one tick in 50 is 0.2-1.5 ms late (2.7 % of the follower's ticks overran in such a
// run); the plant (below the leader and the follower in priority) wakes up to 0.8 ms late and one tick in 40 stalls
// 2-15 ms (its steps made up in one tick); the set-points arrive in bursts 1-20 ms apart (the follower takes the
// newest of each burst).
class LoadedTiming {
 public:
  explicit LoadedTiming(std::uint32_t seed) : random_(seed) {}
  std::int64_t NextFollower(std::int64_t now) { return Next(now, kFollowerPeriodNs, 2'000, 40'000, 50, 200'000, 1'500'000); }
  std::int64_t NextPlant(std::int64_t now, std::int64_t period) {
    return Next(now, period, 0, 800'000, 40, 2'000'000, 15'000'000);
  }
  std::int64_t NextDelivery(std::int64_t now) { return now + Uniform(1'000'000, 20'000'000); }

 private:
  std::int64_t Uniform(std::int64_t lo, std::int64_t hi) { return std::uniform_int_distribution<std::int64_t>(lo, hi)(random_); }
  // The first deadline after `now`, plus the wake-up latency, or once in `one_in` a stall.
  std::int64_t Next(std::int64_t now, std::int64_t period, std::int64_t late_lo, std::int64_t late_hi, int one_in,
                    std::int64_t stall_lo, std::int64_t stall_hi) {
    const std::int64_t deadline = (now / period + 1) * period;
    const bool stall = std::uniform_int_distribution<int>(1, one_in)(random_) == 1;
    return deadline + (stall ? Uniform(stall_lo, stall_hi) : Uniform(late_lo, late_hi));
  }
  std::mt19937 random_;
};

// The largest speed over windows of at least kWindowS between samples (time, pose).
struct Speeds {
  double linear_mps = 0;
};
struct PoseSample {
  double t_s;
  Eigen::Isometry3d X;
};
Speeds MaxSpeedsOver10Ms(const std::vector<PoseSample>& samples) {
  Speeds s;
  std::size_t j = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    while (j + 1 < i && samples[i].t_s - samples[j + 1].t_s >= kWindowS - 1e-9) ++j;
    const double dt = samples[i].t_s - samples[j].t_s;
    if (dt < kWindowS - 1e-9) continue;
    s.linear_mps = std::max(s.linear_mps, (samples[i].X.translation() - samples[j].X.translation()).norm() / dt);
  }
  return s;
}

struct MeasuredSpeeds {
  bool enabled_throughout = true;
  Speeds summary;            // summary.json's max_follower_speed_mm_s, in SI
  Speeds ring_body;          // the measured ring pose (as the back end reports it) over 10 ms of physics time
  Speeds measured_joints;    // the forward kinematics of the measured joints, the same windows
  Speeds commanded_joints;   // the forward kinematics of the commanded joints, over the commands' times
  Speeds commanded_pose;     // the follower's commanded pose, over the commands' times
};

class FollowerMeasuredSpeedTest : public ::testing::Test, protected ShippedFollowerSetup {
 protected:
  MeasuredSpeeds Run(std::uint32_t seed) {
    FollowerConfig config = ShippedFollowerConfig();
    config.setpoint.caps.max_linear_speed_m_s = kCapMps;
    rt::SimulatedClock clock;
    InProcessLink link(clock);
    sim::SimulatedPlant plant = UnloadedBulletPlant(model_, home_);
    FollowerUnit unit(model_, actuation_, config, plant, link, clock);
    SendEnable(link);

    SummaryOptions summary_options;
    summary_options.max_linear_speed_m_s = kCapMps;
    SessionSummary summary(summary_options);
    const LeaderPath leader{home_};
    LoadedTiming timing(seed);
    MeasuredSpeeds out;
    std::vector<PoseSample> ring, joints, cmd_joints, cmd_pose;
    double last_meas_s = -1;
    Eigen::Isometry3d fk_guess = home_, cmd_fk_guess = home_;

    std::uint64_t sequence = 0;
    SetPointMessage newest;  // the leader's newest set-point, not yet delivered
    bool pending = false;
    std::int64_t next_stamp = kLeaderPeriodNs, next_delivery = timing.NextDelivery(0);
    std::int64_t next_follower = kFollowerPeriodNs, next_plant = plant.period_ns();
    while (true) {
      const std::int64_t t = std::min({next_stamp, next_delivery, next_follower, next_plant});
      if (t > kRunNs) break;
      clock.SetNs(t);
      if (t == next_stamp) {  // the leader's 1 kHz set-point, stamped now
        Eigen::Isometry3d X;
        Vector6d v;
        leader.At(1e-9 * static_cast<double>(t), X, v);
        newest = SetPointMessage{};
        newest.sequence = ++sequence;
        newest.leader_session = 1;
        newest.stamp_ns = t;
        const Eigen::Quaterniond q(X.linear());
        newest.p_FM = {X.translation().x(), X.translation().y(), X.translation().z()};
        newest.q_FM = {q.w(), q.x(), q.y(), q.z()};
        for (int k = 0; k < 6; ++k) newest.twist_F[k] = v[k];
        newest.flags = kSetPointPresence;
        pending = true;
        next_stamp += kLeaderPeriodNs;
      }
      if (t == next_delivery) {
        if (pending) link.SendSetPoint(newest);
        pending = false;
        next_delivery = timing.NextDelivery(t);
      }
      if (t == next_follower) {
        unit.Tick();
        next_follower = timing.NextFollower(t);
        FollowerTickRecord r;
        while (unit.TakeRecord(r)) {
          summary.AddFollower(r);
          if (r.time_s < kJudgedFromS) continue;
          if (r.state != OperatingState::kEnabled) out.enabled_throughout = false;
          const Eigen::Isometry3d cmd = PoseFromArrays(r.cmd_p_FM, r.cmd_q_FM);
          cmd_pose.push_back({r.time_s, cmd});
          robot::RsrJointVector q;
          for (int k = 0; k < 6; ++k) q[k] = r.cmd_joints[k];
          const robot::RsrFkResult cmd_fk = robot::CalcForwardKinematics(model_, q, cmd_fk_guess);
          if (cmd_fk.converged()) cmd_joints.push_back({r.time_s, cmd_fk_guess = cmd_fk.X_FM});
          if (r.meas_time_s == last_meas_s) continue;  // one sample per measurement
          last_meas_s = r.meas_time_s;
          const Eigen::Isometry3d meas = PoseFromArrays(r.meas_p_FM, r.meas_q_FM);
          ring.push_back({r.meas_time_s, meas});
          for (int k = 0; k < 6; ++k) q[k] = r.meas_joints[k];
          const robot::RsrFkResult fk = robot::CalcForwardKinematics(model_, q, fk_guess);
          if (fk.converged()) joints.push_back({r.meas_time_s, fk_guess = fk.X_FM});
        }
      }
      if (t == next_plant) {
        plant.Tick(t);
        next_plant = timing.NextPlant(t, plant.period_ns());
      }
    }
    const auto s = summary.Summary();
    out.summary.linear_mps = 1e-3 * s.at("max_follower_speed_mm_s").get<double>();
    out.ring_body = MaxSpeedsOver10Ms(ring);
    out.measured_joints = MaxSpeedsOver10Ms(joints);
    out.commanded_joints = MaxSpeedsOver10Ms(cmd_joints);
    out.commanded_pose = MaxSpeedsOver10Ms(cmd_pose);
    return out;
  }
};

void Print(std::uint32_t seed, const MeasuredSpeeds& m) {
  std::printf("seed %u, speed over the cap: summary %.4f, ring body %.4f, measured joints %.4f, commanded joints %.4f, "
              "commanded pose %.4f\n",
              seed, m.summary.linear_mps / kCapMps, m.ring_body.linear_mps / kCapMps,
              m.measured_joints.linear_mps / kCapMps, m.commanded_joints.linear_mps / kCapMps,
              m.commanded_pose.linear_mps / kCapMps);
}

// Before the physics stopped stepping ahead of its clock, the ring body read 1.019-1.042 × the cap here (the summary
// up to 1.067) while the commanded pose stayed at 1.000: a plant tick late by 0.5 ms stepped to an instant 0.5 ms
// ahead, the drives took the follower's command (itself up to 1 ms old, its loop late too) extrapolated by at most
// command_extrapolation_max_s, and the robot fell short of the path, then made it up in one step.
TEST_F(FollowerMeasuredSpeedTest, OnALoadedMachinesTimingTheMeasuredSpeedStaysWithinTheCap) {
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE(seed);
    const MeasuredSpeeds m = Run(seed);
    Print(seed, m);
    EXPECT_TRUE(m.enabled_throughout);
    EXPECT_LE(m.summary.linear_mps, 1.01 * kCapMps);
    EXPECT_LE(m.ring_body.linear_mps, 1.01 * kCapMps);
    EXPECT_GT(m.summary.linear_mps, 0.9 * kCapMps);  // the leader's path does take the robot to the cap
  }
}

}  // namespace
}  // namespace robossis::teleop
