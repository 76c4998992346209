// The follower publishes the limits it validates set-points against with every status, and a leader whose own copy
// differs (on two machines each reads its own data folder) refuses to start, naming both values.
#include <filesystem>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "robot/actuation/pulse_recorder_follower.h"
#include "src/core/files.h"
#include "src/teleop/follower_limits.h"
#include "src/teleop/follower_unit.h"
#include "src/teleop/in_process_link.h"
#include "tests/teleop/follower_fixture.h"

namespace robossis::teleop {
namespace {

class FollowerLimitsTest : public ::testing::Test, protected ShippedFollowerSetup {
 protected:
  FollowerConfig follower_ = Published();
  rt::SimulatedClock clock_;
  InProcessLink link_{clock_};
  actuation::PulseRecorderFollower back_end_{model_, actuation_, home_, 1 << 10, 1 << 10};
  FollowerUnit unit_{model_, actuation_, follower_, back_end_, link_, clock_};

  FollowerConfig Published() const {
    FollowerConfig c = ShippedFollowerConfig();
    const std::filesystem::path config = DefaultDataDir() / "config";
    c.model_fingerprint = ModelFingerprint({config / "rsr.yaml", config / "actuation.yaml"});
    return c;
  }
  // The leader's check against the status the follower published at its first tick; the error ("" if it starts).
  std::string Check(const FollowerConfig& leader_copy) {
    unit_.Tick();
    try {
      CheckFollowerLimits(link_, LimitsOf(leader_copy), 0.5);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(FollowerLimitsTest, EqualConfigsStart) { EXPECT_EQ(Check(Published()), ""); }

TEST_F(FollowerLimitsTest, AnotherAccelerationCapIsRefusedNamingBothValues) {
  FollowerConfig leader = Published();
  leader.setpoint.max_linear_accel_m_s2 = 2.5;
  ASSERT_NE(follower_.setpoint.max_linear_accel_m_s2, 2.5);
  const std::string error = Check(leader);
  EXPECT_NE(error.find("the leader refuses to start: set-point limit max_linear_accel_m_s2"), std::string::npos)
      << error;
  EXPECT_NE(error.find("the follower validates against " +
                       std::to_string(static_cast<int>(follower_.setpoint.max_linear_accel_m_s2))),
            std::string::npos) << error;
  EXPECT_NE(error.find("this leader's config has 2.5"), std::string::npos) << error;
}

TEST_F(FollowerLimitsTest, AnotherModelConfigIsRefused) {
  FollowerConfig leader = Published();
  ++leader.model_fingerprint;
  EXPECT_NE(Check(leader).find("model config fingerprint"), std::string::npos);
}

// The leader keeps its set-points within the motors' top speeds from its own actuation.yaml: a leader whose drives
// differ (here one step rate) has another fingerprint, and is refused.
TEST_F(FollowerLimitsTest, AnotherActuationConfigIsAnotherFingerprint) {
  const std::filesystem::path config = DefaultDataDir() / "config";
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "fingerprint_actuation";
  std::filesystem::create_directories(dir);
  std::string text = ReadTextFile(config / "actuation.yaml");
  const std::size_t at = text.find("max_step_rate_hz: 4000");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, std::string("max_step_rate_hz: 4000").size(), "max_step_rate_hz: 3000");
  WriteFileAtomically(dir / "actuation.yaml", text);
  const std::uint64_t shipped = ModelFingerprint({config / "rsr.yaml", config / "actuation.yaml"});
  EXPECT_NE(ModelFingerprint({config / "rsr.yaml", dir / "actuation.yaml"}), shipped);
  EXPECT_EQ(ModelFingerprint({config / "rsr.yaml", config / "actuation.yaml"}), shipped);  // equal files, equal
  std::filesystem::remove_all(dir);
}

TEST_F(FollowerLimitsTest, NoFollowerHeardIsRefused) {
  // No tick: nothing published.
  EXPECT_THROW(CheckFollowerLimits(link_, LimitsOf(follower_), 0.01), std::runtime_error);
}

}  // namespace
}  // namespace robossis::teleop
