// The one validated move path (ValidateMove): a move shorter than one actuation tick is refused, the peak of the
// eq. 9 profile is held against the caps (not the samples' mean), the end pose is always checked; and the chain's
// step-rate figure of a pulse train at the motors' maximum.

#include <gtest/gtest.h>

#include "robot/rsr_model.h"
#include "src/core/config.h"
#include "src/core/units.h"
#include "src/teleop/offline_chain.h"

namespace robossis::teleop {
namespace {

class ValidateMoveTest : public ::testing::Test {
 protected:
  const robot::RsrModel model_ = robot::RsrModel::Default();
  const ChainSetup setup_ = LoadChainSetup(DefaultDataDir() / "config", model_);  // 10 kHz, 10 mm/s
  PathVerdict Check(double dz_mm, double duration_s) const {
    transfer::TimedMoveRequest req;
    req.delta_p_F = Eigen::Vector3d(0, 0, MmToM(dz_mm));
    return ValidateMove(transfer::TimedMove(setup_.X_FM_start, req, duration_s), setup_);
  }
};

TEST_F(ValidateMoveTest, AMoveShorterThanOneTickIsRefused) {
  for (const double duration_s : {1e-15, 1e-9, 5e-5, 0.99e-4}) {
    const PathVerdict v = Check(5, duration_s);
    EXPECT_EQ(v.verdict, SetPointVerdict::kTooFast) << duration_s;
    EXPECT_TRUE(v.shorter_than_a_tick) << duration_s;
  }
  // Exactly one tick, slow enough at its peak: accepted.
  const PathVerdict one = Check(0.0005, 1e-4);
  EXPECT_TRUE(one.ok()) << ToString(one.verdict);
  EXPECT_FALSE(one.shorter_than_a_tick);
}

TEST_F(ValidateMoveTest, ThePeakOfTheProfileIsHeldAgainstTheCaps) {
  // One tick, 0.9 µm: 9 mm/s of mean speed, 14.1 mm/s at eq. 9's peak, over the 10 mm/s cap.
  const PathVerdict v = Check(0.0009, 1e-4);
  EXPECT_EQ(v.verdict, SetPointVerdict::kTooFast);
  EXPECT_FALSE(v.shorter_than_a_tick);
  // Five ticks: the samples straddle the peak (at 2.5 ticks); their twists see 0.95 of it, their pose steps 0.98.
  // A 10.3 mm/s peak (over the cap's 2 % tolerance) looked like 10.1 mm/s.
  EXPECT_EQ(Check(0.0032785, 5e-4).verdict, SetPointVerdict::kTooFast);
}

TEST_F(ValidateMoveTest, TheEndPoseIsCheckedHoweverShortTheMove) {
  const PathVerdict v = Check(200, 1e-15);
  EXPECT_EQ(v.verdict, SetPointVerdict::kInfeasible);
  EXPECT_EQ(v.index, 1u);
}

TEST_F(ValidateMoveTest, TheShortestDurationIsAtLeastOneTick) {
  transfer::TimedMoveRequest req;
  req.delta_p_F = Eigen::Vector3d(0, 0, MmToM(0.0001));
  EXPECT_DOUBLE_EQ(MinimumMoveDuration(req, setup_), 1e-4);
  req.delta_p_F = Eigen::Vector3d(0, 0, MmToM(5));
  EXPECT_NEAR(MinimumMoveDuration(req, setup_), kPi / 2 * 0.5, 1e-12);  // eq. 9: pi/2 · 5 mm / 10 mm/s
  EXPECT_EQ(MinimumMoveDuration(transfer::TimedMoveRequest{}, setup_), 0.0);
}

TEST(OfflineChainTest, AMoveAtTheMotorsMaximumStepRateReportsThatRate) {
  // 40 mm in 2 s peaks at 31 mm/s of stroke, over the linear motors' 4000 steps/s: held at exactly 4000 Hz.
  const robot::RsrModel model = robot::RsrModel::Default();
  ChainSetup setup = LoadChainSetup(DefaultDataDir() / "config", model);
  setup.transfer.caps.max_linear_speed_m_s = 0.040;
  transfer::TimedMoveRequest req;
  req.delta_p_F = Eigen::Vector3d(0, 0, 0.040);
  const TransferTrace trace = RunMoveChain({req}, {2.0}, setup);
  EXPECT_GT(trace.summary.rate_limited_ticks, 1000u);
  EXPECT_DOUBLE_EQ(trace.summary.max_step_rate_hz, 4000.0);
}

}  // namespace
}  // namespace robossis::teleop
