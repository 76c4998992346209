#include "src/teleop/offline_chain.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "robot/actuation/step_rate.h"
#include "src/core/units.h"
#include "src/teleop/delay_estimate.h"
#include "src/teleop/follower_config.h"

namespace robossis::teleop {

namespace {

using transfer::HcRecord;

// The validator's caps are the transfer's: one place for each limit, whatever the caller changed.
SetPointLimits LimitsWithTransferCaps(const ChainSetup& setup) {
  SetPointLimits limits = setup.limits;
  limits.caps = setup.transfer.caps;
  return limits;
}

// The ideal incremental trajectory: the clean hand through eq. 10–11 alone (no stall, no filter), at hand time.
void IdealReference(const transfer::HcTrajectory& hc, const transfer::TransferConfig& config, TransferTrace& trace) {
  transfer::IncrementalMapper mapper(config.mapping, config.caps);
  Vector6d x = Vector6d::Zero();
  for (const HcRecord& r : hc.clean_records) {
    mapper.SetClutch(r.clutch);
    transfer::MappingIncrement inc;
    std::uint8_t capped = 0;
    if (mapper.Push(r.ToSample(), inc) == transfer::SampleVerdict::kAccepted) {
      x += inc.delta_F;
      capped = static_cast<std::uint8_t>((inc.scale_linear < 1 ? teleop::kCappedLinear : 0) |
                                         (inc.scale_angular < 1 ? teleop::kCappedAngular : 0));
    }
    trace.t_ref.push_back(r.time_s);
    trace.ref.push_back(x);
    trace.ref_capped.push_back(capped);
  }
}

// The hand→set-point delay by the one estimator (delay_estimate.h): the set-point, subsampled to 1 kHz, against
// the ideal incremental trajectory; the samples where eq. 11 capped the clean hand are not judged.
void EstimateDelay(TransferTrace& tr) {
  if (tr.t_ref.empty() || tr.t.empty()) return;
  std::vector<double> t;
  std::vector<Vector6d> x;
  for (std::size_t k = 0; k < tr.t.size(); k += 10) {
    t.push_back(tr.t[k]);
    x.push_back(tr.displacement[k]);
  }
  tr.summary.final_tracking_error_mm = MToMm((tr.displacement.back().head<3>() - tr.ref.back().head<3>()).norm());
  const DelayEstimate e =
      teleop::EstimateDelay({.t_s = tr.t_ref, .x = tr.ref, .capped = tr.ref_capped}, {.t_s = t, .x = x});
  tr.summary.delay_status = ToString(e.status);
  if (!e.ok()) return;
  tr.summary.delay_ms = e.delay_s * 1e3;
  tr.summary.delay_rms_residual_mm_s = (e.angular ? RadToDeg(1.0) : MToMm(1.0)) * e.rms_residual;
}

// Per-tick bookkeeping shared by both chains.
class Recorder {
 public:
  Recorder(TransferTrace& trace, const ChainSetup& setup)
      : tr_(trace), setup_(setup), validator_(*setup.model, LimitsWithTransferCaps(setup)), guard_(*setup.model, setup.guard),
        X_cmd_(setup.X_FM_start) {
    const robot::RsrLimitCheck start = robot::CalcInverseKinematics(*setup.model, setup.X_FM_start).tightest();
    tr_.summary.min_limit_margin = start.margin;
    tr_.summary.tightest_limit = "arm " + std::to_string(start.arm + 1) + " " + robot::ToString(start.joint);
  }

