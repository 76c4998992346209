// Bilateral feedback: the follower's load on the hand. The leader maps a known follower wrench into the device frame
// (the transfer's R_FO and scale, inverted as energy requires) with the gain, within 2 %; shows nothing while the
// follower is not following; allocates nothing per tick. The wrench estimate inverts the statics. The passivity
// observer never goes negative with a controller, and does without one at >= 25 ms against a hard wall. The
// in-process link's delay line delivers nothing early.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "haptics/device/simulated_device.h"
#include "robot/rsr_kinematics.h"
#include "robot/sim/rsr_simulation.h"
#include "src/core/pose.h"
#include "src/core/units.h"
#include "src/teleop/bilateral_harness.h"
#include "src/teleop/delay_line.h"
#include "src/teleop/in_process_link.h"
#include "src/teleop/leader_unit.h"
#include "src/teleop/teleop_session.h"
#include "src/teleop/wrench_estimate.h"
#include "tests/support/alloc_counter.h"
#include "tests/support/scratch_dir.h"
#include "tests/teleop/teleop_fixture.h"

namespace robossis::teleop {
namespace {

using namespace testing;

haptics::HandScript StillHand() {
  haptics::HandScript s;
  s.name = "still";
  const Eigen::Vector3d c = Sigma7().p_center_O();
  s.target = [c](double) {
    haptics::HandTarget h;
    h.X_OH.translation() = c;
    return h;
  };
  return s;
}

// A leader with a still hand, hearing a follower whose status carries `wrench_F`.
struct FeedbackHarness {
  FeedbackHarness(const transfer::HcToRsrFrame& frame, FeedbackPassivityScheme scheme,
                  const haptics::HandParams& hand = Haptics().hand, bool detect_let_go = false,
                  haptics::HandScript script = StillHand())
      : config(Bilateral(scheme, detect_let_go)),
        transfer(WithFrame(frame)),
        device(Sigma7(), Haptics().device, hand, std::move(script), config.device),
        renderer(Renderer("proxy-safe", config.rate_hz)),
        link(100),
        unit(config, transfer, Rsr(), device, *renderer, link, Rsr().geometry().X_FM_home, 7) {
    device.EnableForces(true);
    link.follower_speaks = true;
    link.follower.state = OperatingState::kEnabled;
    link.follower.wrench_source = WrenchSource::kDriveEfforts;
    PoseToArrays(Rsr().geometry().X_FM_home, link.follower.p_FM, link.follower.q_FM);
  }
  static LeaderConfig Bilateral(FeedbackPassivityScheme scheme, bool detect_let_go) {
    LeaderConfig c = Leader();
    c.feedback.mode = FeedbackMode::kBilateral;
    c.feedback.passivity.scheme = scheme;
    c.feedback.detect_let_go = detect_let_go;
    return c;
  }
  static transfer::TransferConfig WithFrame(const transfer::HcToRsrFrame& frame) {
    transfer::TransferConfig t = Transfer();
    static_cast<transfer::HcToRsrFrame&>(t.mapping) = frame;
    return t;
  }
  // Ticks the leader; the follower's port books the energy an ideal follower (no delay) would: the wrench times the
  // hand's twist mapped into F (the network scheme's budget grows as a real follower's would).
  LeaderTickRecord Run(double seconds) {
    LeaderTickRecord r;
    const auto ticks = static_cast<int>(seconds * config.rate_hz);
    const transfer::HcToRsrFrame& frame = transfer.mapping;
    for (int k = 0; k < ticks; ++k) {
      clock.AdvanceNs(static_cast<std::int64_t>(1e9 / config.rate_hz));
      unit.Tick(clock.now_ns());
      while (unit.records().TryPop(r)) {
        const Eigen::Vector3d v_F = frame.LinearToRsr(Eigen::Vector3d(r.v_O[0], r.v_O[1], r.v_O[2]));
        const Eigen::Vector3d w_F = frame.AngularToRsr(Eigen::Vector3d(r.w_O[0], r.w_O[1], r.w_O[2]));
        const FollowerStatusMessage& f = link.follower;
        const double power = f.wrench_F[0] * v_F[0] + f.wrench_F[1] * v_F[1] + f.wrench_F[2] * v_F[2] +
                             f.wrench_F[3] * w_F[0] + f.wrench_F[4] * w_F[1] + f.wrench_F[5] * w_F[2];
        if (power > 0) link.follower.port_energy_in_j += power / config.rate_hz;
      }
    }
    return r;
  }
  LeaderConfig config;
  transfer::TransferConfig transfer;
  haptics::SimulatedDevice device;
  std::unique_ptr<haptics::HapticRenderer> renderer;
  RecordingLeaderLink link;
  LeaderUnit unit;
  rt::SimulatedClock clock;
};

Vector6d KnownWrench() {
  Vector6d w;
  w << 100, -50, 200, 2, -1, 3;  // N at P, N·m about P, in F: 8.6 N and 0.09 N·m at the hand below the caps
  return w;
}

TEST(BilateralFeedbackTest, AKnownFollowerWrenchIsShownScaledAndRotatedWithin2Percent) {
  transfer::HcToRsrFrame frame;
  frame.R_FO = RotationFromRpy(Eigen::Vector3d(DegToRad(25), DegToRad(-40), DegToRad(110)));
  frame.translation_scale = 1.5;
  // The mapping observed alone: a constant load on a hand that first yields along it is an energy source, which every
  // scheme that keeps the hand passive (classic, network) cuts while the hand yields.
  for (const FeedbackPassivityScheme scheme : {FeedbackPassivityScheme::kOff}) {
    SCOPED_TRACE(ToString(scheme));
    FeedbackHarness h(frame, scheme);
    const Vector6d W = KnownWrench();
    for (int i = 0; i < 6; ++i) h.link.follower.wrench_F[i] = W[i];
    const LeaderTickRecord r = h.Run(3.0);  // the hand settles against the force
    const double g = h.config.feedback.gain;
    const Eigen::Vector3d f_expected = g * frame.translation_scale * (frame.R_FO.transpose() * W.head<3>());
    const Eigen::Vector3d tau_expected = g * frame.rotation_scale * (frame.R_FO.transpose() * W.tail<3>());
    const Eigen::Vector3d f_shown(r.feedback_O[0], r.feedback_O[1], r.feedback_O[2]);
    const Eigen::Vector3d tau_shown(r.feedback_O[3], r.feedback_O[4], r.feedback_O[5]);
    EXPECT_LT((f_shown - f_expected).norm(), 0.02 * f_expected.norm()) << f_shown.transpose();
    EXPECT_LT((tau_shown - tau_expected).norm(), 0.02 * tau_expected.norm()) << tau_shown.transpose();
    // What the device was sent (walls + load; free space at home: the load alone).
    EXPECT_LT((h.device.last_force_O() - f_expected).norm(), 0.02 * f_expected.norm());
    // Unrotated or unscaled, the force would be far off (the check above can fail).
    EXPECT_GT((g * W.head<3>() - f_expected).norm(), 0.3 * f_expected.norm());
  }
}

TEST(BilateralFeedbackTest, NothingIsShownWhileTheFollowerDoesNotFollow) {
  struct Case {
    const char* name;
    OperatingState state;
    WrenchSource source;
  };
  for (const Case& c : {Case{"ready (holding)", OperatingState::kReady, WrenchSource::kDriveEfforts},
                        Case{"clutched", OperatingState::kClutched, WrenchSource::kDriveEfforts},
                        Case{"disabled", OperatingState::kDisabled, WrenchSource::kDriveEfforts},
                        Case{"enabled but holding (no wrench)", OperatingState::kEnabled, WrenchSource::kNone}}) {
    SCOPED_TRACE(c.name);
    FeedbackHarness h(transfer::HcToRsrFrame{}, FeedbackPassivityScheme::kOff);
    const Vector6d W = KnownWrench();
    for (int i = 0; i < 6; ++i) h.link.follower.wrench_F[i] = W[i];
    h.link.follower.state = c.state;
    h.link.follower.wrench_source = c.source;
    const LeaderTickRecord r = h.Run(1.0);
    for (double v : r.feedback_O) EXPECT_EQ(v, 0.0);
    EXPECT_EQ(r.feedback_shown, 0);
    EXPECT_LT(h.device.last_force_O().norm(), 1e-9);
  }
}

TEST(BilateralFeedbackTest, FeedbackTickDoesNotAllocate) {
  FeedbackHarness h(transfer::HcToRsrFrame{}, FeedbackPassivityScheme::kNetwork);
  const Vector6d W = KnownWrench();
  for (int i = 0; i < 6; ++i) h.link.follower.wrench_F[i] = W[i];
  for (int k = 0; k < 200; ++k) {  // warm up
    h.clock.AdvanceNs(1'000'000);
    h.unit.Tick(h.clock.now_ns());
  }
  LeaderTickRecord r;
  ::robossis::testing::AllocationCounter counter;
  for (int k = 0; k < 2000; ++k) {
    h.clock.AdvanceNs(1'000'000);
    h.link.follower.port_energy_in_j += 1e-4;  // the network budget moves
    h.unit.Tick(h.clock.now_ns());
    h.unit.records().TryPop(r);
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_EQ(r.feedback_shown, 1);
}

// A hand moving 10 mm back and forth along x at 1 Hz about the workspace centre.
haptics::HandScript SwayingHand() {
  haptics::HandScript s;
  s.name = "swaying";
  const Eigen::Vector3d c = Sigma7().p_center_O();
  s.target = [c](double t) {
    constexpr double kW = 2 * 3.14159265358979323846;
    haptics::HandTarget h;
    h.X_OH.translation() = c + Eigen::Vector3d(0.01 * std::sin(kW * t), 0, 0);
    h.v_O = Eigen::Vector3d(0.01 * kW * std::cos(kW * t), 0, 0);
    return h;
  };
  return s;
}

// The feedback port's books, the run's and the passivity observer's own, count the force the device actually
// displayed: a device whose forces are disabled (it writes zero) gives the hand nothing and takes nothing from it,
// however the hand moves against the load the controller was asked to show. An observer that booked the controller's
// own output counted the energy of a force never shown (its E_in − E_out moved), so this test can fail; with the
// forces on, the same motion books both ways.
TEST(BilateralFeedbackTest, TheBooksCountOnlyTheForceTheDeviceDisplayed) {
  for (const bool forces : {false, true}) {
    SCOPED_TRACE(forces ? "forces on" : "forces disabled");
    FeedbackHarness h(transfer::HcToRsrFrame{}, FeedbackPassivityScheme::kOff, Haptics().hand, false, SwayingHand());
    h.device.EnableForces(forces);
    const Vector6d W = KnownWrench();
    for (int i = 0; i < 6; ++i) h.link.follower.wrench_F[i] = W[i];
    const LeaderTickRecord r = h.Run(2.0);
    EXPECT_EQ(r.feedback_shown, 1);
    EXPECT_EQ(r.force_zeroed, forces ? 0 : 1);
    if (forces) {
      EXPECT_GT(r.feedback_energy_in_j, 1e-3);
      EXPECT_GT(r.feedback_energy_out_j, 1e-3);
    } else {
      EXPECT_EQ(r.feedback_energy_in_j, 0.0);
      EXPECT_EQ(r.feedback_energy_out_j, 0.0);
      EXPECT_EQ(h.unit.counters().max_feedback_energy_j, 0.0);
      EXPECT_EQ(r.passivity_observed_j, 0.0);
    }
  }
}

// The operator lets go of the device while the follower's load is shown (the presence button kept pressed): the
// handle is left with its own mass, no grasp. With the let-go detector the leader replaces the load by its damper and
// the device rests (< 1 mm/s) within 1 s with no load on it, with or without the passivity controller; without the
// detector and with the controller off, the load keeps pushing the device into its mechanical limit, so this test
// can fail. A held device never looks let go.
TEST(LetGoRuntimeTest, TheLeaderDampsALetGoDeviceToRestAndNeverJudgesAHeldOneLetGo) {
  haptics::HandParams let_go = Haptics().hand;
  let_go.mass_kg = LetGoConfig{}.device_mass_kg;  // the handle alone
  let_go.stiffness_n_per_m = 0;
  let_go.damping_ns_per_m = 0;
  struct Case {
    FeedbackPassivityScheme scheme;
    bool detect;
  };
  for (const Case c : {Case{FeedbackPassivityScheme::kOff, false}, Case{FeedbackPassivityScheme::kOff, true},
                       Case{FeedbackPassivityScheme::kClassic, true}}) {
    const bool detect = c.detect;
    SCOPED_TRACE(std::string(ToString(c.scheme)) + (detect ? " with the detector" : " without the detector"));
    FeedbackHarness h(transfer::HcToRsrFrame{}, c.scheme, let_go, detect);
    const Vector6d W = KnownWrench();
    for (int i = 0; i < 6; ++i) h.link.follower.wrench_F[i] = W[i];
    const LeaderTickRecord r = h.Run(1.0);
    const double speed = std::sqrt(r.v_O[0] * r.v_O[0] + r.v_O[1] * r.v_O[1] + r.v_O[2] * r.v_O[2]);
    const double force = std::sqrt(r.f_O[0] * r.f_O[0] + r.f_O[1] * r.f_O[1] + r.f_O[2] * r.f_O[2]);
    if (detect) {
      EXPECT_EQ(r.let_go, 1);
      EXPECT_LT(speed, 1e-3);
      EXPECT_LT(force, 0.1);
    } else {
      EXPECT_EQ(r.let_go, 0);
      EXPECT_GT(force, 1.0);
    }
  }
  FeedbackHarness held(transfer::HcToRsrFrame{}, FeedbackPassivityScheme::kClassic, Haptics().hand, true);
  const Vector6d W = KnownWrench();
  for (int i = 0; i < 6; ++i) held.link.follower.wrench_F[i] = W[i];
  EXPECT_EQ(held.Run(3.0).let_go, 0);  // latched once believed: never, over the whole run
}

// The whole runtime: the Bullet follower pulled by the paper's 517 N, 74 N·m, the hand's loop, 100 ms each way. The
// load reaches the hand (scaled by the gain, within the caps) and the classic controller keeps the port passive at
// every tick; with the walls alone nothing of it is shown.
// The runtime's setup with the teleop runs' speed caps (100 mm/s, 20 deg/s) and a bilateral request: the Bullet
// follower pulled by the paper's 517 N, 74 N·m, the simulated hand's loop, 100 ms each way.
TeleopSetup FastSetup() {
  TeleopSetup setup = TeleopSetup::Load(DefaultDataDir(), Rsr(), Sigma7());
  setup.transfer.caps.max_linear_speed_m_s = 0.1;
  setup.transfer.caps.max_angular_speed_rad_s = DegToRad(20);
  setup.follower.setpoint.caps = setup.transfer.caps;
  return setup;
}

TeleopRequest LoadedRequest(const char* passivity) {
  TeleopRequest request;
  request.device = "sim";
  request.follower = "sim";
  request.duration_s = 3;
  request.sim_load_n = 517;
  request.sim_load_nm = 74;
  request.link_delay_s = 0.1;
  request.feedback = "bilateral";
  request.feedback_passivity = passivity;
  return request;
}

TEST(BilateralSessionTest, TheMusclesLoadIsFeltPassivelyBehindADelayAndNotWithTheWallsAlone) {
  const robossis::testing::ScratchDir dir("robossis_bilateral_session");
  std::filesystem::create_directories(dir.path());
  const TeleopSetup setup = FastSetup();
  TeleopRequest request = LoadedRequest("classic");
  const auto bilateral = RunTeleop(request, setup, dir.path() / "bilateral.rlog").summary;
  const double felt = bilateral["max_feedback_force_n"].get<double>();
  EXPECT_GT(felt, 0.9 * 0.025 * 517);
  EXPECT_LE(felt, 15.0 + 1e-9);
  EXPECT_LE(bilateral["feedback_energy_max_j"].get<double>(), 1e-9);
  EXPECT_GE(bilateral["passivity_observer_min_j"].get<double>(), -1e-9);
  EXPECT_EQ(bilateral["follower_limit_violations"].get<int>(), 0);
  // The shown load against the muscles' true load (the simulation's), mapped and with the delay removed: judged.
  ASSERT_TRUE(bilateral["feedback_force_error_n_rms"].is_number());
  EXPECT_LT(bilateral["feedback_force_error_n_rms"].get<double>(), 0.9 * 0.025 * 517);
  request.feedback = "walls";
  const auto walls = RunTeleop(request, setup, dir.path() / "walls.rlog").summary;
  EXPECT_EQ(walls["max_feedback_force_n"].get<double>(), 0.0);
}

// The let-go detector in the whole runtime while the simulated hand holds on, the 517 N load shown behind 0-100 ms,
// with both schemes: it never believes a let-go. Judged "lighter than the device" (the apparent mass below 1.5x the
// device's, with no bound below), the held hand's own push, unbalanced where the taper faded the load it held
// against, was taken for a let-go within the first 0.3 s (classic at 50 and 100 ms, network at 0, 50 and 100 ms), so
// this test can fail.
TEST(LetGoRuntimeTest, AHeldHandIsNeverTakenForALetGoBehindADelay) {
  const robossis::testing::ScratchDir dir("robossis_let_go_held");
  std::filesystem::create_directories(dir.path());
  // `robossis teleop --max-speed-mm-s 100`: the angular cap stays the paper's.
  TeleopSetup setup = TeleopSetup::Load(DefaultDataDir(), Rsr(), Sigma7());
  setup.transfer.caps.max_linear_speed_m_s = 0.1;
  setup.follower.setpoint.caps = setup.transfer.caps;
  for (const char* scheme : {"classic", "network"}) {
    for (const double delay_s : {0.0, 0.05, 0.1}) {
      SCOPED_TRACE(std::string(scheme) + " at " + std::to_string(delay_s) + " s");
      TeleopRequest request = LoadedRequest(scheme);
      request.duration_s = 1;
      request.link_delay_s = delay_s;
      request.let_go_detector = true;
      const auto summary = RunTeleop(request, setup, dir.path() / "held.rlog").summary;
      EXPECT_EQ(summary["let_go_detected_s"].get<double>(), -1.0);
      EXPECT_GT(summary["max_feedback_force_n"].get<double>(), 1.0);  // the load was shown: the detector judged
    }
  }
}

// The network form at both ports in the runtime: the set-points carry the hand's energy, and the Bullet follower
// gives the muscles no more than the hand put in (divided by the gain), at every 10 kHz tick, behind 100 ms; the
// hand gets no more than it gave. Without the follower's half the robot stretches the muscles on the hand's motion
// alone, far beyond what the hand paid for, so this test can fail.
TEST(BilateralSessionTest, TheNetworkFormBoundsWhatTheFollowerGivesTheEnvironment) {
  const robossis::testing::ScratchDir dir("robossis_bilateral_network");
  std::filesystem::create_directories(dir.path());
  const auto summary = RunTeleop(LoadedRequest("network"), FastSetup(), dir.path() / "network.rlog").summary;
  // The one-tick lag of the measured wrench: (W(k) − W(k−1))·dq per step, the physics' 1 ms steps at the speed cap.
  EXPECT_LE(summary["follower_port_excess_max_j"].get<double>(), 0.02);
  EXPECT_LE(summary["feedback_energy_max_j"].get<double>(), 1e-9);
  EXPECT_GT(summary["max_feedback_force_n"].get<double>(), 1.0);  // the load is shown: the bound is not idle
  EXPECT_EQ(summary["follower_limit_violations"].get<int>(), 0);
}

TEST(WrenchEstimateTest, InvertsTheStaticsAndRemovesTheCarriedWeight) {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-1, 1);
  WrenchEstimateConfig config;
  config.carried_mass_kg = 3.2;
  config.com_M = Eigen::Vector3d(0.01, -0.02, 0.05);
  config.gravity_F_mps2 = Eigen::Vector3d(0, -9.81, 0);
  for (int k = 0; k < 200; ++k) {
    Eigen::Isometry3d X = Rsr().geometry().X_FM_home;
    X.translation() += 0.03 * Eigen::Vector3d(u(gen), u(gen), u(gen));
    X.linear() = RotationFromVector(0.1 * Eigen::Vector3d(u(gen), u(gen), u(gen))) * X.linear();
    if (!robot::IsPoseFeasible(Rsr(), X)) continue;
    Vector6d W;
    W << 500 * u(gen), 500 * u(gen), 500 * u(gen), 70 * u(gen), 70 * u(gen), 70 * u(gen);
    // The drives hold the load and the weight.
    const Eigen::Vector3d weight = config.carried_mass_kg * config.gravity_F_mps2;
    Vector6d total = W;
    total.head<3>() += weight;
    total.tail<3>() += (X.linear() * config.com_M).cross(weight);
    const robot::RsrStaticsResult q = robot::CalcActuatorEfforts(Rsr(), X, total);
    ASSERT_FALSE(q.singular);
    robot::RsrJointVector effort;
    effort << q.rotary_torque_nm, q.linear_force_n;
    const Vector6d estimate = EstimateExternalWrench(Rsr(), X, effort, config);
    EXPECT_LT((estimate - W).norm(), 1e-6 * W.norm()) << estimate.transpose() << " vs " << W.transpose();
  }
}

// The Bullet follower holding the ring at home against the muscles (517 N along the femur axis, 74 N·m about it):
// the estimate from its drive efforts, the ring's and the arms' weight removed, is the traction it applies, as it
// reports it with the measurement (the true wrench summary.json judges the shown load against: same frame, same
// point).
TEST(WrenchEstimateTest, TheBulletFollowersEffortsGiveTheMusclesTraction) {
  const sim::SimConfig config = sim::LoadSimConfig(ConfigPath("sim.yaml"), DefaultDataDir());
  const Eigen::Isometry3d home = Rsr().geometry().X_FM_home;
  sim::MuscleTraction traction(config.traction, Eigen::Vector3d::UnitZ(),
                               Eigen::Vector3d(0, 0, config.bone.fracture_site_z_m), home);
  traction.Calibrate(home, home.linear(), 517, 74);
  sim::SimOptions options;
  options.with_bone = false;
  sim::RsrSimulation simulation(Rsr(), config, nullptr, &traction, home, options);
  for (int k = 0; k < 1000; ++k) simulation.Step();  // 1 s: settled
  WrenchEstimateConfig estimate_config;
  estimate_config.carried_mass_kg = config.masses.moving_ring_kg;
  estimate_config.gravity_F_mps2 = config.physics.gravity_F_mps2;
  estimate_config.remove_arm_weight = true;
  estimate_config.arm_masses = config.masses;
  const robot::RsrFollowerState state = simulation.State();
  const Vector6d estimate = EstimateExternalWrench(Rsr(), state.X_FM, state.effort, estimate_config);
  ASSERT_TRUE(state.true_wrench_known);
  const Vector6d truth = state.true_wrench_F;
  EXPECT_EQ(truth, simulation.diagnostics().traction.wrench_P_F);
  ASSERT_GT(truth.head<3>().norm(), 500);
  EXPECT_LT((estimate.head<3>() - truth.head<3>()).norm(), 0.02 * truth.head<3>().norm())
      << estimate.transpose() << " vs " << truth.transpose();
  EXPECT_LT((estimate.tail<3>() - truth.tail<3>()).norm(), 0.02 * truth.tail<3>().norm())
      << estimate.transpose() << " vs " << truth.transpose();
}

TEST(DelayLineTest, DeliversTheNewestMessageOnlyOnceItsDelayHasPassed) {
  DelayLine<int> line(25'000'000, 64);
  line.Send(1, 0);
  line.Send(2, 1'000'000);
  int v = 0;
  std::int64_t due = 0;
  EXPECT_FALSE(line.Take(24'999'999, v, due));
  ASSERT_TRUE(line.Take(25'000'000, v, due));
  EXPECT_EQ(v, 1);
  EXPECT_FALSE(line.Take(25'500'000, v, due));
  ASSERT_TRUE(line.Take(40'000'000, v, due));
  EXPECT_EQ(v, 2);
  EXPECT_EQ(due, 26'000'000);
}

// --link-delay-ms: both directions of the in-process link arrive that much later, the set-point stamped with its
// arrival (the follower judges freshness from it); a watcher reads the status as the follower published it.
TEST(DelayLineTest, TheInProcessLinkDelaysBothDirections) {
  rt::SimulatedClock clock;
  InProcessLink link(clock, 64, 0.05);
  SetPointMessage sp;
  sp.sequence = 7;
  link.SendSetPoint(sp);
  FollowerStatusMessage status;
  status.sequence = 9;
  link.PublishStatus(status);
  SetPointMessage got_sp;
  FollowerStatusMessage got_status;
  std::int64_t arrival_ns = 0;
  clock.AdvanceNs(49'000'000);
  EXPECT_FALSE(link.TakeSetPoint(got_sp, arrival_ns));
  EXPECT_FALSE(link.TakeFollowerStatus(got_status));
  EXPECT_TRUE(link.ReadFollowerStatus(got_status));
  clock.AdvanceNs(1'000'000);
  ASSERT_TRUE(link.TakeSetPoint(got_sp, arrival_ns));
  EXPECT_EQ(got_sp.sequence, 7u);
  EXPECT_EQ(arrival_ns, 50'000'000);
  ASSERT_TRUE(link.TakeFollowerStatus(got_status));
  EXPECT_EQ(got_status.sequence, 9u);
}

// The observer (the scheme's budget minus the output energy) never goes negative with a controller, at any delay,
// with 5 % loss and jitter (the classic one-port's budget is what the hand gave: the hand never gets more); without
// one it does against the hard wall at >= 25 ms, so this test can fail.
TEST(FeedbackPassivityTest, TheObserverStaysPositiveWithAControllerAndNotWithout) {
  HarnessParams p;
  p.scenario = HarnessScenario::kWall;
  p.duration_s = 20;
  for (const double delay_ms : {0.0, 10.0, 25.0, 50.0, 100.0, 200.0}) {
    SCOPED_TRACE(delay_ms);
    p.one_way_delay_s = 1e-3 * delay_ms;
    for (const FeedbackPassivityScheme scheme : {FeedbackPassivityScheme::kClassic, FeedbackPassivityScheme::kNetwork}) {
      p.scheme = scheme;
      const HarnessResult r = RunHarness(p);
      EXPECT_GE(r.min_observer_j, -1e-12) << ToString(scheme);
      // The one-port bound is the hand's own: the port never gave it more than it took.
      if (scheme == FeedbackPassivityScheme::kClassic) {
        EXPECT_LE(r.max_feedback_energy_j, 1e-12);
      }
    }
    if (delay_ms >= 25) {
      p.scheme = FeedbackPassivityScheme::kOff;
      EXPECT_LT(RunHarness(p).min_observer_j, 0.0);
    }
  }
}

// The network form with its follower-side controller: the channel gives the environment no more than the hand put in
// (E_out,F <= E_in,L(k − T) / G, within the one-sample lag of the environment's measured force: 0.02 J at the
// follower is 0.5 mJ at the hand), and the hand gets no more than it gave, at every sample, at every delay, with 5 %
// loss and jitter. Without the follower's controller the robot pushes 1.6-160 J more into the wall or the traction
// than the hand paid for (the classic scheme's follower in `robossis bilateral-matrix`), so this test can fail.
TEST(FeedbackPassivityTest, TheNetworkFormIsPassiveAtBothPorts) {
  HarnessParams p;
  p.scheme = FeedbackPassivityScheme::kNetwork;
  p.duration_s = 20;
  for (const HarnessScenario scenario : {HarnessScenario::kWall, HarnessScenario::kLoad517}) {
    p.scenario = scenario;
    for (const double delay_ms : {0.0, 10.0, 25.0, 50.0, 100.0, 200.0}) {
      SCOPED_TRACE(std::string(ToString(scenario)) + " " + std::to_string(delay_ms) + " ms");
      p.one_way_delay_s = 1e-3 * delay_ms;
      const HarnessResult r = RunHarness(p);
      EXPECT_LE(r.max_follower_excess_j, 0.02);
      EXPECT_LE(r.max_feedback_energy_j, 1e-12);
      EXPECT_GE(r.min_observer_j, -1e-12);
    }
  }
}

// The controller's action released over release_s instead of tick by tick: the force's share above 25 Hz falls
// below 10 % where the tick-by-tick controller puts 13-41 % there (so this test can fail), and the port stays passive
// at every sample.
TEST(FeedbackPassivityTest, AReleasedControllerDoesNotChatterAndStaysPassive) {
  HarnessParams p;
  p.duration_s = 20;
  for (const HarnessScenario scenario : {HarnessScenario::kWall, HarnessScenario::kLoad517}) {
    p.scenario = scenario;
    for (const double delay_ms : {25.0, 100.0}) {
      p.one_way_delay_s = 1e-3 * delay_ms;
      for (const FeedbackPassivityScheme scheme :
           {FeedbackPassivityScheme::kClassic, FeedbackPassivityScheme::kNetwork}) {
        SCOPED_TRACE(std::string(ToString(scenario)) + " " + std::to_string(delay_ms) + " ms " + ToString(scheme));
        p.scheme = scheme;
        p.passivity.reserve_j = 0;  // the release, not the taper
        p.passivity.release_s = 0.25;
        const HarnessResult released = RunHarness(p);
        EXPECT_LT(released.force_hf_share, 0.1);
        EXPECT_LE(released.max_feedback_energy_j, 1e-12);
        p.passivity.release_s = 0;
        EXPECT_GT(RunHarness(p).force_hf_share, 0.1);
      }
    }
  }
}

// The energy-reserve taper (the default): the force's share above 25 Hz stays below 5 % in every loaded cell at
// every delay, where the tick-by-tick controller (reserve_j 0) puts more than 5 % there at >= 25 ms (7-52 % at
// 60 s), so this test can fail; the hand never gets more than it gave, and the scheme's observer never goes negative.
TEST(FeedbackPassivityTest, TheTaperedControllerDoesNotChatterAndStaysPassive) {
  HarnessParams p;
  p.duration_s = 20;
  for (const HarnessScenario scenario : {HarnessScenario::kWall, HarnessScenario::kSpring, HarnessScenario::kLoad517,
                                         HarnessScenario::kRelease}) {
    p.scenario = scenario;
    for (const double delay_ms : {0.0, 10.0, 25.0, 50.0, 100.0, 200.0}) {
      p.one_way_delay_s = 1e-3 * delay_ms;
      for (const FeedbackPassivityScheme scheme :
           {FeedbackPassivityScheme::kClassic, FeedbackPassivityScheme::kNetwork}) {
        SCOPED_TRACE(std::string(ToString(scenario)) + " " + std::to_string(delay_ms) + " ms " + ToString(scheme));
        p.scheme = scheme;
        p.passivity = FeedbackPassivityConfig{};
        const HarnessResult tapered = RunHarness(p);
        EXPECT_LT(tapered.force_hf_share, 0.05);
        EXPECT_LE(tapered.max_feedback_energy_j, 1e-12);
        EXPECT_GE(tapered.min_observer_j, -1e-12);
        if (delay_ms >= 25 && scenario != HarnessScenario::kSpring) {
          p.passivity.reserve_j = 0;
          EXPECT_GT(RunHarness(p).force_hf_share, 0.05);
        }
      }
    }
  }
}

// After the operator lets go with the 517 N load, the taper's damper brings the device to rest (< 1 mm/s) within
// 1 s at every delay from 10 ms, with no let-go detector; without the damper the device coasts on its own friction
// for more than 1 s (classic, 25-200 ms), so this test can fail.
TEST(FeedbackPassivityTest, TheTapersDamperBringsADeviceLetGoToRest) {
  HarnessParams p;
  p.scenario = HarnessScenario::kLetGo;
  p.duration_s = 35;
  for (const double delay_ms : {10.0, 25.0, 50.0, 100.0, 200.0}) {
    p.one_way_delay_s = 1e-3 * delay_ms;
    for (const FeedbackPassivityScheme scheme :
         {FeedbackPassivityScheme::kClassic, FeedbackPassivityScheme::kNetwork}) {
      SCOPED_TRACE(std::to_string(delay_ms) + " ms " + ToString(scheme));
      p.scheme = scheme;
      p.passivity = FeedbackPassivityConfig{};
      const HarnessResult r = RunHarness(p);
      EXPECT_GE(r.rest_after_event_s, 0.0);
      EXPECT_LT(r.rest_after_event_s, 1.0);
      EXPECT_LE(r.max_feedback_energy_j, 1e-12);
      if (scheme == FeedbackPassivityScheme::kClassic && delay_ms >= 25) {
        p.passivity.rest_damping_n_s_per_m = 0;
        EXPECT_GT(RunHarness(p).rest_after_event_s, 1.0);
      }
    }
  }
}

// With the taper (the default) and the let-go detector's 10 ms confirmation, the classic scheme brings the device to
// rest within 1 s of the let-go at every delay, 0 ms included (where the load stays within the budget, goes slack
// and leaves the device coasting 2.4 s without the detector), and the detector believes no let-go while the hand
// holds on; with a one-tick confirmation it fires falsely (517 N at 50 ms), so this test can fail.
// The network form too: judged under the taper's damper alone (a force proportional to the velocity, which does not
// tell the mass), the held hand was taken for a let-go at 1.6-2.0 s in its loaded cells at 0, 10 and 200 ms.
TEST(LetGoDetectorTest, WithTheTaperTheDeviceRestsAndTheHeldHandIsNotTakenForALetGo) {
  HarnessParams p;
  p.detect_let_go = true;
  for (const FeedbackPassivityScheme scheme : {FeedbackPassivityScheme::kClassic, FeedbackPassivityScheme::kNetwork}) {
    for (const double delay_ms : {0.0, 10.0, 25.0, 50.0, 100.0, 200.0}) {
      SCOPED_TRACE(std::string(ToString(scheme)) + " at " + std::to_string(delay_ms) + " ms");
      p.scheme = scheme;
      p.one_way_delay_s = 1e-3 * delay_ms;
      p.duration_s = 35;
      p.scenario = HarnessScenario::kLetGo;
      const HarnessResult r = RunHarness(p);
      EXPECT_GE(r.rest_after_event_s, 0.0);
      EXPECT_LT(r.rest_after_event_s, 1.0);
      EXPECT_LE(r.max_feedback_energy_j, 1e-12);
      p.duration_s = 60;
      for (const HarnessScenario held : {HarnessScenario::kFree, HarnessScenario::kWall, HarnessScenario::kSpring,
                                         HarnessScenario::kLoad517, HarnessScenario::kRelease}) {
        p.scenario = held;
        EXPECT_LT(RunHarness(p).let_go_detected_s, 0.0) << ToString(held);
      }
    }
  }
}

// Position drift between the follower and the hand (delay removed) after 60 s of mixed motion at 100 ms, with the
// default (tapered classic) controller: <= 0.5 mm, and no more than 0.1 mm above the same measure after 5 s.
TEST(FeedbackPassivityTest, TheFollowerDoesNotDriftAt100Ms) {
  HarnessParams p;
  p.one_way_delay_s = 0.1;
  p.scheme = FeedbackPassivityScheme::kClassic;
  for (const HarnessScenario scenario : {HarnessScenario::kFree, HarnessScenario::kWall, HarnessScenario::kSpring,
                                         HarnessScenario::kLoad517}) {
    SCOPED_TRACE(ToString(scenario));
    p.scenario = scenario;
    const HarnessResult r = RunHarness(p);
    EXPECT_LE(r.drift_mm, 0.5);
    EXPECT_LE(r.drift_growth_mm, 0.1);
  }
}

// The controller counts as acting only where it changed the shown force by more than active_tolerance_n: while the
// taper fades a load that would give the hand energy it acts (and so does its taper); once the hand pays again and
// the load's share has come back to within a hair of 1 (0.5 s, 25 time constants), it no longer does. Counted as
// acting whenever the share was below 1 (exactly), it acted at every tick of a bilateral run (tdpa_active_fraction
// 1.0), so this test can fail.
TEST(FeedbackPassivityTest, ActsOnlyWhereItChangesTheShownForceBeyondItsTolerance) {
  FeedbackPassivity port(FeedbackPassivityConfig{});
  Vector6d load = Vector6d::Zero(), along = Vector6d::Zero(), against = Vector6d::Zero();
  load[0] = 5;
  along[0] = 0.01;
  against[0] = -0.01;
  constexpr double kDt = 1e-3;
  port.Observe(port.Apply(Vector6d::Zero(), load, along, kDt, 15, 0.3, 0).feedback, along, kDt, 0);
  EXPECT_TRUE(port.active());  // the load would give energy: no budget, faded
  EXPECT_TRUE(port.taper_active());
  for (int k = 0; k < 500; ++k) {
    port.Observe(port.Apply(Vector6d::Zero(), load, against, kDt, 15, 0.3, 0).feedback, against, kDt, 0);
  }
  EXPECT_FALSE(port.active());
  EXPECT_FALSE(port.taper_active());
}

TEST(FeedbackPassivityTest, RejectsANegativeReserveNamingTheField) {
  FeedbackPassivityConfig c;
  c.reserve_j = -0.01;
  try {
    c.Validate();
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("reserve_j"), std::string::npos) << e.what();
  }
}

// leader.yaml carries the taper's settings and the controller's activity tolerance: the file's values reach the
// controller, and a bad one is refused naming its field (before, the taper ran on its compiled defaults whatever the
// file said, so this test can fail).
TEST(LeaderConfigTest, ReadsTheTapersFieldsAndRefusesABadOneNamingIt) {
  const FeedbackPassivityConfig read = Leader().feedback.passivity;
  EXPECT_DOUBLE_EQ(read.reserve_j, 0.01);
  EXPECT_DOUBLE_EQ(read.rest_damping_n_s_per_m, 10);
  EXPECT_DOUBLE_EQ(read.still_m_s, 0.001);
  EXPECT_DOUBLE_EQ(read.active_tolerance_n, 0.01);
  const robossis::testing::ScratchDir dir("robossis_leader_taper_yaml");
  std::filesystem::create_directories(dir.path());
  std::ifstream in(ConfigPath("leader.yaml"));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  struct Bad {
    const char* line;
    const char* replacement;
    const char* field;
  };
  for (const Bad& bad : {Bad{"reserve_j: 0.01", "reserve_j: -0.01", "feedback.taper.reserve_j"},
                         Bad{"rest_damping_n_s_per_m: 10   # [assumed] the faded",
                             "rest_damping_n_s_per_m: nan  # [assumed] the faded",
                             "feedback.taper.rest_damping_n_s_per_m"},
                         Bad{"active_tolerance_n: 0.01", "active_tolerance_n: 0", "feedback.active_tolerance_n"}}) {
    SCOPED_TRACE(bad.field);
    std::string changed = text;
    const auto at = changed.find(bad.line);
    ASSERT_NE(at, std::string::npos);
    changed.replace(at, std::string(bad.line).size(), bad.replacement);
    const auto file = dir.path() / "leader.yaml";
    std::ofstream(file) << changed;
    try {
      LeaderConfig::FromYaml(file);
      FAIL() << "no error";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(bad.field), std::string::npos) << e.what();
    }
  }
}

