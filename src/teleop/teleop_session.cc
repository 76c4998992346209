#include "src/teleop/teleop_session.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include "haptics/device/device_factory.h"
#include "haptics/rendering/renderer_factory.h"
#include "robot/actuation/pulse_recorder_follower.h"
#include "robot/drivers/hal_follower.h"
#include "robot/sim/rsr_simulation.h"
#include "src/core/rt/periodic_loop.h"
#include "src/teleop/flight_recorder.h"
#include "src/teleop/follower_unit.h"
#include "src/teleop/in_process_link.h"
#include "src/teleop/leader_unit.h"
#include "src/teleop/session_summary.h"

namespace robossis::teleop {

std::vector<std::string> KnownFollowers() { return {"sim", "recorder", "hal"}; }

TeleopSetup TeleopSetup::Load(const std::filesystem::path& data_dir, const robot::RsrModel& rsr,
                              const robot::Sigma7Model& sigma7) {
  const std::filesystem::path config = data_dir / "config";
  TeleopSetup s;
  s.rsr = &rsr;
  s.sigma7 = &sigma7;
  s.haptics = haptics::HapticsConfig::FromYaml(config / "haptics.yaml");
  s.transfer = transfer::TransferConfig::FromYaml(config / "transfer.yaml");
  s.actuation = actuation::ActuationConfig::FromYaml(config / "actuation.yaml");
  s.follower = FollowerConfig::FromYaml(config / "follower.yaml", s.transfer.caps);
  s.leader = LeaderConfig::FromYaml(config / "leader.yaml");
  s.leader.guard = s.follower.guard;  // one guard tuning for both units (follower.yaml)
  s.sim = sim::LoadSimConfig(config / "sim.yaml", data_dir);
  s.config_dir = config;
  return s;
}

namespace {

// The follower unit reads its clock itself; the loops hand it the tick.
class FollowerTask final : public rt::PeriodicTask {
 public:
  explicit FollowerTask(FollowerUnit& unit) : unit_(unit) {}
  void Tick(std::int64_t) noexcept override { unit_.Tick(); }

