// The whole runtime on the hardware back ends, as `robossis teleop --device dhd --follower hal` runs it: the Force
// Dimension SDK back end against the fake SDK (tests/haptics/fake_dhd), the leader and follower units on real-time
// loops, and the LinuxCNC HAL follower driving a software stepgen in a HAL session the test starts and stops.

#include <dlfcn.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "src/core/config.h"
#include "src/teleop/teleop_session.h"
#include "tests/drivers/hal_session.h"
#include "tests/drivers/stepgen_counts.h"
#include "tests/haptics/fake_dhd/fake_dhd_control.h"
#include "tests/teleop/teleop_fixture.h"

namespace robossis::teleop {
namespace {

using robossis::testing::HalSession;

// The fake SDK's test controls, from the same library instance the back end opens.
class FakeSdkControls {
 public:
  FakeSdkControls() : handle_(dlopen(FAKE_DHD_LIBRARY, RTLD_NOW | RTLD_LOCAL)) {
    if (handle_ == nullptr) throw std::runtime_error(std::string("cannot open the fake SDK: ") + dlerror());
  }
  ~FakeSdkControls() { dlclose(handle_); }
  template <typename Fn>
  Fn Get(const char* name) const {
    Fn fn = reinterpret_cast<Fn>(dlsym(handle_, name));
    if (fn == nullptr) throw std::runtime_error(std::string("the fake SDK has no ") + name);
    return fn;
  }

 private:
  void* handle_;
};

void ExpectASafeSession(const nlohmann::ordered_json& s) {
  // The follower's deadlines, ticked or skipped (overruns): what a loaded machine cannot change.
  EXPECT_GT(s["follower_ticks"].get<double>(), 0);
  EXPECT_GT(s["follower_ticks"].get<double>() + s["follower_overruns"].get<double>(), 1000);
  EXPECT_EQ(s["follower_limit_violations"].get<double>(), 0);
  EXPECT_EQ(s["nonfinite_outputs"].get<double>(), 0);
  EXPECT_NE(s["follower_transitions"].dump().find("enabled"), std::string::npos) << s["follower_transitions"].dump();
}

TEST(TeleopHardwareTest, AReplayedFastHandDrivesTheStepgenWithinTheLimits) {
  HalSession hal(DefaultDataDir() / "hal" / "robossis-stepgen.hal");
  TeleopRequest request;
  request.device = "replay:" + testing::FastHand().string();
  request.follower = "hal";
  request.home_at_start = true;  // the operator's: the robot stands at its home pose (the stepgens count from 0)
  request.method = "proxy-safe";
  request.real_clock = true;
  request.duration_s = 4;
  const TeleopSetup setup = TeleopSetup::Load(DefaultDataDir(), testing::Rsr(), testing::Sigma7());
  const std::filesystem::path log = std::filesystem::path(::testing::TempDir()) / "teleop_hardware_replay.rlog";
  const TeleopOutputs out = RunTeleop(request, setup, log);
  ExpectASafeSession(out.summary);
  // Where the replay left the robot (it moves mostly in x-y: the rotary joints).
  robossis::testing::ExpectStepgenCountsMatchTheCommand();
  EXPECT_GT(out.summary["max_follower_speed_mm_s"].get<double>(), 5.0) << "the replay did not move the robot";
}

TEST(TeleopHardwareTest, TheFakeSigma7DrivesTheStepgenThroughTheWholeRuntime) {
  HalSession hal(DefaultDataDir() / "hal" / "robossis-stepgen.hal");
  FakeSdkControls sdk;
  sdk.Get<void (*)()>("fake_dhd_reset")();
  sdk.Get<void (*)(double)>("fake_dhd_set_tick")(1e-3);  // the leader's 1 kHz tick
  sdk.Get<void (*)(unsigned)>("fake_dhd_set_buttons")(1u);  // the operator holds the presence button
  FakeDhdState start{};
  sdk.Get<void (*)(FakeDhdState*)>("fake_dhd_get_state")(&start);
  // Once the follower is enabled (the leader renders no motion before), the hand lifts the handle 5 mm and holds it
  // there: the ring rises, the three legs extend (~1000 steps each).
  sdk.Get<void (*)(double, double, double, double)>("fake_dhd_set_hand_target_after")(1.0, start.p[0], start.p[1],
                                                                                        start.p[2] + 0.005);

  TeleopRequest request;
  request.device = "dhd:lib=" FAKE_DHD_LIBRARY;
  request.follower = "hal";
  request.home_at_start = true;  // the operator's: the robot stands at its home pose (the stepgens count from 0)
  request.method = "proxy-safe";
  request.real_clock = true;
  request.duration_s = 4;
  const TeleopSetup setup = TeleopSetup::Load(DefaultDataDir(), testing::Rsr(), testing::Sigma7());
  const std::filesystem::path log = std::filesystem::path(::testing::TempDir()) / "teleop_hardware.rlog";
  const TeleopOutputs out = RunTeleop(request, setup, log);

  ExpectASafeSession(out.summary);
  EXPECT_GT(robossis::testing::ExpectStepgenCountsMatchTheCommand(), 1000)
      << "the 5 mm hand motion did not reach the drives; summary: " << out.summary.dump();
}

}  // namespace
}  // namespace robossis::teleop
