#include "src/teleop/teleop_session.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <optional>
#include <random>
#include <stdexcept>

#include "haptics/device/device_factory.h"
#include "haptics/rendering/renderer_factory.h"
#include "robot/actuation/pulse_recorder_follower.h"
#include "robot/drivers/hal_follower.h"
#include "robot/sim/rsr_simulation.h"
#include "robot/sim/simulated_plant.h"
#include "src/core/rt/periodic_loop.h"
#include "src/teleop/flight_recorder.h"
#include "src/teleop/follower_limits.h"
#include "src/teleop/follower_unit.h"
#include "src/teleop/in_process_link.h"
#include "src/teleop/leader_unit.h"
#include "src/teleop/local_command_link.h"
#include "src/teleop/session_summary.h"
#include "src/teleop/streamed_text_file.h"

namespace robossis::teleop {

std::vector<std::string> KnownFollowers() { return {"sim", "recorder", "hal"}; }

bool EnablesAtStartByDefault(const std::string& kind) { return kind != "hal"; }

namespace {

// The muscles of the reduction scenario (femur axis along z through the fracture site), pulling with load_n and
// twisting with load_nm at the home pose (the fragments aligned there); none without a load.
std::optional<sim::MuscleTraction> SimTraction(const TeleopSetup& setup, double load_n, double load_nm) {
  std::optional<sim::MuscleTraction> traction;
  if (load_n > 0 || load_nm > 0) {
    const Eigen::Isometry3d home = setup.rsr->geometry().X_FM_home;
    traction.emplace(setup.sim.traction, Eigen::Vector3d::UnitZ(),
                     Eigen::Vector3d(0, 0, setup.sim.bone.fracture_site_z_m), home);
    traction->Calibrate(home, home.linear(), load_n, load_nm);
  }
  return traction;
}

}  // namespace

std::unique_ptr<robot::Follower> MakeFollowerBackEnd(const std::string& kind, const TeleopSetup& setup,
                                                     double max_duration_s, double load_n, double load_nm) {
  const robot::RsrModel& rsr = *setup.rsr;
  const Eigen::Isometry3d home = rsr.geometry().X_FM_home;
  if (kind == "sim") {
    sim::SimOptions options;
    options.with_bone = false;  // at the home pose the fragments touch: a motion would push one into the other
    const std::optional<sim::MuscleTraction> traction = SimTraction(setup, load_n, load_nm);
    options.with_traction = traction.has_value();
    // The simulated robot steps on a loop of its own (sim::SimulatedPlant), not inside the follower's tick.
    return std::make_unique<sim::SimulatedPlant>(std::make_unique<sim::RsrSimulation>(
        rsr, setup.sim, nullptr, traction ? &*traction : nullptr, home, options));
  }
  if (kind == "hal") return drivers::MakeHalFollower(rsr, setup.config_dir);
  if (kind == "recorder") {
    const double rate_hz = setup.transfer.rates.actuation_rate_hz;
    const auto n = static_cast<std::size_t>(std::min(max_duration_s * rate_hz + 1000.0, 4.0e6));
    return std::make_unique<actuation::PulseRecorderFollower>(rsr, setup.actuation, home, n, n);
  }
  throw std::invalid_argument("follower back end '" + kind + "' is not known (sim, recorder, hal)");
}

TeleopSetup TeleopSetup::Load(const std::filesystem::path& data_dir, const robot::RsrModel& rsr,
                              const robot::Sigma7Model& sigma7) {
  const std::filesystem::path config = data_dir / "config";
  TeleopSetup s;
  s.rsr = &rsr;
  s.sigma7 = &sigma7;
  s.haptics = haptics::HapticsConfig::FromYaml(config / "haptics.yaml");
  s.transfer = transfer::TransferConfig::FromYaml(config / "transfer.yaml");
  // The actuation rate's one place is transfer.yaml; actuation.yaml's rate-dependent checks use it.
  s.actuation = actuation::ActuationConfig::FromYaml(config / "actuation.yaml", s.transfer.rates.actuation_rate_hz);
  s.follower = FollowerConfig::FromYaml(config / "follower.yaml", s.transfer.caps);
  s.leader = LeaderConfig::FromYaml(config / "leader.yaml");
  s.leader.feedback.max_force_n = s.haptics.limits.max_force_n;  // the walls' caps bound walls + load (haptics.yaml)
  s.leader.feedback.max_torque_nm = s.haptics.limits.max_torque_nm;
  s.leader.guard = s.follower.guard;  // one guard tuning for both units (follower.yaml)
  s.leader.max_linear_accel_m_s2 = s.follower.setpoint.max_linear_accel_m_s2;  // the follower's caps (follower.yaml)
  s.leader.max_angular_accel_rad_s2 = s.follower.setpoint.max_angular_accel_rad_s2;
  const auto motor_speeds = s.actuation.MaxJointSpeeds();  // the motors' top speeds (actuation.yaml)
  for (int i = 0; i < actuation::kNumMotors; ++i) s.leader.max_joint_speed[i] = motor_speeds[i];
  s.follower.setpoint.setpoint_period_s = 1.0 / s.transfer.rates.transfer_rate_hz;  // one set-point per transfer tick
  s.follower.model_fingerprint = ModelFingerprint({config / "rsr.yaml", config / "actuation.yaml"});
  s.sim = sim::LoadSimConfig(config / "sim.yaml", data_dir);
  s.config_dir = config;
  return s;
}

namespace {

enum class Units { kBoth, kLeader, kFollower };

void CheckRequest(const TeleopRequest& r, Units units) {
  if (units != Units::kFollower) {
    haptics::ParseMethodName(r.method, "--method");  // the one parser of method names; throws naming the list
  }
  if (units != Units::kLeader) {
    const auto followers = KnownFollowers();
    if (std::find(followers.begin(), followers.end(), r.follower) == followers.end()) {
      throw std::invalid_argument("--follower: unknown follower '" + r.follower + "'; known: sim, recorder, hal");
    }
  }
  if (!(r.duration_s > 0 && r.duration_s <= 3600)) {
    throw std::invalid_argument("--duration-s: expected 0 < N <= 3600 s");
  }
}

// The leader's side of a session: the device, the renderer and the leader unit over `link`.
struct LeaderSide {
  std::unique_ptr<haptics::HapticDevice> device;
  std::unique_ptr<haptics::HapticRenderer> renderer;
  std::unique_ptr<LeaderUnit> unit;
};

LeaderSide MakeLeaderSide(const TeleopRequest& request, const TeleopSetup& setup, LeaderLink& link) {
  LeaderConfig config = setup.leader;
  config.rate_hz = request.rate_hz;
  if (!request.feedback.empty()) config.feedback.mode = ParseFeedbackMode("--feedback", request.feedback);
  if (request.feedback_gain >= 0) config.feedback.gain = request.feedback_gain;
  if (!request.feedback_passivity.empty()) {
    config.feedback.passivity.scheme = ParseFeedbackPassivityScheme("--feedback-passivity", request.feedback_passivity);
  }
  if (request.let_go_detector) config.feedback.detect_let_go = true;
  try {
    config.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--rate-hz: ") + e.what());
  }
  const robot::RsrModel& rsr = *setup.rsr;
  LeaderSide side;
  haptics::DeviceScriptOptions script = config.sim_script;
  script.replay_frame = setup.transfer.mapping;
  side.device = haptics::MakeDevice(request.device, *setup.sigma7, setup.haptics, config.device, script);
  if (side.device->EnableForces(true) != haptics::DeviceStatus::kOk) {
    throw std::runtime_error("--device " + request.device + ": the device refused to enable its forces");
  }
  side.renderer = haptics::MakeRenderer(
      request.method, setup.haptics, rsr, haptics::HcToRsrMap{}, request.rate_hz, request.atlas,
      request.real_clock ? haptics::BackgroundWork::kThread : haptics::BackgroundWork::kSimulated);
  std::random_device entropy;
  const std::uint64_t session = (static_cast<std::uint64_t>(entropy()) << 32) | entropy();
  side.unit = std::make_unique<LeaderUnit>(config, setup.transfer, rsr, *side.device, *side.renderer, link,
                                           rsr.geometry().X_FM_home, session);
  return side;
}

// The follower's side: the back end and the follower unit over `link`, stamped by `clock`.
struct FollowerSide {
  std::unique_ptr<robot::Follower> back_end;
  std::unique_ptr<FollowerUnit> unit;
  std::int64_t status_stamp_offset_ns = 0;  // the link's (FollowerLink::StatusStampOffsetNs), for the log
};

FollowerSide MakeFollowerSide(const TeleopRequest& request, const TeleopSetup& setup, FollowerLink& link,
                              const rt::Clock& clock) {
  FollowerSide side;
  side.back_end = MakeFollowerBackEnd(request.follower, setup, request.duration_s, request.sim_load_n,
                                      request.sim_load_nm);
  FollowerConfig config = setup.follower;
  if (request.follower == "sim") {
    // The simulation's own masses: the ring (no fragment here) and the arms, whose weight the wrench estimate removes.
    const sim::MassConfig& m = setup.sim.masses;
    config.wrench.carried_mass_kg = m.moving_ring_kg;
    config.wrench.gravity_F_mps2 = setup.sim.physics.gravity_F_mps2;
    config.wrench.remove_arm_weight = true;
    config.wrench.arm_masses = m;
  }
  side.unit = std::make_unique<FollowerUnit>(*setup.rsr, setup.actuation, config, *side.back_end, link, clock);
  side.status_stamp_offset_ns = link.StatusStampOffsetNs();
  return side;
}

StateCommandMessage EnableCommand() {
  StateCommandMessage enable;
  enable.command = StateCommand::kEnable;
  enable.sequence = 1;
  return enable;
}

// The operator's commands at a follower's start, in order: home, then enable (each only if asked for). An enable
// that arrives while the follower is homing takes effect once it is homed.
std::vector<StateCommandMessage> StartCommands(const TeleopRequest& request) {
  std::vector<StateCommandMessage> commands;
  if (request.home_at_start) {
    StateCommandMessage home;
    home.command = StateCommand::kHome;
    home.sequence = 1;
    commands.push_back(home);
  }
  if (request.enable_at_start) {
    commands.push_back(EnableCommand());
    commands.back().sequence = commands.size();
  }
  return commands;
}

// The clock a run steps (simulated) or sleeps on (real): exactly one is set.
struct RunClock {
  rt::SimulatedClock* simulated = nullptr;
  const rt::MonotonicClock* real = nullptr;
};

// The CSVs of a run with request.csv_dir set: the summary's text goes to the files as the run goes (the files of the
// units run only). Without csv_dir, nothing: the summary keeps the text for TeleopOutputs.
class SessionCsv {
 public:
  SessionCsv(const std::filesystem::path& dir, bool leader, bool follower) {
    if (dir.empty()) return;
    if (leader) leader_ = std::make_unique<StreamedTextFile>(dir / "leader.csv");
    if (follower) follower_ = std::make_unique<StreamedTextFile>(dir / "follower.csv");
    streaming_ = true;
  }
  void Take(SessionSummary& summary) {
    if (!streaming_) return;
    summary.MoveCsvTo(leader_text_, follower_text_);
    if (leader_) leader_->Append(leader_text_);
    if (follower_) follower_->Append(follower_text_);
    leader_text_.clear();  // (a unit not run: its header only, not written)
    follower_text_.clear();
  }
  void Flush() {
    if (leader_) leader_->Flush();
    if (follower_) follower_->Flush();
  }

