// End-to-end latency of the teleoperation runtime: hand sample → follower joint command (see BENCHMARKS.md).
//
// The two instants compared, for every set-point the follower used:
//   A  the device sample's own time: SetPointMessage::stamp_ns, which the leader copies from the device reading
//      (DeviceState::time_s) it read in the tick that produced the set-point (for the simulated device, the leader
//      clock at that tick's device read);
//   B  FollowerTickRecord::command_time_s of the follower tick that first commanded joints from that set-point:
//      the tick that took it from the link and accepted it while following (state enabled), read on the same clock
//      right after the joint command went to the back end.
// Latency = B − A. It holds the leader's tick after the read (rendering, motion transfer, IK check, send), the wait
// for the next 10 kHz follower tick (≤ 100 µs) and the follower's tick up to the command (validation, state
// machine, guard, actuation eq. 15–17). It excludes the motion transfer's filter delay (up-sampling, moving
// average, Kalman eq. 12, cap guard: how far the set-point's motion lags the hand's), which is a property of the
// signal, not of the runtime; BM_TransferFilterDelay measures it apart, in simulated time, with a ramp of the hand
// (a step in velocity): at steady state the set-point lags the eq. 10–11 goal by a constant time.
//
// The runtime is wired as `robossis teleop --device sim --clock real` wires it (the simulated sigma.7 and its hand,
// the leader unit at 1 kHz and the follower unit at 10 kHz on their own threads on absolute deadlines through
// rt::RunRealTime, the in-process link, one clock for both); the follower's back end is the pulse recorder (arg 0),
// the Bullet simulation as a plant on its own 1 kHz loop (arg 1, what `robossis teleop --follower sim` runs), or the
// same simulation stepped inside the follower's tick by Service() (arg 2, the design it replaced, for comparison).
// Budgets: the leader's 1 ms tick, the follower's 100 µs tick, and the 50 ms hand-to-set-point goal.

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "haptics/device/device_factory.h"
#include "haptics/rendering/renderer_factory.h"
#include "haptics/transfer/motion_transfer.h"
#include "robot/actuation/pulse_recorder_follower.h"
#include "robot/sim/rsr_simulation.h"
#include "robot/sim/simulated_plant.h"
#include "src/core/config.h"
#include "src/core/rt/periodic_loop.h"
#include "src/teleop/capped_motion.h"
#include "src/teleop/delay_estimate.h"
#include "src/teleop/feedback_passivity.h"
#include "src/teleop/follower_passivity.h"
#include "src/teleop/let_go_detector.h"
#include "src/teleop/wrench_estimate.h"
#include "src/teleop/follower_unit.h"
#include "src/teleop/in_process_link.h"
#include "src/teleop/leader_unit.h"
#include "src/teleop/teleop_session.h"
#include "tests/support/forwarding_follower.h"