  void FastTick(const transfer::RsrSetPoint& sp, double time_s, actuation::Actuator* act) {
    const double dt = 1.0 / setup_.transfer.rates.actuation_rate_hz;
    TransferSummary& s = tr_.summary;
    tr_.t.push_back(time_s);
    tr_.displacement.push_back(sp.displacement);
    tr_.velocity.push_back(sp.velocity);
    tr_.acceleration.push_back(sp.acceleration);
    s.max_speed_mm_s = std::max(s.max_speed_mm_s, MToMm(sp.velocity.head<3>().norm()));
    s.max_angular_speed_deg_s = std::max(s.max_angular_speed_deg_s, RadToDeg(sp.velocity.tail<3>().norm()));
    s.max_accel_mm_s2 = std::max(s.max_accel_mm_s2, MToMm(sp.acceleration.head<3>().norm()));
    s.max_angular_accel_deg_s2 = std::max(s.max_angular_accel_deg_s2, RadToDeg(sp.acceleration.tail<3>().norm()));
    if (have_prev_) {
      s.max_jerk_mm_s3 = std::max(s.max_jerk_mm_s3, MToMm((sp.acceleration.head<3>() - prev_a_).norm() / dt));
    }
    prev_a_ = sp.acceleration.head<3>();
    have_prev_ = true;
    ++s.ticks;
    if (act == nullptr) return;
    // The one validated path: the guard projects the set-point onto the feasible set (no joint limit crossed, the
    // cones included; exact IK), then the validator checks it (finite, in order, inside, caps). A refused set-point
    // holds the robot where it is.
    // A held robot approaches a set-point that ran ahead at the caps, never faster.
    const Vector6d towards = CapStepToSpeeds(robot::TwistStepBetween(X_cmd_, sp.X_FM), setup_.transfer.caps, dt);
    const bool reachable = towards == robot::TwistStepBetween(X_cmd_, sp.X_FM);
    const robot::FeasibleMotionResult guarded =
        guard_.Step(X_cmd_, reachable ? sp.X_FM : robot::ApplyTwistStep(X_cmd_, towards));
    if (guarded.status != robot::FeasibleMotionStatus::kTracked) ++s.guard_limited_ticks;
    SetPointSample sample;
    sample.time_s = time_s;
    sample.X_FM = guarded.X_FM;
    sample.twist_F = guarded.status == robot::FeasibleMotionStatus::kTracked && reachable
                         ? sp.velocity
                         : Vector6d(robot::TwistStepBetween(X_cmd_, guarded.X_FM) / dt);
    const SetPointVerdict verdict = validator_.Check(sample);
    Vector6d twist = Vector6d::Zero();
    if (verdict == SetPointVerdict::kAccepted) {
      X_cmd_ = guarded.X_FM;
      twist = sample.twist_F;
    } else {
      ++s.setpoints_rejected;
      ++s.rejected_by_verdict[static_cast<int>(verdict)];
    }
    const actuation::ActuationOutput& out = act->Tick(time_s, X_cmd_, twist);
    tr_.q.push_back(out.command.q);
    tr_.q_dot.push_back(out.command.q_dot);
    tr_.steps.push_back(out.steps);
    tr_.events.insert(tr_.events.end(), out.events.begin(), out.events.begin() + out.num_events);
    for (int m = 0; m < 6; ++m) s.steps_error_max = std::max(s.steps_error_max, std::abs(out.step_error[m]));
    if (out.status == actuation::ActuationStatus::kJointLimit) ++s.limit_ticks;
    if (out.status == actuation::ActuationStatus::kRateLimit) ++s.rate_limited_ticks;
    const robot::RsrIkResult ik = robot::CalcInverseKinematics(*setup_.model, X_cmd_);
    if (!ik.feasible) ++s.follower_limit_violations;
    const robot::RsrLimitCheck& tight = ik.tightest();
    if (tight.margin < s.min_limit_margin) {
      s.min_limit_margin = tight.margin;
      s.tightest_limit = "arm " + std::to_string(tight.arm + 1) + " " + robot::ToString(tight.joint);
    }
    if (ik.feasible) {
      s.max_joint_ik_error = std::max(s.max_joint_ik_error, (ik.joints.actuated() - out.command.q).cwiseAbs().maxCoeff());
    }
  }

  void Finish(actuation::Actuator* act) {
    TransferSummary& s = tr_.summary;
    s.num_events = tr_.events.size();
    if (act != nullptr) {
      tr_.q_start = act->q_start();
      for (int m = 0; m < 6; ++m) {
        s.steps_total[m] = act->output().steps[m];
        s.steps_commanded[m] = (act->q()[m] - act->q_start()[m]) * act->config().motors[m].steps_per_unit;
      }
      s.max_step_rate_hz = actuation::MaxStepRateHz(tr_.events);
    }
  }

