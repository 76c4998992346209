// Actuation (eq. 13–17): Jacobian joint velocities, eq. 16 integration, pulses equal to the joint displacement,
// joint limits never crossed, step-rate caps, allocation-free tick, and the follower hand-off.

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "haptics/transfer/motion_transfer.h"
#include "haptics/transfer/timed_move.h"
#include "robot/actuation/actuator.h"
#include "robot/actuation/pulse_recorder.h"
#include "robot/actuation/step_rate.h"
#include "src/core/config.h"
#include "src/core/units.h"
#include "tests/support/alloc_counter.h"

namespace robossis::actuation {
namespace {

ActuationConfig Config() {
  const auto dir = DefaultDataDir() / "config";
  return ActuationConfig::FromYaml(dir / "actuation.yaml");
}

struct RunResult {
  double worst_step_error = 0;   // |n - s|, steps
  double worst_ik_error = 0;     // |q - IK(x)|
  bool within_limits = true;
  int limit_ticks = 0;
  int rate_ticks = 0;
};

RunResult RunMove(Actuator& act, const robot::RsrModel& model, const transfer::TimedMove& move, double t_end) {
  RunResult r;
  const double dt = 1e-4;
  for (int k = 1; k * dt <= t_end + 1e-12; ++k) {
    const transfer::RsrSetPoint sp = move.Evaluate(k * dt);
    const ActuationOutput& out = act.Tick(k * dt, sp.X_FM, sp.velocity);
    for (int m = 0; m < kNumMotors; ++m) {
      const double s = (out.command.q[m] - act.q_start()[m]) * act.config().motors[m].steps_per_unit;
      r.worst_step_error = std::max(r.worst_step_error, std::abs(out.steps[m] - s));
      r.within_limits = r.within_limits && out.command.q[m] >= act.q_min()[m] && out.command.q[m] <= act.q_max()[m];
    }
    if (out.status == ActuationStatus::kJointLimit) ++r.limit_ticks;
    if (out.status == ActuationStatus::kRateLimit) ++r.rate_ticks;
    const robot::RsrIkResult ik = robot::CalcInverseKinematics(model, sp.X_FM);
    if (ik.feasible) r.worst_ik_error = std::max(r.worst_ik_error, (ik.joints.actuated() - out.command.q).cwiseAbs().maxCoeff());
  }
  return r;
}

TEST(ActuatorTest, StepCountMatchesTheJointDisplacement) {
  const robot::RsrModel model = robot::RsrModel::Default();
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> p(-0.01, 0.01), a(-0.05, 0.05);
  for (int i = 0; i < 5; ++i) {
    transfer::TimedMoveRequest req;
    req.delta_p_F = Eigen::Vector3d(p(gen), p(gen), p(gen));
    req.delta_rot_F = Eigen::Vector3d(a(gen), a(gen), a(gen));
    const transfer::TimedMove move(model.geometry().X_FM_home, req, 2.0);
    Actuator act(model, Config(), model.geometry().X_FM_home);
    const RunResult r = RunMove(act, model, move, 2.2);
    EXPECT_LE(r.worst_step_error, 0.5);  // within one step (half a step, by rounding)
    EXPECT_LT(r.worst_ik_error, 1e-5);   // q (eq. 16) stays on IK(x): < 10 µm / 10 µrad
  }
}

TEST(ActuatorTest, EulerBackwardIntegrationOfEq16) {
  // With the IK correction off, q(t) - q(t-1) = dt · q_dot(t) and q_dot(t) = J(x(t)) x_dot(t) exactly.
  const robot::RsrModel model = robot::RsrModel::Default();
  ActuationConfig config = Config();
  config.ik_correction_gain_per_s = 0;
  transfer::TimedMoveRequest req;
  req.delta_p_F = Eigen::Vector3d(0, 0.005, 0.005);
  const transfer::TimedMove move(model.geometry().X_FM_home, req, 1.0);
  Actuator act(model, config, model.geometry().X_FM_home);
  robot::RsrJointVector q_prev = act.q();
  double worst_drift = 0;
  for (int k = 1; k <= 12000; ++k) {
    const transfer::RsrSetPoint sp = move.Evaluate(k * 1e-4);
    const ActuationOutput& out = act.Tick(k * 1e-4, sp.X_FM, sp.velocity);
    const robot::RsrJointVector expected_q_dot = robot::CalcJacobian(model, sp.X_FM) * sp.velocity;
    ASSERT_LT((out.command.q_dot - expected_q_dot).norm(), 1e-15);
    ASSERT_LT((out.command.q - q_prev - 1e-4 * out.command.q_dot).norm(), 1e-15);
    q_prev = out.command.q;
    worst_drift = std::max(worst_drift, (robot::CalcInverseKinematics(model, sp.X_FM).joints.actuated() - out.command.q)
                                            .cwiseAbs()
                                            .maxCoeff());
  }
  EXPECT_LT(worst_drift, 1e-5);  // first-order integration error stays small over this move
}

TEST(ActuatorTest, JointLimitsAreNeverCrossed) {
  // A move far past the stroke limit (z + 120 mm: d > 354 mm): clamp, flag, hold.
  const robot::RsrModel model = robot::RsrModel::Default();
  transfer::TimedMoveRequest req;
  req.delta_p_F = Eigen::Vector3d(0, 0, 0.120);
  const transfer::TimedMove move(model.geometry().X_FM_home, req, 6.0);
  ActuationConfig config = Config();
  Actuator act(model, config, model.geometry().X_FM_home);
  const RunResult r = RunMove(act, model, move, 6.5);
  EXPECT_TRUE(r.within_limits);
  EXPECT_GT(r.limit_ticks, 1000);
  EXPECT_LE(r.worst_step_error, 0.5);
  for (int i = 3; i < 6; ++i) EXPECT_NEAR(act.q()[i], model.limits().stroke_max_m, 1e-12);  // holding at the limit
  // Coming back inside is allowed again.
  const Eigen::Isometry3d X_back = model.geometry().X_FM_home;
  const ActuationOutput& out = act.Tick(6.5001, X_back, Vector6d::Zero());
  EXPECT_LT(out.command.q[3], model.limits().stroke_max_m);
}

TEST(ActuatorTest, StepRateIsCapped) {
  const robot::RsrModel model = robot::RsrModel::Default();
  ActuationConfig config = Config();
  for (auto& m : config.motors) m.max_step_rate_hz = 1000;  // 5 mm/s of stroke at 200 steps/mm
  transfer::TimedMoveRequest req;
  req.delta_p_F = Eigen::Vector3d(0, 0, 0.010);
  const transfer::TimedMove move(model.geometry().X_FM_home, req, 1.0);  // 15.7 mm/s peak
  Actuator act(model, config, model.geometry().X_FM_home);
  PulseRecorder rec;
  const double dt = 1e-4;
  for (int k = 1; k <= 40000; ++k) {
    const transfer::RsrSetPoint sp = move.Evaluate(k * dt);
    rec.Record(act.Tick(k * dt, sp.X_FM, sp.velocity));
  }
  // No 10 ms window holds more than 1000 steps/s · 10 ms on any motor.
  EXPECT_LE(MaxStepRateHz(rec.events()), 1000.0);
  // It still arrives: the IK correction catches up once the rate allows.
  EXPECT_NEAR(act.q()[3], robot::CalcInverseKinematics(model, move.X_FM_end()).joints.d_m[0], 5e-6);
}

TEST(ActuatorTest, TickAllocatesNothing) {
  const robot::RsrModel model = robot::RsrModel::Default();
  Actuator act(model, Config(), model.geometry().X_FM_home);
  transfer::TimedMoveRequest req;
  req.delta_p_F = Eigen::Vector3d(0.01, 0, 0.01);
  const transfer::TimedMove move(model.geometry().X_FM_home, req, 1.0);
  const testing::AllocationCounter counter;
  for (int k = 1; k <= 5000; ++k) {
    const transfer::RsrSetPoint sp = move.Evaluate(k * 1e-4);
    act.Tick(k * 1e-4, sp.X_FM, sp.velocity);
  }
  EXPECT_EQ(counter.count(), 0u);
}

TEST(ActuatorTest, WholeTenKilohertzTickAllocatesNothing) {
  // The full 10 kHz tick as the follower side runs it: motion transfer fast path, then the actuator.
  const robot::RsrModel model = robot::RsrModel::Default();
  transfer::MotionTransfer mt(transfer::TransferConfig{}, model.geometry().X_FM_home);
  Actuator act(model, Config(), model.geometry().X_FM_home);
  transfer::HcSample sample;
  const testing::AllocationCounter counter;
  for (int k = 0; k < 1000; ++k) {
    sample.time_s = k * 1e-3;
    sample.p_OH = Eigen::Vector3d(0.02 * k * 1e-3, 0, 0);  // 20 mm/s: scaled to the cap
    mt.PushHcSample(sample);
    mt.TransferTick();
    for (int j = 0; j < 10; ++j) {
      const transfer::RsrSetPoint& sp = mt.ActuationTick();
      act.Tick(sp.time_s, sp.X_FM, sp.velocity);
    }
  }
  EXPECT_EQ(counter.count(), 0u);
  std::int64_t moved = 0;
  for (std::int64_t n : act.output().steps) moved += n < 0 ? -n : n;
  EXPECT_GT(moved, 0);  // it did move
}

class RecordingFollower : public robot::Follower {
 public:
  bool Enable() noexcept override { return true; }
  void Disable() noexcept override {}
  bool Home() noexcept override { return true; }
  bool MeasuresJoints() const noexcept override { return true; }
  bool ResetFault() noexcept override { return true; }
  void Command(const robot::RsrJointCommand& c) noexcept override { last = c; ++count; }
  void Service(double) noexcept override {}
  robot::RsrFollowerState State() const noexcept override { return {}; }
  robot::RsrJointCommand last;
  int count = 0;
};

TEST(ActuatorTest, FeedsAnyFollower) {
  const robot::RsrModel model = robot::RsrModel::Default();
  Actuator act(model, Config(), model.geometry().X_FM_home);
  RecordingFollower follower;
  Eigen::Isometry3d X = model.geometry().X_FM_home;
  X.translation().z() += 1e-6;
  Vector6d twist = Vector6d::Zero();
  twist[2] = 0.01;
  CommandFollower(act.Tick(1e-4, X, twist), follower);
  EXPECT_EQ(follower.count, 1);
  EXPECT_DOUBLE_EQ(follower.last.time_s, 1e-4);
  EXPECT_EQ(follower.last.q, act.q());
  EXPECT_GT(follower.last.q_dot[3], 0);  // moving up extends the legs
}

TEST(ActuatorTest, RejectsAStartOutsideTheLimits) {
  const robot::RsrModel model = robot::RsrModel::Default();
  Eigen::Isometry3d X = model.geometry().X_FM_home;
  X.translation().z() += 0.2;
  EXPECT_THROW(Actuator(model, Config(), X), std::invalid_argument);
}


TEST(ActuatorTest, ALongGapBetweenTicksDoesNotOvershootTheCorrection) {
  // The IK correction pulls q toward IK(x) by gain · dt of the error; after a gap of seconds gain · dt is far above
  // 1, and an unbounded correction would throw the joints past IK(x) by that factor.
  const robot::RsrModel model = robot::RsrModel::Default();
  const Eigen::Isometry3d home = model.geometry().X_FM_home;
  Actuator act(model, Config(), home, 0.0);
  Eigen::Isometry3d X = home;
  X.translation().z() += 20e-6;  // a set-point 20 um away, reached only by the correction (zero twist)
  act.Tick(2.0, X, Vector6d::Zero());
  const robot::RsrJointVector q_ik = robot::CalcInverseKinematics(model, X).joints.actuated();
  EXPECT_LT((act.q() - q_ik).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(ActuatorTest, ResyncStartsFromTheMeasuredJointsWithoutABurstOfSteps) {
  const robot::RsrModel model = robot::RsrModel::Default();
  const Eigen::Isometry3d home = model.geometry().X_FM_home;
  const ActuationConfig config = Config();
  Actuator act(model, config, home, 0.0);
  // The motors were pushed 0.2 mm along stroke 0 while the drives were off, and the actuator learns it at t = 3 s.
  Eigen::Isometry3d X_meas = home;
  robot::RsrJointVector q_meas = robot::CalcInverseKinematics(model, home).joints.actuated();
  q_meas[robot::StrokeIndex(0)] += 0.2e-3;
  X_meas = robot::CalcForwardKinematics(model, q_meas, home).X_FM;
  std::array<std::int64_t, kNumMotors> steps_before{};
  for (int m = 0; m < kNumMotors; ++m) steps_before[m] = act.output().steps[m];
  act.Resync(3.0, q_meas);
  EXPECT_EQ(act.q(), q_meas);
  // Holding there: no pulse, no motion.
  const ActuationOutput& out = act.Tick(3.0001, X_meas, Vector6d::Zero());
  EXPECT_EQ(out.num_events, 0);
  for (int m = 0; m < kNumMotors; ++m) EXPECT_EQ(out.steps[m], steps_before[m]) << "motor " << m;
  EXPECT_LT((act.q() - q_meas).cwiseAbs().maxCoeff(), 1e-9);
  // Moving on from there: the steps count the motion from the measured joints (eq. 17 with the moved zero).
  Eigen::Isometry3d X_next = X_meas;
  X_next.translation().z() += 1e-6;
  act.Tick(3.0002, X_next, Vector6d::Zero());
  for (int m = 0; m < kNumMotors; ++m) {
    const double s = (act.q()[m] - act.q_start()[m]) * config.motors[m].steps_per_unit;
    EXPECT_LE(std::abs(static_cast<double>(act.output().steps[m]) - s), 0.5 + 1e-9) << "motor " << m;
  }
}

}  // namespace
}  // namespace robossis::actuation