 private:
  bool streaming_ = false;
  std::unique_ptr<StreamedTextFile> leader_, follower_;
  std::string leader_text_, follower_text_;
};

// [assumed] After a recorder failure the session runs on for the deceleration from the speed caps at the
// acceleration caps plus this margin, the follower holding, and then ends: the drives are unpowered at rest, not
// mid-motion (unpowered, they stop where they are).
inline constexpr double kRecorderFailureMargin_s = 0.5;

double RecorderFailureRunOn_s(const FollowerConfig& follower) {
  const SetPointLimits& l = follower.setpoint;
  return std::max(l.caps.max_linear_speed_m_s / l.max_linear_accel_m_s2,
                  l.caps.max_angular_speed_rad_s / l.max_angular_accel_rad_s2) +
         kRecorderFailureMargin_s;
}

// Runs the sides given (either may be null, not both) on their loops, records every tick in `log_file`, and
// computes the outputs. `background` runs on the calling thread beside the flight recorder's drain. A recorder
// failure (see FollowerUnit::WatchRecorder) holds the follower, ends the run and is named in recorder_error.
TeleopOutputs RunSides(const TeleopRequest& request, const TeleopSetup& setup, Units units, LeaderSide* leader,
                       FollowerSide* follower, RunClock clock, const std::filesystem::path& log_file,
                       const std::atomic<bool>* stop, const std::function<void(double)>& background) {
  const double follower_rate_hz = setup.transfer.rates.actuation_rate_hz;
  const char* unit_names[] = {"both", "leader", "follower"};
  nlohmann::json meta = {{"device", request.device},     {"method", request.method},
                         {"follower", request.follower}, {"rate_hz", request.rate_hz},
                         {"follower_rate_hz", follower_rate_hz}, {"duration_s", request.duration_s},
                         {"clock", clock.real ? "real" : "simulated"}, {"units", unit_names[static_cast<int>(units)]},
                         {"max_linear_speed_m_s", setup.transfer.caps.max_linear_speed_m_s},
                         {"max_angular_speed_rad_s", setup.transfer.caps.max_angular_speed_rad_s}};
  if (leader != nullptr) {
    const transfer::HcToRsrFrame& frame = setup.transfer.mapping;
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> R = frame.R_FO;
    meta["feedback_gain"] = request.feedback_gain >= 0 ? request.feedback_gain : setup.leader.feedback.gain;
    meta["feedback_translation_scale"] = frame.translation_scale;
    meta["feedback_R_FO"] = std::vector<double>(R.data(), R.data() + 9);
  }
  // What the follower's link adds to the stamps of the statuses it sends: the leader's log, which holds those
  // stamps, joins this one on the follower's clock (ReplaySplitSession).
  if (follower != nullptr) meta["status_stamp_offset_ns"] = follower->status_stamp_offset_ns;
  std::vector<StreamSpec> streams = {LeaderStreamSpec(), FollowerStreamSpec(), EndStreamSpec()};
  SessionLogWriter log(log_file, meta, streams);
  SessionSummary summary(SummaryOptionsFromMeta(meta));
  SessionCsv csv(request.csv_dir, leader != nullptr, follower != nullptr);
  std::atomic<bool> recorder_failed{false};  // set by the recorder or the follower unit; the follower unit holds
  std::string recorder_error;                // why (the simulated clock's drain; the real clock's recorder.Stop())
  if (follower) follower->unit->WatchRecorder(&recorder_failed);
  const auto drain = [&](SessionLogWriter& w) {
    LeaderTickRecord l;
    while (leader && leader->unit->records().TryPop(l)) {
      w.Append(kLeaderStream, &l);
      summary.AddLeader(l);
    }
    FollowerTickRecord f;
    while (follower && follower->unit->TakeRecord(f)) {
      w.Append(kFollowerStream, &f);
      summary.AddFollower(f);
    }
    csv.Take(summary);
  };
  // A replay ends the session 0.5 s after its last sample (the robot has come to rest).
  double ended_since_s = -1;
  double failed_since_s = -1;
  const double failure_run_on_s = RecorderFailureRunOn_s(setup.follower);
  const auto keep_going = [&](double now_s) {
    if (background) background(now_s);
    if (stop && stop->load(std::memory_order_relaxed)) return false;
    if (recorder_failed.load(std::memory_order_relaxed)) {
      if (failed_since_s < 0) failed_since_s = now_s;
      if (now_s - failed_since_s >= failure_run_on_s) return false;
    }
    if (!leader) return true;
    LeaderTickRecord latest;
    const bool ended = leader->unit->latest().Read(latest) &&
                       latest.leader_state == static_cast<std::uint8_t>(LeaderState::kEnded);
    if (!ended) ended_since_s = -1;
    else if (ended_since_s < 0) ended_since_s = now_s;
    return !(ended && now_s - ended_since_s >= 0.5);
  };

  std::vector<rt::ScheduledTask> tasks;
  if (leader) {
    rt::LoopOptions o;
    o.name = "leader";
    o.period_ns = std::llround(1e9 / request.rate_hz);
    o.fifo_priority = rt::kHapticLoopFifoPriority;
    tasks.push_back({leader->unit.get(), o});
  }
  if (follower) {
    rt::LoopOptions o;
    o.name = "follower";
    o.period_ns = std::llround(1e9 / follower_rate_hz);
    o.fifo_priority = rt::kActuationLoopFifoPriority;
    tasks.push_back({follower->unit.get(), o});
    // Ticked after the follower unit when both are due, as the robot moves after the command reached it.
    if (const robot::Follower::Plant plant = follower->back_end->plant(); plant.task != nullptr) {
      tasks.push_back({plant.task, rt::PlantLoopOptions(plant.period_ns)});
    }
  }

  rt::RunResult run;
  if (clock.real) {
    FlightRecorder recorder(log, drain, 0.002, &recorder_failed);
    recorder.Start();
    run = rt::RunRealTime(*clock.real, tasks, request.duration_s, keep_going);
    recorder_error = recorder.Stop();
  } else {
    // As the recorder thread does: the first error stops the draining and holds the follower.
    const auto drain_once = [&] {
      if (!recorder_error.empty()) return;
      try {
        drain(log);
      } catch (const std::exception& e) {
        recorder_error = e.what();
        recorder_failed.store(true);
      }
    };
    run = rt::RunSimulated(*clock.simulated, tasks, request.duration_s, [&](double now_s) {
      drain_once();
      if (leader) leader->renderer->StepSimulatedBackground(now_s);
      return keep_going(now_s);
    });
    drain_once();
  }

  // The session is over: the device's forces off, the drives unpowered (they hold where they are).
  if (leader) leader->device->EnableForces(false);
  if (follower) follower->back_end->Disable();

  SessionEndRecord end;
  end.elapsed_s = run.elapsed_s;
  std::size_t next = 0;
  if (leader) {
    const rt::LoopStats& ls = run.stats[next++];
    end.leader_loop_ticks = ls.ticks;
    end.leader_overruns = ls.overruns;
    end.leader_overruns_late_wake = ls.overruns_late_wake;
    end.leader_overruns_long_tick = ls.overruns_long_tick;
    end.leader_period_jitter_us_p99 = ls.period_jitter.PercentileUs(0.99);
    end.leader_period_jitter_us_max = ls.period_jitter.max_us();
    end.leader_wake_latency_us_p99 = ls.wake_latency.PercentileUs(0.99);
    end.leader_records_dropped = leader->unit->counters().records_dropped;
    end.device_failures = leader->unit->counters().device_failures;
    end.ik_rejected = leader->unit->counters().ik_rejected;
  }
  if (follower) {
    const rt::LoopStats& fs = run.stats[next++];
    const FollowerCounters& c = follower->unit->counters();
    end.follower_loop_ticks = fs.ticks;
    end.follower_overruns = fs.overruns;
    end.follower_overruns_late_wake = fs.overruns_late_wake;
    end.follower_overruns_long_tick = fs.overruns_long_tick;
    end.follower_period_jitter_us_p99 = fs.period_jitter.PercentileUs(0.99);
    end.follower_period_jitter_us_max = fs.period_jitter.max_us();
    end.follower_wake_latency_us_p99 = fs.wake_latency.PercentileUs(0.99);
    end.watchdog_holds = c.watchdog_holds;
    end.setpoints_accepted = c.setpoints_accepted;
    end.setpoints_rejected = c.setpoints_rejected;
    end.follower_records_dropped = c.records_dropped;
    if (next < run.stats.size()) {  // the plant's own loop, scheduled after the follower's
      const rt::LoopStats& ps = run.stats[next++];
      end.plant_loop_ticks = ps.ticks;
      end.plant_overruns = ps.overruns;
      end.plant_overruns_late_wake = ps.overruns_late_wake;
      end.plant_overruns_long_tick = ps.overruns_long_tick;
    }
  }
  if (recorder_error.empty()) {
    try {
      log.Append(kEndStream, &end);
      log.Flush();
      summary.SetEnd(end);
    } catch (const std::exception& e) {
      recorder_error = e.what();
    }
  }
  // What was recorded goes to the CSVs, after a failure of the log too (a failure of a CSV is named already).
  try {
    csv.Take(summary);
    csv.Flush();
  } catch (const std::exception& e) {
    if (recorder_error.empty()) recorder_error = e.what();
  }

  TeleopOutputs out;
  out.summary = summary.Summary();
  out.summary["units"] = meta["units"];
  if (recorder_error.empty() && recorder_failed.load()) {
    recorder_error = "the flight recorder's queue was full (" +
                     std::to_string(end.leader_records_dropped + end.follower_records_dropped) +
                     " records dropped)";
  }
  if (!recorder_error.empty()) {
    out.recorder_error = "recording failed: " + recorder_error +
                         (follower ? "; the follower held the robot at rest and the session ended" : "");
    out.summary["recorder_error"] = out.recorder_error;
  }
  if (request.csv_dir.empty()) {  // else streamed: the files hold them, and these stay empty
    out.leader_csv = summary.leader_csv();
    out.follower_csv = summary.follower_csv();
  }
  out.periods_csv = summary.PeriodsCsv();
  out.warnings = run.warnings;
  return out;
}

}  // namespace

TeleopOutputs RunTeleop(const TeleopRequest& request, const TeleopSetup& setup, const std::filesystem::path& log_file) {
  CheckRequest(request, Units::kBoth);
  rt::SimulatedClock sim_clock;
  rt::MonotonicClock mono_clock;
  const rt::Clock& clock = request.real_clock ? static_cast<const rt::Clock&>(mono_clock) : sim_clock;
  InProcessLink link(clock, 64, request.link_delay_s);
  FollowerSide follower = MakeFollowerSide(request, setup, link, clock);
  LeaderSide leader = MakeLeaderSide(request, setup, link);
  for (const StateCommandMessage& command : StartCommands(request)) link.operator_commands().Send(command);
  RunClock run_clock;
  if (request.real_clock) run_clock.real = &mono_clock;
  else run_clock.simulated = &sim_clock;
  return RunSides(request, setup, Units::kBoth, &leader, &follower, run_clock, log_file, nullptr, {});
}

TeleopOutputs RunLeader(const TeleopRequest& request, const TeleopSetup& setup, LeaderLink& link,
                        const std::filesystem::path& log_file, const std::atomic<bool>* stop) {
  CheckRequest(request, Units::kLeader);
  TeleopRequest real = request;
  real.real_clock = true;
  rt::MonotonicClock clock;
  // On two machines each reads its own configs: a follower validating against other limits would refuse the
  // set-points (or judge them in another workspace), so the leader does not start.
  CheckFollowerLimits(link, LimitsOf(setup.follower));
  LeaderSide leader = MakeLeaderSide(real, setup, link);
  RunClock run_clock;
  run_clock.real = &clock;
  // The leader sends no state command: enable, reset and home are the panel's or the follower's console's (the
  // leader's link credentials do not grant the command topic).
  return RunSides(real, setup, Units::kLeader, &leader, nullptr, run_clock, log_file, stop, {});
}

TeleopOutputs RunFollower(const TeleopRequest& request, const TeleopSetup& setup, FollowerLink& link,
                          const rt::MonotonicClock& clock, const std::filesystem::path& log_file,
                          const std::atomic<bool>* stop, const std::function<void()>& running) {
  CheckRequest(request, Units::kFollower);
  TeleopRequest real = request;
  real.real_clock = true;
  LocalCommandLink local(link);
  FollowerSide follower = MakeFollowerSide(real, setup, local, clock);
  for (const StateCommandMessage& command : StartCommands(request)) local.SendLocal(command);
  RunClock run_clock;
  run_clock.real = &clock;
  bool announced = false;
  return RunSides(real, setup, Units::kFollower, nullptr, &follower, run_clock, log_file, stop, [&](double) {
    if (announced || !running) return;
    announced = true;
    running();
  });
}

TeleopOutputs ReplaySessionLog(const std::filesystem::path& log_file) {
  const SessionLog log = ReadSessionLog(log_file);
  SummaryOptions options;
  try {
    options = SummaryOptionsFromMeta(log.meta);
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
  out.summary["units"] = log.meta.value("units", "both");
  if (log.truncated) out.warnings.push_back(where + "the last frame was cut short (the run was killed)");
  return out;
}

}  // namespace robossis::teleop