 private:
  TransferTrace& tr_;
  const ChainSetup& setup_;
  SetPointValidator validator_;
  robot::FeasibleMotionGuard guard_;
  Eigen::Isometry3d X_cmd_;
  Eigen::Vector3d prev_a_ = Eigen::Vector3d::Zero();
  bool have_prev_ = false;
};

}  // namespace

ChainSetup LoadChainSetup(const std::filesystem::path& config_dir, const robot::RsrModel& model) {
  ChainSetup setup;
  setup.transfer = transfer::TransferConfig::FromYaml(config_dir / "transfer.yaml");
  // The actuation rate's one place is transfer.yaml; actuation.yaml's rate-dependent checks use it.
  setup.actuation =
      actuation::ActuationConfig::FromYaml(config_dir / "actuation.yaml", setup.transfer.rates.actuation_rate_hz);
  const FollowerConfig follower = FollowerConfig::FromYaml(config_dir / "follower.yaml", setup.transfer.caps);
  setup.limits = follower.setpoint;
  setup.guard = follower.guard;
  setup.model = &model;
  setup.X_FM_start = model.geometry().X_FM_home;
  return setup;
}

double MinimumMoveDuration(const transfer::TimedMoveRequest& request, const ChainSetup& setup) {
  const transfer::SpeedCaps& caps = setup.transfer.caps;
  const double inf = std::numeric_limits<double>::infinity();
  const double at_caps = transfer::TimedMove::DurationForPeakSpeeds(
      request, caps.max_linear_speed_m_s > 0 ? caps.max_linear_speed_m_s : inf,
      caps.max_angular_speed_rad_s > 0 ? caps.max_angular_speed_rad_s : inf);
  return at_caps > 0 ? std::max(at_caps, 1.0 / setup.transfer.rates.actuation_rate_hz) : 0.0;
}

PathVerdict ValidateMove(const transfer::TimedMove& move, const ChainSetup& setup) {
  return ValidateMove(move, *setup.model, LimitsWithTransferCaps(setup), setup.transfer.rates.actuation_rate_hz);
}

TransferTrace RunTransferChain(const transfer::HcTrajectory& hc, const ChainSetup& setup) {
  if (hc.records.empty()) throw std::invalid_argument("transfer: the HC trajectory has no samples");
  TransferTrace tr;
  transfer::MotionTransfer mt(setup.transfer, setup.X_FM_start);
  std::unique_ptr<actuation::Actuator> act;
  const double t0 = hc.records.front().arrival_s;
  if (setup.with_actuation) act = std::make_unique<actuation::Actuator>(*setup.model, setup.actuation, setup.X_FM_start, t0);
  double t_end = 0;
  for (const HcRecord& r : hc.records) t_end = std::max({t_end, r.arrival_s, r.time_s});
  t_end += setup.settle_s;
  const double dt_slow = 1.0 / setup.transfer.rates.transfer_rate_hz;
  const int ratio = setup.transfer.rates.upsampling_ratio();
  const double dt_fast = dt_slow / ratio;
  const std::size_t n_slow = static_cast<std::size_t>(std::ceil((t_end - t0) / dt_slow));
  tr.t.reserve(n_slow * ratio);
  Recorder rec(tr, setup);
  std::size_t next = 0;
  Vector6d hc_view = hc.records.front().pose_mm_deg;
  for (std::size_t k = 0; k < n_slow; ++k) {
    const double t_slow = t0 + k * dt_slow;
    // Deliver what has arrived by this tick (a stall delivers a burst).
    while (next < hc.records.size() && hc.records[next].arrival_s <= t_slow + 1e-12) {
      const HcRecord& r = hc.records[next++];
      mt.SetClutch(r.clutch);
      mt.PushHcSample(r.ToSample());
      hc_view = r.pose_mm_deg;
    }
    mt.TransferTick();
    tr.t_slow.push_back(t_slow);
    tr.goal.push_back(mt.tick_info().goal);
    tr.hc_view.push_back(hc_view);
    tr.scale_linear.push_back(mt.tick_info().scale_linear);
    tr.scale_angular.push_back(mt.tick_info().scale_angular);
    tr.hc_speed.push_back(mt.tick_info().hc_speed_m_s);
    tr.summary.max_hc_speed_mm_s = std::max(tr.summary.max_hc_speed_mm_s, MToMm(mt.tick_info().hc_speed_m_s));
    for (int j = 0; j < ratio; ++j) {
      const transfer::RsrSetPoint& sp = mt.ActuationTick();
      rec.FastTick(sp, t0 + (k * ratio + j + 1) * dt_fast, act.get());
    }
  }
  tr.summary.counters = mt.counters();
  rec.Finish(act.get());
  IdealReference(hc, setup.transfer, tr);
  EstimateDelay(tr);
  return tr;
}

TransferTrace RunMoveChain(const std::vector<transfer::TimedMoveRequest>& moves, const std::vector<double>& durations,
                           const ChainSetup& setup) {
  TransferTrace tr;
  actuation::Actuator act(*setup.model, setup.actuation, setup.X_FM_start, 0.0);
  Recorder rec(tr, setup);
  const double dt = 1.0 / setup.transfer.rates.actuation_rate_hz;
  Eigen::Isometry3d X = setup.X_FM_start;
  double t_start = 0;
  std::size_t tick = 0;
  Vector6d base = Vector6d::Zero();
  for (std::size_t i = 0; i < moves.size(); ++i) {
    transfer::TimedMoveRequest req = moves[i];
    req.start_time_s = t_start;
    const transfer::TimedMove move(X, req, durations[i]);
    const double t_end = move.end_time_s() + (i + 1 == moves.size() ? setup.settle_s : 0.0);
    while ((tick + 1) * dt <= t_end + 1e-12) {
      ++tick;
      transfer::RsrSetPoint sp = move.Evaluate(tick * dt);
      sp.displacement += base;
      rec.FastTick(sp, tick * dt, &act);
      tr.t_ref.push_back(tick * dt);
      tr.ref.push_back(sp.displacement);
    }
    base.head<3>() += req.delta_p_F;
    base.tail<3>() += req.delta_rot_F;
    X = move.X_FM_end();
    t_start = move.end_time_s();
  }
  rec.Finish(&act);
  tr.summary.delay_ms = 0;  // eq. 9 is evaluated directly at 10 kHz: no filter, no delay
  return tr;
}

FollowerReplay ReplayOnFollower(const TransferTrace& trace, const robot::RsrModel& model, robot::Follower& follower,
                                const Eigen::Isometry3d& X_FM_start, double step_s, double t_end, int csv_every) {
  if (trace.q.empty()) throw std::invalid_argument("replay: the trace has no joint commands");
  FollowerReplay r;
  r.csv = "t_s,cmd_x_mm,cmd_y_mm,cmd_z_mm,meas_x_mm,meas_y_mm,meas_z_mm,translation_error_mm,rotation_error_deg\n";
  const auto num = [](double v, const char* format) {
    char buf[48];
    std::snprintf(buf, sizeof buf, format, v);
    return std::string(buf);
  };
  double sum_e_p = 0, sum_e_r = 0;
  std::size_t k = 0;
  Eigen::Isometry3d X_cmd = X_FM_start;
  for (long n = 1; n * step_s <= t_end + 1e-12; ++n) {
    const double t_next = n * step_s;
    while (k + 1 < trace.t.size() && trace.t[k + 1] <= t_next + 1e-12) ++k;
    follower.Command(robot::RsrJointCommand{trace.t[k], trace.q[k], trace.q_dot[k]});
    follower.Service(t_next);
    const robot::RsrFollowerState state = follower.State();
    if (state.fault == robot::FollowerFault::kUnstable) throw std::runtime_error("replay: the simulation became unstable");
    const robot::RsrFkResult fk = robot::CalcForwardKinematics(model, trace.q[k], X_cmd);
    if (!fk.converged()) throw std::runtime_error("replay: FK of the commanded joints did not converge");
    X_cmd = fk.X_FM;
    const double e_p = (state.X_FM.translation() - X_cmd.translation()).norm();
    const double e_r = RotationAngleBetween(state.X_FM.linear(), X_cmd.linear());
    r.max_translation_error_m = std::max(r.max_translation_error_m, e_p);
    r.max_rotation_error_rad = std::max(r.max_rotation_error_rad, e_r);
    sum_e_p += e_p, sum_e_r += e_r, ++r.steps;
    r.duration_s = t_next;
    if (r.steps % csv_every == 0) {
      const Eigen::Vector3d c = X_cmd.translation() * kMToMm, m = state.X_FM.translation() * kMToMm;
      r.csv += num(t_next, "%.4f") + "," + num(c.x(), "%.4f") + "," + num(c.y(), "%.4f") + "," + num(c.z(), "%.4f") +
               "," + num(m.x(), "%.4f") + "," + num(m.y(), "%.4f") + "," + num(m.z(), "%.4f") + "," +
               num(MToMm(e_p), "%.3e") + "," + num(RadToDeg(e_r), "%.3e") + "\n";
    }
  }
  r.mean_translation_error_m = sum_e_p / std::max<long>(r.steps, 1);
  r.mean_rotation_error_rad = sum_e_r / std::max<long>(r.steps, 1);
  return r;
}

nlohmann::ordered_json SummaryJson(const TransferSummary& s) {
  nlohmann::ordered_json j;
  j["max_speed_mm_s"] = s.max_speed_mm_s;
  j["max_angular_speed_deg_s"] = s.max_angular_speed_deg_s;
  j["max_accel_mm_s2"] = s.max_accel_mm_s2;
  j["max_jerk_mm_s3"] = s.max_jerk_mm_s3;
  j["delay_ms"] = s.delay_ms;
  j["delay_status"] = s.delay_status;
  j["steps_error_max"] = s.steps_error_max;
  j["max_angular_accel_deg_s2"] = s.max_angular_accel_deg_s2;
  j["delay_velocity_rms_residual"] = s.delay_rms_residual_mm_s;
  j["final_tracking_error_mm"] = s.final_tracking_error_mm;
  j["max_hc_speed_mm_s"] = s.max_hc_speed_mm_s;
  j["max_joint_ik_error"] = s.max_joint_ik_error;
  j["steps_total"] = s.steps_total;
  j["steps_commanded"] = s.steps_commanded;
  j["step_events"] = s.num_events;
  j["max_step_rate_hz"] = s.max_step_rate_hz;
  j["ticks_10khz"] = s.ticks;
  j["joint_limit_ticks"] = s.limit_ticks;
  j["guard_limited_ticks"] = s.guard_limited_ticks;
  j["setpoints_rejected"] = s.setpoints_rejected;
  nlohmann::ordered_json by_verdict;
  for (int v = 1; v < kNumSetPointVerdicts; ++v) {
    by_verdict[ToString(static_cast<SetPointVerdict>(v))] = s.rejected_by_verdict[v];
  }
  j["setpoints_rejected_by_reason"] = by_verdict;
  j["follower_limit_violations"] = s.follower_limit_violations;
  j["min_limit_margin"] = s.min_limit_margin;
  j["tightest_limit"] = s.tightest_limit;
  j["rate_limited_ticks"] = s.rate_limited_ticks;
  j["hc_samples"] = {{"accepted", s.counters.accepted}, {"anchored", s.counters.anchored},
                     {"repeated", s.counters.repeated}, {"late", s.counters.late},
                     {"invalid", s.counters.invalid}, {"clutch_open", s.counters.clutch_open}};
  j["dropped_backlog_mm"] = MToMm(s.counters.dropped_backlog_m);
  return j;
}

namespace {
void Append(std::string& out, const char* fmt, double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, fmt, v);
  out += buf;
}
}  // namespace