// After the operator lets go with the 517 N load at 100 ms, the device comes to rest (< 1 mm/s) within 1 s with the
// let-go detector and not without it (classic: it coasts on its own friction once the controller cut the load); the
// detector believes no let-go in the scenarios where the hand holds on.
TEST(LetGoDetectorTest, TheDeviceRestsWithinASecondAfterTheOperatorLetsGo) {
  HarnessParams p;
  p.passivity.reserve_j = 0;  // the tick-by-tick controller: the detector alone brings the device to rest
  p.let_go.confirm_s = 0.001;  // one tick: the controller cuts the load the tick after the let-go
  p.duration_s = 35;
  p.one_way_delay_s = 0.1;
  for (const FeedbackPassivityScheme scheme : {FeedbackPassivityScheme::kClassic, FeedbackPassivityScheme::kNetwork}) {
    SCOPED_TRACE(ToString(scheme));
    p.scheme = scheme;
    p.scenario = HarnessScenario::kLetGo;
    p.detect_let_go = false;
    // (network holds the follower back at 100 ms and the device happens to stop in 0.7 s without the detector.)
    if (scheme == FeedbackPassivityScheme::kClassic) {
      EXPECT_GT(RunHarness(p).rest_after_event_s, 1.0);
    }
    p.detect_let_go = true;
    const HarnessResult r = RunHarness(p);
    EXPECT_GE(r.rest_after_event_s, 0.0);
    EXPECT_LT(r.rest_after_event_s, 1.0);
    EXPECT_LE(r.max_feedback_energy_j, 1e-12);
    for (const HarnessScenario held : {HarnessScenario::kWall, HarnessScenario::kLoad517, HarnessScenario::kRelease}) {
      p.scenario = held;
      EXPECT_LT(RunHarness(p).let_go_detected_s, 0.0) << ToString(held);
    }
  }
}

}  // namespace
}  // namespace robossis::teleop
