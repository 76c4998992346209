// The panel's own session on the robot's drives (`robossis panel --follower hal`): the follower unit's 10 kHz
// actuation into the LinuxCNC HAL follower, driving a software stepgen in a HAL session the test starts and
// stops. Once through the session's API (panel::LocalSessionBackend on its real-time loops), once through the
// window (the `robossis panel` binary under Xvfb), as a person at the surgical unit would jog the robot.

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "robot/follower.h"
#include "robot/rsr_model.h"
#include "robot/sigma7_model.h"
#include "src/core/config.h"
#include "src/core/rt/clock.h"
#include "src/core/units.h"
#include "src/panel/local_session_backend.h"
#include "src/panel/view_model.h"
#include "src/teleop/teleop_session.h"
#include "tests/drivers/hal_session.h"
#include "tests/drivers/stepgen_counts.h"
#include "tests/panel/panel_run.h"

namespace robossis::panel {
namespace {

using robossis::testing::HalSession;
using teleop::OperatingState;

std::filesystem::path StepgenHal() { return DefaultDataDir() / "hal" / "robossis-stepgen.hal"; }

// Polls the follower's status until `done` holds or `timeout_s` of wall-clock time passed; returns the last status.
template <typename Done>
teleop::FollowerStatusMessage WaitFor(LocalSessionBackend& backend, double timeout_s, Done done) {
  teleop::FollowerStatusMessage status;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < until) {
    if (backend.ReadStatus(status) && done(status)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return status;
}

// What a failed jog's messages name: the follower's state and fault reason (the back end's fault), its rejected
// set-points by reason, its watchdog holds and both loops' overruns.
std::string FollowerReport(LocalSessionBackend& backend, const teleop::FollowerStatusMessage& status) {
  std::ostringstream out;
  out << "follower " << teleop::ToString(status.state) << " (reason " << teleop::ToString(status.fault_reason)
      << ", back end " << robot::ToString(static_cast<robot::FollowerFault>(status.back_end_fault)) << "), "
      << status.setpoints_accepted << " set-points accepted, " << status.setpoints_rejected << " rejected";
  LoopHealth health;
  if (!backend.ReadHealth(health)) return out.str();
  for (int v = 0; v < teleop::kNumSetPointVerdicts; ++v) {
    if (v == static_cast<int>(teleop::SetPointVerdict::kAccepted) || health.setpoints_by_verdict[v] == 0) continue;
    out << ", " << teleop::ToString(static_cast<teleop::SetPointVerdict>(v)) << " " << health.setpoints_by_verdict[v];
  }
  out << "; " << health.watchdog_holds << " watchdog holds, overruns: follower " << health.follower_loop.overruns
      << ", leader " << health.leader_loop.overruns;
  return out.str();
}

// The panel's own session on the HAL drives, as `robossis panel --follower hal` builds it, started.
struct HalPanelSession {
  static JogLimits Limits(const teleop::TeleopSetup& setup) {
    JogLimits limits;
    limits.setpoint = setup.follower.setpoint;
    return limits;
  }
  HalPanelSession()
      : backend(model, teleop::MakeFollowerBackEnd("hal", setup, 0), setup.follower, setup.actuation, Limits(setup),
                setup.transfer.rates, clock) {
    backend.Start();
  }
  const robot::RsrModel model = robot::RsrModel::FromYaml(DefaultDataDir() / "config" / "rsr.yaml");
  const robot::Sigma7Model sigma7 = robot::Sigma7Model::FromYaml(DefaultDataDir() / "config" / "sigma7.yaml");
  const teleop::TeleopSetup setup = teleop::TeleopSetup::Load(DefaultDataDir(), model, sigma7);
  const rt::MonotonicClock clock;
  LocalSessionBackend backend;
};

bool AnyStepgenEnabled() {
  for (int m = 0; m < 6; ++m)
    if (HalSession::GetBit("stepgen." + std::to_string(m) + ".enable")) return true;
  return false;
}

TEST(PanelHalTest, AJogMovesTheDrivesByTheRequestedAmountAndTheEStopCutsThem) {
  HalSession hal(StepgenHal());
  HalPanelSession session;
  LocalSessionBackend& backend = session.backend;

  ASSERT_TRUE(backend.SendCommand(teleop::StateCommand::kHome));
  ASSERT_TRUE(backend.SendCommand(teleop::StateCommand::kEnable));
  teleop::FollowerStatusMessage status =
      WaitFor(backend, 10, [](const auto& s) { return s.state == OperatingState::kReady; });
  ASSERT_EQ(status.state, OperatingState::kReady) << teleop::ToString(status.state);
  const Eigen::Vector3d start = PoseOf(status).translation();

  JogRequest jog;
  jog.axis = JogAxis::kZ;
  jog.amount = MmToM(2);
  jog.duration_s = 1;
  const JogVerdict verdict = backend.StartJog(jog);
  ASSERT_TRUE(verdict.accepted) << verdict.reason;
  // The jog is over when its last set-point is commanded and the drives got there; waited for, not timed, so that a
  // loaded machine only makes it later.
  status = WaitFor(backend, 60, [&](const auto& s) {
    Eigen::Isometry3d commanded;
    return backend.ReadCommandedPose(commanded) &&
           (commanded.translation() - verdict.X_FM_end.translation()).norm() < 1e-6 &&
           std::abs(PoseOf(s).translation().z() - start.z() - MmToM(2)) < MmToM(0.01);
  });
  const Eigen::Vector3d moved = PoseOf(status).translation() - start;
  const std::string report = FollowerReport(backend, status);
  EXPECT_NEAR(MToMm(moved.z()), 2, 0.02) << report;
  EXPECT_NEAR(MToMm(moved.head<2>().norm()), 0, 0.02) << report;
  EXPECT_GT(testing::ExpectStepgenCountsMatchTheCommand(), 200) << "the jog did not reach the drives; " << report;
  EXPECT_EQ(status.setpoints_rejected, 0u) << report;

  ASSERT_TRUE(backend.SendCommand(teleop::StateCommand::kEStop));
  status = WaitFor(backend, 5, [](const auto& s) { return s.state == OperatingState::kEStop; });
  EXPECT_EQ(status.state, OperatingState::kEStop);
  // HAL's servo thread passes the dropped enables to the stepgens in its next period: polled, not slept for.
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (AnyStepgenEnabled() && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  for (int m = 0; m < 6; ++m)
    EXPECT_FALSE(HalSession::GetBit("stepgen." + std::to_string(m) + ".enable")) << "motor " << m;
  backend.Stop();
}

// The follower process as a person would run it at the robot, in a child process of the test: its own session on
// the HAL drives, homed, enabled, jogged `jog_mm` up, then left running until killed. Reports through `fd` how far
// the robot measured it moved (mm, as text), or a negative number if it could not.
[[noreturn]] void RunFollowerUntilKilled(int fd, double jog_mm) {
  double moved_mm = -1;
  try {
    auto* session = new HalPanelSession;  // never freed: the process is killed
    LocalSessionBackend* backend = &session->backend;
    backend->SendCommand(teleop::StateCommand::kHome);
    backend->SendCommand(teleop::StateCommand::kEnable);
    teleop::FollowerStatusMessage status =
        WaitFor(*backend, 30, [](const auto& s) { return s.state == OperatingState::kReady; });
    const double z0 = PoseOf(status).translation().z();
    JogRequest jog;
    jog.axis = JogAxis::kZ;
    jog.amount = MmToM(jog_mm);
    jog.timing = JogTiming::kSpeed;
    jog.peak_speed = 0.9 * session->setup.follower.setpoint.caps.max_linear_speed_m_s;  // within the set-point caps
    if (status.state == OperatingState::kReady && backend->StartJog(jog).accepted) {
      status = WaitFor(*backend, 60, [&](const auto& s) {
        return std::abs(MToMm(PoseOf(s).translation().z() - z0) - jog_mm) < 0.01;
      });
      moved_mm = MToMm(PoseOf(status).translation().z() - z0);
    }
  } catch (const std::exception&) {
  }
  const std::string text = std::to_string(moved_mm) + "\n";
  if (write(fd, text.data(), text.size()) < 0) _exit(1);
  for (;;) pause();
}

// A follower killed (kill -9: no destructor, no disable) after it moved the robot, then restarted: it starts
// disabled and unhomed, and refuses an enable with the reason in its status until the operator homes it. Before,
// the enable homed it where it stood (every later pose offset by the move). HAL keeps a killed userspace
// component registered under its name (`halcmd unload` does not remove it), so the restarted follower needs HAL
// restarted too, as after a power cut; the drives, cut by HAL's watchdog when the heartbeat stopped, count from 0.
TEST(PanelHalTest, AKilledFollowerRestartsDisabledAndUnhomedAndRefusesEnableUntilHomed) {
  auto hal = std::make_unique<HalSession>(StepgenHal());
  int pipe_fd[2];
  ASSERT_EQ(pipe(pipe_fd), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    close(pipe_fd[0]);
    RunFollowerUntilKilled(pipe_fd[1], 20);
  }
  close(pipe_fd[1]);
  char text[64] = {};
  const ssize_t got = read(pipe_fd[0], text, sizeof text - 1);  // blocks until the child moved (or gave up)
  close(pipe_fd[0]);
  kill(child, SIGKILL);
  int child_status = 0;
  ASSERT_EQ(waitpid(child, &child_status, 0), child);
  ASSERT_GT(got, 0);
  const double moved_mm = std::atof(text);
  std::printf("the killed follower had moved the robot %.3f mm\n", moved_mm);
  EXPECT_NEAR(moved_mm, 20, 0.01) << "the follower did not make its move before it was killed";
  // HAL's watchdog cut the drives when the killed follower's heartbeat stopped.
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (AnyStepgenEnabled() && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_FALSE(AnyStepgenEnabled()) << "HAL's watchdog did not cut the killed follower's drives";
  hal.reset();
  hal = std::make_unique<HalSession>(StepgenHal());

  HalPanelSession session;
  LocalSessionBackend& backend = session.backend;
  teleop::FollowerStatusMessage status = WaitFor(backend, 10, [](const auto&) { return true; });
  EXPECT_EQ(status.state, OperatingState::kDisabled);
  EXPECT_FALSE(status.homed);
  ASSERT_TRUE(backend.SendCommand(teleop::StateCommand::kEnable));
  status = WaitFor(backend, 10, [](const auto& s) { return s.fault_reason == teleop::FaultReason::kNotHomed; });
  std::printf("the restarted follower after an enable: state %s, reason %s, homed %d\n", teleop::ToString(status.state),
              teleop::ToString(status.fault_reason), static_cast<int>(status.homed));
  EXPECT_EQ(status.state, OperatingState::kDisabled) << teleop::ToString(status.state);
  EXPECT_EQ(status.fault_reason, teleop::FaultReason::kNotHomed) << teleop::ToString(status.fault_reason);
  EXPECT_FALSE(status.homed);
  EXPECT_NE(BuildViewModel(session.model, status).refusal_text.find("not homed"), std::string::npos);
  EXPECT_FALSE(AnyStepgenEnabled());

  // The operator homes it (the robot stands at its home pose now), then enables it.
  ASSERT_TRUE(backend.SendCommand(teleop::StateCommand::kHome));
  ASSERT_TRUE(backend.SendCommand(teleop::StateCommand::kEnable));
  status = WaitFor(backend, 10, [](const auto& s) { return s.state == OperatingState::kReady; });
  EXPECT_EQ(status.state, OperatingState::kReady) << teleop::ToString(status.state);
  EXPECT_TRUE(status.homed);
  EXPECT_EQ(status.fault_reason, teleop::FaultReason::kNone);
  backend.Stop();
}

// The script waits for the conditions, never for a time: with fixed times (home at 0.2 s, the jog at 2.0 s, quit at
// 6.0 s) a loaded machine could still be homing when the jog was clicked (refused), or quit before the stepgens had
// made the jog's last steps, and HAL's watchdog then cut the drives short of the command.
TEST(PanelHalTest, TheWindowJogsTheDrives) {
  HalSession hal(StepgenHal());
  const auto dir = testing::TestDir("hal_jog");
  const testing::PanelRun run = testing::RunPanel(dir,
                                                  "0.2 click home\n"
                                                  "0.2 click enable\n"
                                                  "0.2 wait state ready\n"
                                                  "0.2 set jog.axis z\n"
                                                  "0.2 set jog.amount 2\n"
                                                  "0.2 set jog.timing duration\n"
                                                  "0.2 set jog.duration_s 1\n"
                                                  "0.2 click jog.go\n"
                                                  "0.2 wait jog.done\n"
                                                  "0.2 quit\n",
                                                  "--no-slice --no-bone --follower hal");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_FALSE(run.json.is_discarded()) << run.output;
  EXPECT_EQ(run.json["follower"], "hal");
  EXPECT_EQ(run.json["state"], "ready") << run.output;
  const robot::RsrModel model = robot::RsrModel::FromYaml(DefaultDataDir() / "config" / "rsr.yaml");
  EXPECT_NEAR(run.json["pose_mm_deg"][2].get<double>(), MToMm(model.geometry().X_FM_home.translation().z()) + 2,
              0.02);
  EXPECT_EQ(run.json["setpoints_rejected"].get<int>(), 0);
  EXPECT_GT(testing::ExpectStepgenCountsMatchTheCommand(), 200) << "the jog did not reach the drives";
}

}  // namespace
}  // namespace robossis::panel