 private:
  FollowerUnit& unit_;
};

SummaryOptions OptionsFromMeta(const nlohmann::json& meta) {
  SummaryOptions o;
  o.leader_rate_hz = meta.at("rate_hz").get<double>();
  o.follower_rate_hz = meta.at("follower_rate_hz").get<double>();
  return o;
}

void CheckRequest(const TeleopRequest& r) {
  const auto methods = haptics::KnownMethods();
  if (std::find(methods.begin(), methods.end(), r.method) == methods.end()) {
    std::string known;
    for (const auto& m : methods) known += (known.empty() ? "" : ", ") + m;
    throw std::invalid_argument("--method: unknown method '" + r.method + "'; known: " + known);
  }
  const auto followers = KnownFollowers();
  if (std::find(followers.begin(), followers.end(), r.follower) == followers.end()) {
    throw std::invalid_argument("--follower: unknown follower '" + r.follower + "'; known: sim, recorder, hal");
  }
  if (!(r.duration_s > 0 && r.duration_s <= 3600)) {
    throw std::invalid_argument("--duration-s: expected 0 < N <= 3600 s");
  }
}

}  // namespace

TeleopOutputs RunTeleop(const TeleopRequest& request, const TeleopSetup& setup, const std::filesystem::path& log_file) {
  CheckRequest(request);
  const robot::RsrModel& rsr = *setup.rsr;
  const Eigen::Isometry3d home = rsr.geometry().X_FM_home;
  LeaderConfig leader_config = setup.leader;
  leader_config.rate_hz = request.rate_hz;
  try {
    leader_config.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--rate-hz: ") + e.what());
  }
  const double follower_rate_hz = setup.transfer.rates.actuation_rate_hz;

  rt::SimulatedClock sim_clock;
  rt::MonotonicClock mono_clock;
  const rt::Clock& clock = request.real_clock ? static_cast<const rt::Clock&>(mono_clock) : sim_clock;
  InProcessLink link(clock);

  std::unique_ptr<robot::Follower> back_end;
  if (request.follower == "sim") {
    sim::SimOptions options;
    options.with_bone = false;
    options.with_traction = false;
    back_end = std::make_unique<sim::RsrSimulation>(rsr, setup.sim, nullptr, nullptr, home, options);
  } else if (request.follower == "hal") {
    back_end = drivers::MakeHalFollower(rsr, setup.config_dir);
  } else {
    const auto n = static_cast<std::size_t>(std::min(request.duration_s * follower_rate_hz + 1000.0, 4.0e6));
    back_end = std::make_unique<actuation::PulseRecorderFollower>(rsr, setup.actuation, home, n, n);
  }
  FollowerUnit follower(rsr, setup.actuation, setup.follower, *back_end, link, clock);
  FollowerTask follower_task(follower);

  std::unique_ptr<haptics::HapticDevice> device = haptics::MakeDevice(
      request.device, *setup.sigma7, setup.haptics, leader_config.device, [&] {
        haptics::DeviceScriptOptions o = leader_config.sim_script;
        o.replay_scale = setup.transfer.mapping.translation_scale;
        return o;
      }());
  if (device->EnableForces(true) != haptics::DeviceStatus::kOk) {
    throw std::runtime_error("--device " + request.device + ": the device refused to enable its forces");
  }
  std::unique_ptr<haptics::HapticRenderer> renderer = haptics::MakeRenderer(
      request.method, setup.haptics, rsr, haptics::HcToRsrMap{}, request.rate_hz, request.atlas,
      request.real_clock ? haptics::BackgroundWork::kThread : haptics::BackgroundWork::kSimulated);
  std::random_device entropy;
  const std::uint64_t session = (static_cast<std::uint64_t>(entropy()) << 32) | entropy();
  LeaderUnit leader(leader_config, setup.transfer, rsr, *device, *renderer, link, home, session);

  // The operator enables the follower (homing, then ready; it follows once the leader has presence).
  StateCommandMessage enable;
  enable.command = StateCommand::kEnable;
  enable.sequence = 1;
  link.operator_commands().Send(enable);

  nlohmann::json meta = {{"device", request.device},     {"method", request.method},
                         {"follower", request.follower}, {"rate_hz", request.rate_hz},
                         {"follower_rate_hz", follower_rate_hz}, {"duration_s", request.duration_s},
                         {"clock", request.real_clock ? "real" : "simulated"}};
  SessionLogWriter log(log_file, meta, {LeaderStreamSpec(), FollowerStreamSpec(), EndStreamSpec()});
  SessionSummary summary(OptionsFromMeta(meta));
  const auto drain = [&](SessionLogWriter& w) {
    LeaderTickRecord l;
    while (leader.records().TryPop(l)) {
      w.Append(kLeaderStream, &l);
      summary.AddLeader(l);
    }
    FollowerTickRecord f;
    while (follower.TakeRecord(f)) {
      w.Append(kFollowerStream, &f);
      summary.AddFollower(f);
    }
  };
  // A replay ends the session 0.5 s after its last sample (the robot has come to rest).
  double ended_since_s = -1;
  const auto keep_going = [&](double now_s) {
    LeaderTickRecord latest;
    const bool ended = leader.latest().Read(latest) && latest.leader_state == static_cast<std::uint8_t>(LeaderState::kEnded);
    if (!ended) ended_since_s = -1;
    else if (ended_since_s < 0) ended_since_s = now_s;
    return !(ended && now_s - ended_since_s >= 0.5);
  };

  rt::LoopOptions leader_loop, follower_loop;
  leader_loop.name = "leader";
  leader_loop.period_ns = std::llround(1e9 / request.rate_hz);
  follower_loop.name = "follower";
  follower_loop.period_ns = std::llround(1e9 / follower_rate_hz);
  follower_loop.fifo_priority = 81;  // the actuation outranks the haptic loop [assumed]: a late step is a jerk
  const std::vector<rt::ScheduledTask> tasks = {{&leader, leader_loop}, {&follower_task, follower_loop}};

  rt::RunResult run;
  if (request.real_clock) {
    FlightRecorder recorder(log, drain);
    recorder.Start();
    run = rt::RunRealTime(mono_clock, tasks, request.duration_s, keep_going);
    if (const std::string error = recorder.Stop(); !error.empty()) throw std::runtime_error(error);
  } else {
    run = rt::RunSimulated(sim_clock, tasks, request.duration_s, [&](double now_s) {
      drain(log);
      renderer->StepSimulatedBackground(now_s);
      return keep_going(now_s);
    });
    drain(log);
  }

  // The session is over: the device's forces off, the drives unpowered (they hold where they are).
  device->EnableForces(false);
  back_end->Disable();

  SessionEndRecord end;
  end.elapsed_s = run.elapsed_s;
  const rt::LoopStats& ls = run.stats[0];
  const rt::LoopStats& fs = run.stats[1];
  end.leader_loop_ticks = ls.ticks;
  end.leader_overruns = ls.overruns;
  end.leader_period_jitter_us_p99 = ls.period_jitter.PercentileUs(0.99);
  end.leader_period_jitter_us_max = ls.period_jitter.max_us();
  end.leader_wake_latency_us_p99 = ls.wake_latency.PercentileUs(0.99);
  end.follower_loop_ticks = fs.ticks;
  end.follower_overruns = fs.overruns;
  end.follower_period_jitter_us_p99 = fs.period_jitter.PercentileUs(0.99);
  end.follower_period_jitter_us_max = fs.period_jitter.max_us();
  end.follower_wake_latency_us_p99 = fs.wake_latency.PercentileUs(0.99);
  end.watchdog_holds = follower.counters().watchdog_holds;
  end.setpoints_accepted = follower.counters().setpoints_accepted;
  end.setpoints_rejected = follower.counters().setpoints_rejected;
  end.leader_records_dropped = leader.counters().records_dropped;
  end.follower_records_dropped = follower.counters().records_dropped;
  end.device_failures = leader.counters().device_failures;
  end.ik_rejected = leader.counters().ik_rejected;
  log.Append(kEndStream, &end);
  log.Flush();
  summary.SetEnd(end);

  TeleopOutputs out;
  out.summary = summary.Summary();
  out.leader_csv = summary.leader_csv();
  out.follower_csv = summary.follower_csv();
  out.periods_csv = summary.PeriodsCsv();
  out.warnings = run.warnings;
  return out;
}

TeleopOutputs ReplaySessionLog(const std::filesystem::path& log_file) {
  const SessionLog log = ReadSessionLog(log_file);
  SummaryOptions options;
  try {
    options = OptionsFromMeta(log.meta);
  } catch (const std::exception& e) {
    throw std::runtime_error(log_file.string() + ": the header's meta lacks the loop rates: " + e.what());
  }
  SessionSummary summary(options);
  const std::string where = log_file.string() + ": ";
  try {
    for (const auto& r : log.Decode<LeaderTickRecord>("leader", LeaderStreamSpec())) summary.AddLeader(r);
    for (const auto& r : log.Decode<FollowerTickRecord>("follower", FollowerStreamSpec())) summary.AddFollower(r);
    const auto end = log.Decode<SessionEndRecord>("end", EndStreamSpec());
    if (!end.empty()) summary.SetEnd(end.back());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(where + e.what());
  }
  TeleopOutputs out;
  out.summary = summary.Summary();
  out.leader_csv = summary.leader_csv();
  out.follower_csv = summary.follower_csv();
  out.periods_csv = summary.PeriodsCsv();
  if (log.truncated) out.warnings.push_back(where + "the last frame was cut short (the run was killed)");
  return out;
}

}  // namespace robossis::teleop