std::string SetPointsCsv(const TransferTrace& tr, int decimate) {
  std::string out =
      "time_s,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg,vx_mm_s,vy_mm_s,vz_mm_s,speed_mm_s,angular_speed_deg_s,"
      "ax_mm_s2,ay_mm_s2,az_mm_s2,accel_mm_s2\n";
  out.reserve(tr.t.size() / decimate * 160);
  for (std::size_t k = 0; k < tr.t.size(); k += decimate) {
    Append(out, "%.5f", tr.t[k]);
    for (int i = 0; i < 3; ++i) Append(out, ",%.6f", MToMm(tr.displacement[k][i]));
    for (int i = 3; i < 6; ++i) Append(out, ",%.6f", RadToDeg(tr.displacement[k][i]));
    for (int i = 0; i < 3; ++i) Append(out, ",%.5f", MToMm(tr.velocity[k][i]));
    Append(out, ",%.5f", MToMm(tr.velocity[k].head<3>().norm()));
    Append(out, ",%.5f", RadToDeg(tr.velocity[k].tail<3>().norm()));
    for (int i = 0; i < 3; ++i) Append(out, ",%.4f", MToMm(tr.acceleration[k][i]));
    Append(out, ",%.4f", MToMm(tr.acceleration[k].head<3>().norm()));
    out += '\n';
  }
  return out;
}