namespace {

using namespace robossis;
using namespace robossis::teleop;

double Percentile(std::vector<double>& v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

// The translational speed of a displacement series [p; theta] at each sample (the one rate estimator's central
// differences).
std::vector<double> TranslationalSpeeds(const std::vector<double>& t, const std::vector<Vector6d>& x) {
  std::vector<double> p;
  for (const Vector6d& x_k : x) p.insert(p.end(), x_k.data(), x_k.data() + 3);
  const std::vector<double> v = RatesWithinSegments(t, p, 3);
  std::vector<double> speed(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) speed[k] = Eigen::Vector3d(&v[3 * k]).norm();
  return speed;
}

const TeleopSetup& Setup() {
  static const robot::RsrModel rsr = robot::RsrModel::Default();
  static const robot::Sigma7Model sigma7 = robot::Sigma7Model::Default();
  static const TeleopSetup setup = TeleopSetup::Load(DefaultDataDir(), rsr, sigma7);
  return setup;
}

// Hand sample → follower joint command on real clocks: 1 kHz leader, 10 kHz follower, `duration_s` per iteration.
void AddCounts(rt::LoopCounts& sum, const rt::LoopCounts& c) {
  sum.ticks += c.ticks;
  sum.overruns += c.overruns;
  sum.overruns_late_wake += c.overruns_late_wake;
  sum.overruns_long_tick += c.overruns_long_tick;
}

// <loop>_overruns and their causes (rt::LoopStats): a late wake-up (scheduling) or a long tick (the tick's own work,
// with any preemption inside it).
void SetOverrunCounters(benchmark::State& state, const std::string& loop, const rt::LoopCounts& c) {
  state.counters[loop + "_overruns"] = static_cast<double>(c.overruns);
  state.counters[loop + "_overruns_late_wake"] = static_cast<double>(c.overruns_late_wake);
  state.counters[loop + "_overruns_long_tick"] = static_cast<double>(c.overruns_long_tick);
}

void BM_HandToJointCommandLatency(benchmark::State& state) {
  const TeleopSetup& setup = Setup();
  const robot::RsrModel& rsr = *setup.rsr;
  const Eigen::Isometry3d home = rsr.geometry().X_FM_home;
  const double duration_s = 5.0;
  const double follower_rate_hz = setup.transfer.rates.actuation_rate_hz;
  std::vector<double> latency_us, follower_part_us, wait_us;  // wait: sample → the follower tick's start
  std::uint64_t used = 0, realtime_refused = 0;
  rt::LoopCounts leader_loop, follower_loop, plant_loop;  // summed over the iterations; overruns by cause
  // The follower loop's own tick (LoopStats::tick_duration, wall time from the tick's start to its end).
  double follower_tick_p50_us = 0, follower_tick_p99_us = 0, follower_tick_max_us = 0, plant_tick_p99_us = 0;
  for (auto _ : state) {
    rt::MonotonicClock clock;
    InProcessLink link(clock);
    std::unique_ptr<robot::Follower> back_end;
    if (state.range(0) >= 1) {
      sim::SimOptions options;
      options.with_bone = false;
      options.with_traction = false;
      auto simulation = std::make_unique<sim::RsrSimulation>(rsr, setup.sim, nullptr, nullptr, home, options);
      if (state.range(0) == 1) back_end = std::make_unique<sim::SimulatedPlant>(std::move(simulation));
      else back_end = std::move(simulation);  // 2: stepped inside the follower's tick (Service), for comparison
    } else {
      const auto n = static_cast<std::size_t>(duration_s * follower_rate_hz + 1000.0);
      back_end = std::make_unique<actuation::PulseRecorderFollower>(rsr, setup.actuation, home, n, n);
    }
    FollowerUnit follower(rsr, setup.actuation, setup.follower, *back_end, link, clock);
    LeaderConfig leader_config = setup.leader;
    leader_config.rate_hz = 1000;
    haptics::DeviceScriptOptions script = leader_config.sim_script;
    script.replay_frame = setup.transfer.mapping;
    auto device = haptics::MakeDevice("sim", *setup.sigma7, setup.haptics, leader_config.device, script);
    device->EnableForces(true);
    auto renderer = haptics::MakeRenderer("proxy-safe", setup.haptics, rsr, haptics::HcToRsrMap{}, 1000, nullptr,
                                          haptics::BackgroundWork::kThread);
    LeaderUnit leader(leader_config, setup.transfer, rsr, *device, *renderer, link, home, std::random_device{}());
    StateCommandMessage enable;
    enable.command = StateCommand::kEnable;
    enable.sequence = 1;
    link.operator_commands().Send(enable);

    std::vector<FollowerTickRecord> records;
    records.reserve(static_cast<std::size_t>(duration_s * follower_rate_hz * 1.2));
    const auto drain = [&](double) {
      LeaderTickRecord l;
      while (leader.records().TryPop(l)) {
      }
      FollowerTickRecord f;
      while (follower.TakeRecord(f)) records.push_back(f);
      return true;
    };
    rt::LoopOptions leader_options, follower_options;
    leader_options.name = "leader";
    leader_options.period_ns = 1'000'000;
    follower_options.name = "follower";
    follower_options.period_ns = std::llround(1e9 / follower_rate_hz);
    follower_options.fifo_priority = 81;
    std::vector<rt::ScheduledTask> tasks = {{&leader, leader_options}, {&follower, follower_options}};
    if (const robot::Follower::Plant plant = back_end->plant(); plant.task != nullptr) {
      tasks.push_back({plant.task, rt::PlantLoopOptions(plant.period_ns)});
    }
    const rt::RunResult run = rt::RunRealTime(clock, tasks, duration_s, drain);
    drain(0);
    realtime_refused += run.warnings.size();
    AddCounts(leader_loop, run.stats[0].counts());
    AddCounts(follower_loop, run.stats[1].counts());
    follower_tick_p50_us = std::max(follower_tick_p50_us, run.stats[1].tick_duration.PercentileUs(0.50));
    follower_tick_p99_us = std::max(follower_tick_p99_us, run.stats[1].tick_duration.PercentileUs(0.99));
    follower_tick_max_us = std::max(follower_tick_max_us, run.stats[1].tick_duration.max_us());
    if (run.stats.size() > 2) {
      plant_tick_p99_us = std::max(plant_tick_p99_us, run.stats[2].tick_duration.PercentileUs(0.99));
      AddCounts(plant_loop, run.stats[2].counts());
    }
    for (const FollowerTickRecord& r : records) {
      if (!r.took_setpoint || r.setpoint_verdict != SetPointVerdict::kAccepted) continue;
      if (r.state != OperatingState::kEnabled) continue;  // joints commanded from the set-point only when following
      const double a_s = 1e-9 * static_cast<double>(r.setpoint_stamp_ns);
      latency_us.push_back(1e6 * (r.command_time_s - a_s));
      follower_part_us.push_back(1e6 * (r.command_time_s - r.time_s));
      wait_us.push_back(1e6 * (r.time_s - a_s));
      ++used;
    }
  }
  const double p50 = Percentile(latency_us, 0.50), p99 = Percentile(latency_us, 0.99);
  state.counters["setpoints_used"] = static_cast<double>(used);
  state.counters["latency_p50_us"] = p50;
  state.counters["latency_p99_us"] = p99;
  state.counters["latency_max_us"] = latency_us.empty() ? 0 : latency_us.back();
  state.counters["p99_over_1ms_tick"] = p99 / 1000.0;
  state.counters["p99_over_50ms_goal"] = p99 / 50000.0;
  state.counters["follower_tick_to_command_p99_us"] = Percentile(follower_part_us, 0.99);
  state.counters["sample_to_follower_tick_p50_us"] = Percentile(wait_us, 0.50);
  state.counters["sample_to_follower_tick_p01_us"] = Percentile(wait_us, 0.01);
  state.counters["realtime_warnings"] = static_cast<double>(realtime_refused);  // SCHED_FIFO or mlockall refused
  SetOverrunCounters(state, "leader", leader_loop);
  SetOverrunCounters(state, "follower", follower_loop);
  state.counters["follower_overrun_rate"] = follower_loop.ticks ? static_cast<double>(follower_loop.overruns) /
                                                                      static_cast<double>(follower_loop.ticks)
                                                                : 0.0;
  state.counters["follower_tick_p50_us"] = follower_tick_p50_us;
  state.counters["follower_tick_p99_us"] = follower_tick_p99_us;
  state.counters["follower_tick_max_us"] = follower_tick_max_us;
  state.counters["follower_tick_p99_over_period"] = follower_tick_p99_us * 1e-6 * follower_rate_hz;
  state.counters["plant_tick_p99_us"] = plant_tick_p99_us;  // the simulated robot's own loop (arg 1 only)
  SetOverrunCounters(state, "plant", plant_loop);
}
BENCHMARK(BM_HandToJointCommandLatency)->Arg(0)->Arg(1)->Arg(2)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// The motion transfer's filter delay, apart: the hand rests for 0.5 s, then moves at constant speed (a step in
// velocity), through the leader's own use of the transfer (one sample per 1 kHz tick, then ten 10 kHz actuation
// ticks, then the set-point is read), in simulated time. filter_delay_ms: the one delay estimator
// (src/teleop/delay_estimate.h, as summary.json's hand_to_setpoint_delay_ms) between the eq. 10–11 goal and the
// set-point; for a step it is the filters' centroid delay. ramp_position_lag_ms: at steady state, how far the
// set-point's position trails the goal's, in time at that speed (the delay plus any constant offset the filters
// leave). velocity_50pct_delay_ms: from the goal's velocity reaching half its final speed to the set-point's;
// velocity_overshoot: the set-point's peak speed over the final one, minus 1. Arg 1: the goal's speed in % of the
// linear cap (below it, so that the cap's rate limiting plays no part).
void BM_TransferFilterDelay(benchmark::State& state) {
  const TeleopSetup& setup = Setup();
  const Eigen::Isometry3d home = setup.rsr->geometry().X_FM_home;
  const double fraction = 0.01 * static_cast<double>(state.range(0));
  const int ratio = static_cast<int>(std::lround(setup.transfer.rates.actuation_rate_hz / 1000.0));
  DelayEstimate estimate;
  double lag_ms = 0, rise_ms = 0, overshoot = 0;
  // Arg 2: the filters' share, one at a time: 0 as shipped, 1 without the Kalman filter (eq. 12), 2 without the
  // moving average, 3 without either (the cap guard's position feedback alone).
  transfer::TransferConfig config = setup.transfer;
  const int variant = static_cast<int>(state.range(1));
  if (variant & 1) config.filter.kalman_enabled = false;
  if (variant & 2) config.filter.moving_average_window = 1;
  for (auto _ : state) {
    transfer::MotionTransfer mt(config, home);
    mt.SetClutch(true);
    // The hand's speed such that the goal moves at `fraction` of the cap (eq. 11 scales the hand's motion).
    const double v_hand = fraction * setup.transfer.caps.max_linear_speed_m_s / setup.transfer.mapping.translation_scale;
    std::vector<double> t;
    std::vector<Vector6d> goal, disp;
    for (int k = 0; k < 3000; ++k) {
      transfer::HcSample s;
      s.time_s = 1e-3 * k;
      s.p_OH = Eigen::Vector3d(v_hand * std::max(0.0, s.time_s - 0.5), 0, 0);
      mt.PushHcSample(s);
      mt.TransferTick();
      for (int j = 0; j < ratio; ++j) mt.ActuationTick();
      t.push_back(s.time_s);
      goal.push_back(mt.tick_info().goal);
      disp.push_back(mt.set_point().displacement);
    }
    estimate = EstimateDelay({.t_s = t, .x = goal}, {.t_s = t, .x = disp});
    const std::size_t n = t.size();
    const double v_goal = (goal[n - 1] - goal[n - 2]).head<3>().norm() / 1e-3;
    lag_ms = v_goal > 0 ? 1e3 * (goal[n - 1] - disp[n - 1]).head<3>().norm() / v_goal : 0;
    // The step's 50 % point: the goal's velocity, then the set-point's, first at half the final speed.
    const std::vector<double> v_set = TranslationalSpeeds(t, disp), v_goal_series = TranslationalSpeeds(t, goal);
    const auto first_half = [&](const std::vector<double>& v) {
      for (std::size_t k = 0; k < n; ++k) {
        if (v[k] >= 0.5 * v_goal) return t[k];
      }
      return t.back();
    };
    rise_ms = 1e3 * (first_half(v_set) - first_half(v_goal_series));
    overshoot = 0;
    for (const double v : v_set) overshoot = std::max(overshoot, v / v_goal - 1.0);
    benchmark::DoNotOptimize(lag_ms);
  }
  if (!estimate.ok()) state.SkipWithError((std::string("delay estimate: ") + ToString(estimate.status)).c_str());
  state.counters["filter_delay_ms"] = 1e3 * estimate.delay_s;
  state.counters["delay_over_50ms_goal"] = 1e3 * estimate.delay_s / 50.0;
  state.counters["ramp_position_lag_ms"] = lag_ms;
  state.counters["velocity_50pct_delay_ms"] = rise_ms;
  state.counters["velocity_overshoot"] = overshoot;
}
BENCHMARK(BM_TransferFilterDelay)
    ->Args({20, 0})
    ->Args({50, 0})
    ->Args({90, 0})
    ->Args({50, 1})
    ->Args({50, 2})
    ->Args({50, 3})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// The bilateral feedback's added cost per tick (budget: 20 µs): the leader's passivity observer and controller on
// the feedback port (arg 0: observing only; arg 1: the default, the energy-reserve taper and its damper ahead of the
// controller acting every tick; arg 2: the tick-by-tick controller alone, its damper capped and the feedback cut;
// arg 3: the same released over 0.25 s), the follower's side of the network form
// and the let-go detector, and the follower's wrench estimate (the Jacobian of eq. 15, the statics, the
// arms' weight by virtual work), which runs in its 10 kHz tick.
void BM_FeedbackPassivityTick(benchmark::State& state) {
  teleop::FeedbackPassivityConfig config;
  config.scheme = state.range(0) == 0 ? teleop::FeedbackPassivityScheme::kOff : teleop::FeedbackPassivityScheme::kNetwork;
  if (state.range(0) >= 2) config.reserve_j = 0;
  if (state.range(0) == 3) config.release_s = 0.25;
  teleop::FeedbackPassivity port(config);
  Vector6d wall = Vector6d::Zero(), feedback, twist;
  feedback << 8, -3, 5, 0.05, 0.02, -0.04;
  twist << 0.05, -0.02, 0.03, 0.2, 0.1, -0.2;  // along the feedback: output power every tick
  double sink = 0;
  for (auto _ : state) {
    const teleop::CappedWrench c = port.Apply(wall, feedback, twist, 1e-3, 15.0, 0.3, 0.0);
    sink += c.displayed[0] + port.Observe(c.feedback, twist, 1e-3, 0.0).out_j;
    twist[0] = -twist[0];  // alternate so that the books move both ways
    benchmark::DoNotOptimize(sink);
  }
}
BENCHMARK(BM_FeedbackPassivityTick)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMicrosecond);

void BM_FeedbackFollowerPortAndLetGo(benchmark::State& state) {
  teleop::FollowerPassivity follower_port;
  teleop::LetGoDetector let_go(teleop::LetGoConfig{});
  Vector6d step, wrench;
  step << 1e-4, -2e-5, 3e-5, 2e-4, 1e-4, -2e-4;
  wrench << -300, 50, -100, 20, -10, 30;  // against the step: the budget binds
  double sink = 0;
  for (auto _ : state) {
    const double share = follower_port.StepShare(step, wrench, 1.0);
    follower_port.Book(wrench, share * step);
    sink += share;
    benchmark::DoNotOptimize(let_go.Update(wrench.head<3>() * 0.01, step.head<3>(), -step.head<3>(), 1e-3, 0.0));
    benchmark::DoNotOptimize(sink);
  }
}
BENCHMARK(BM_FeedbackFollowerPortAndLetGo)->Unit(benchmark::kMicrosecond);

void BM_FollowerWrenchEstimate(benchmark::State& state) {
  const robot::RsrModel model = robot::RsrModel::Default();
  teleop::WrenchEstimateConfig config;
  config.carried_mass_kg = 2.5;
  config.gravity_F_mps2 = Eigen::Vector3d(0, -9.81, 0);
  config.remove_arm_weight = true;
  robot::RsrJointVector effort;
  effort << 1, -2, 3, 170, 175, 168;
  const Eigen::Isometry3d X = model.geometry().X_FM_home;
  for (auto _ : state) benchmark::DoNotOptimize(teleop::EstimateExternalWrench(model, X, effort, config));
}
BENCHMARK(BM_FollowerWrenchEstimate)->Unit(benchmark::kMicrosecond);

// The leader's next set-point twist within the follower's caps (arg 0) and within the motors' top speeds as well
// (arg 1: the Jacobian of eq. 15 at the last set-point, what the leader adds per set-point since it keeps within
// them), from rest toward a step 30 mm away along z, where the linear motors bind.
void BM_SetPointTwistWithinMotorSpeeds(benchmark::State& state) {
  const TeleopSetup& setup = Setup();
  SetPointLimits limits = setup.follower.setpoint;
  limits.caps.max_linear_speed_m_s = 0.1;
  const Eigen::Isometry3d X = setup.rsr->geometry().X_FM_home;
  robot::RsrJointVector speeds = setup.leader.motor_speed_share * setup.leader.max_joint_speed;
  if (state.range(0) == 0) speeds.setConstant(std::numeric_limits<double>::infinity());
  Vector6d remaining = Vector6d::Zero(), twist = Vector6d::Zero();
  remaining[2] = 0.03;
  for (auto _ : state) {
    const Matrix6d rows = MotorRows(*setup.rsr, X, speeds);
    benchmark::DoNotOptimize(NextCappedTwist(twist, remaining, limits, 1e-3, rows));
  }
}
BENCHMARK(BM_SetPointTwistWithinMotorSpeeds)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// A back end that measures at the Bullet plant's 1 kHz while the follower ticks at 10 kHz (the pulse recorder's
// state, held for 1 ms, with a constant load on the drives): what the follower's wrench estimate sees in
// `robossis teleop --follower sim`.
class MeasuredAtOneKilohertz final : public ::robossis::testing::ForwardingFollower {
 public:
  MeasuredAtOneKilohertz(robot::Follower& inner, const robot::RsrJointVector& effort)
      : ForwardingFollower(inner), effort_(effort) {}
  void Service(double now_s) noexcept override {
    inner_.Service(now_s);
    if (measured_ && now_s < state_.time_s + 1e-3 - 1e-9) return;
    state_ = inner_.State();
    state_.time_s = now_s;
    state_.effort = effort_;
    measured_ = true;
  }
  robot::RsrFollowerState State() const noexcept override { return measured_ ? state_ : inner_.State(); }