std::string JointsCsv(const TransferTrace& tr, int decimate) {
  std::string out = "time_s,theta1_deg,theta2_deg,theta3_deg,d1_mm,d2_mm,d3_mm,theta1_dot_deg_s,theta2_dot_deg_s,"
                    "theta3_dot_deg_s,d1_dot_mm_s,d2_dot_mm_s,d3_dot_mm_s,steps1,steps2,steps3,steps4,steps5,steps6\n";
  for (std::size_t k = 0; k < tr.q.size(); k += decimate) {
    Append(out, "%.5f", tr.t[k]);
    for (int i = 0; i < 3; ++i) Append(out, ",%.7f", RadToDeg(tr.q[k][i]));
    for (int i = 3; i < 6; ++i) Append(out, ",%.6f", MToMm(tr.q[k][i]));
    for (int i = 0; i < 3; ++i) Append(out, ",%.6f", RadToDeg(tr.q_dot[k][i]));
    for (int i = 3; i < 6; ++i) Append(out, ",%.6f", MToMm(tr.q_dot[k][i]));
    for (int i = 0; i < 6; ++i) {
      out += ',';
      out += std::to_string(tr.steps[k][i]);
    }
    out += '\n';
  }
  return out;
}

std::string PulsesCsv(const TransferTrace& tr) {
  std::string out = "time_s,motor,direction\n";
  out.reserve(tr.events.size() * 24);
  for (const auto& e : tr.events) {
    Append(out, "%.7f", e.time_s);
    out += ',';
    out += std::to_string(e.motor + 1);
    out += e.direction > 0 ? ",1\n" : ",-1\n";
  }
  return out;
}

std::string SlowTraceCsv(const TransferTrace& tr) {
  std::string out = "time_s,hc_x_mm,hc_y_mm,hc_z_mm,hc_speed_mm_s,scale_linear,scale_angular,goal_x_mm,goal_y_mm,"
                    "goal_z_mm\n";
  for (std::size_t k = 0; k < tr.t_slow.size(); ++k) {
    Append(out, "%.4f", tr.t_slow[k]);
    for (int i = 0; i < 3; ++i) Append(out, ",%.5f", tr.hc_view[k][i]);
    Append(out, ",%.4f", MToMm(tr.hc_speed[k]));
    Append(out, ",%.5f", tr.scale_linear[k]);
    Append(out, ",%.5f", tr.scale_angular[k]);
    for (int i = 0; i < 3; ++i) Append(out, ",%.5f", MToMm(tr.goal[k][i]));
    out += '\n';
  }
  return out;
}

std::string HcRecordsCsv(const transfer::HcTrajectory& hc) {
  std::string out = "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,clutch,arrival_s\n";
  std::vector<HcRecord> by_time = hc.records;  // the file format is in time order; arrival_s keeps the delivery
  std::stable_sort(by_time.begin(), by_time.end(),
                   [](const HcRecord& a, const HcRecord& b) { return a.time_s < b.time_s; });
  for (const HcRecord& r : by_time) {
    Append(out, "%.4f", r.time_s);
    for (int i = 0; i < 6; ++i) Append(out, ",%.6f", r.pose_mm_deg[i]);
    out += r.clutch ? ",1" : ",0";
    Append(out, ",%.4f", r.arrival_s);
    out += '\n';
  }
  return out;
}

}  // namespace robossis::teleop