 private:
  robot::RsrJointVector effort_;
  robot::RsrFollowerState state_;
  bool measured_ = false;
};

// One follower tick (FollowerUnit::Tick) while it follows a set-point stream moving at 5 mm/s, on a simulated clock
// (10 kHz, a set-point every tenth tick), the wrench estimated from a back end measuring at 1 kHz, the ring's and the
// arms' weight removed as `robossis teleop --follower sim` does.
void BM_FollowerTick(benchmark::State& state) {
  const TeleopSetup& setup = Setup();
  const robot::RsrModel& rsr = *setup.rsr;
  const Eigen::Isometry3d home = rsr.geometry().X_FM_home;
  const auto ticks = static_cast<std::size_t>(state.max_iterations) + 100;
  actuation::PulseRecorderFollower recorder(rsr, setup.actuation, home, ticks, ticks);
  robot::RsrJointVector effort;
  effort << 1, -2, 3, 170, 175, 168;
  MeasuredAtOneKilohertz back_end(recorder, effort);
  rt::SimulatedClock clock;
  InProcessLink link(clock);
  // The weight the session removes for the Bullet follower (the estimate's longest path).
  FollowerConfig config = setup.follower;
  config.wrench.carried_mass_kg = setup.sim.masses.moving_ring_kg;
  config.wrench.gravity_F_mps2 = setup.sim.physics.gravity_F_mps2;
  config.wrench.remove_arm_weight = true;
  config.wrench.arm_masses = setup.sim.masses;
  FollowerUnit follower(rsr, setup.actuation, config, back_end, link, clock);
  StateCommandMessage enable;
  enable.command = StateCommand::kEnable;
  enable.sequence = 1;
  link.operator_commands().Send(enable);
  SetPointMessage sp;
  sp.leader_session = 1;
  sp.flags = kSetPointPresence;
  sp.twist_F = {0.005, 0, 0, 0, 0, 0};
  const auto send = [&](std::uint64_t k) {
    if (k % 10 != 0) return;
    Eigen::Isometry3d X = home;
    X.translation().x() += 0.005 * clock.NowS();
    PoseToArrays(X, sp.p_FM, sp.q_FM);
    ++sp.sequence;
    sp.stamp_ns = clock.now_ns();
    link.SendSetPoint(sp);
  };
  FollowerTickRecord record;
  std::uint64_t k = 0;
  for (; k < 100; ++k) {  // enabled and following before the timing starts
    send(k);
    clock.AdvanceNs(100'000);
    follower.Tick();
    while (follower.TakeRecord(record)) {
    }
  }
  for (auto _ : state) {
    send(k++);
    clock.AdvanceNs(100'000);
    follower.Tick();
    follower.TakeRecord(record);
  }
  state.counters["following"] = follower.state() == OperatingState::kEnabled ? 1 : 0;
  state.counters["wrench_x_n"] = record.wrench_F[0];
}
BENCHMARK(BM_FollowerTick)->Iterations(100000)->Unit(benchmark::kMicrosecond);

}  // namespace
