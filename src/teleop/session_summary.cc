#include "src/teleop/session_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "robot/actuation/actuator.h"
#include "src/core/units.h"

namespace robossis::teleop {

namespace {

Eigen::Isometry3d Pose(const std::array<double, 3>& p, const std::array<double, 4>& q) { return PoseFromArrays(p, q); }

template <std::size_t N>
bool Finite(const std::array<double, N>& a) {
  return std::all_of(a.begin(), a.end(), [](double v) { return std::isfinite(v); });
}

// A value in the fixed format `fmt` when it is of a plausible size, else in %.17g: a huge value (a corrupt log's
// 1e300) stays one short cell instead of hundreds of digits (which snprintf would also cut at the buffer).
constexpr double kMaxFixedCellMagnitude = 1e9;

void Append(std::string& out, const char* fmt, double v) {
  char buf[48];
  if (std::isfinite(v) && std::fabs(v) >= kMaxFixedCellMagnitude) {
    std::snprintf(buf, sizeof buf, "%s%.17g", fmt[0] == ',' ? "," : "", v);
  } else {
    std::snprintf(buf, sizeof buf, fmt, v);
  }
  out += buf;
}

void AppendPose(std::string& out, const Eigen::Isometry3d& X) {
  const Vector6d v = MmDegFromPose(X);
  for (int i = 0; i < 6; ++i) Append(out, ",%.4f", v[i]);
}

double Norm3(const std::array<double, 3>& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

}  // namespace

SummaryOptions SummaryOptionsFromMeta(const nlohmann::json& meta) {
  SummaryOptions o;
  o.leader_rate_hz = meta.at("rate_hz").get<double>();
  o.follower_rate_hz = meta.at("follower_rate_hz").get<double>();
  // The caps, for the delay estimate; absent from the logs written before they were recorded (then unknown).
  if (meta.contains("max_linear_speed_m_s")) o.max_linear_speed_m_s = meta.at("max_linear_speed_m_s").get<double>();
  if (meta.contains("max_angular_speed_rad_s")) {
    o.max_angular_speed_rad_s = meta.at("max_angular_speed_rad_s").get<double>();
  }
  // The leader's feedback map, for the shown load against the true one; absent from older logs (then not judged).
  if (meta.contains("feedback_gain")) {
    o.feedback_map_known = true;
    o.feedback_gain = meta.at("feedback_gain").get<double>();
    o.feedback_translation_scale = meta.at("feedback_translation_scale").get<double>();
    const std::vector<double> R = meta.at("feedback_R_FO").get<std::vector<double>>();
    if (R.size() != 9) throw std::runtime_error("feedback_R_FO: expected 9 numbers (row-major)");
    o.feedback_R_FO = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(R.data());
  }
  return o;
}


SessionSummary::SessionSummary(const SummaryOptions& options) : options_(options) {
  leader_decimation_ = std::max(1, static_cast<int>(std::lround(options.leader_rate_hz / options.leader_csv_rate_hz)));
  follower_decimation_ =
      std::max(1, static_cast<int>(std::lround(options.follower_rate_hz / options.follower_csv_rate_hz)));
  window_.resize(100);
  leader_csv_ =
      "t_s,hand_x_mm,hand_y_mm,hand_z_mm,hand_roll_deg,hand_pitch_deg,hand_yaw_deg,fx_n,fy_n,fz_n,tx_nm,ty_nm,tz_nm,"
      "haptic_status,goal_x_mm,goal_y_mm,goal_z_mm,goal_roll_deg,goal_pitch_deg,goal_yaw_deg,sent_x_mm,sent_y_mm,"
      "sent_z_mm,sent_roll_deg,sent_pitch_deg,sent_yaw_deg,stopped_at_boundary,leader_state,scale_linear,"
      "hand_speed_mm_s\n";
  follower_csv_ =
      "t_s,cmd_x_mm,cmd_y_mm,cmd_z_mm,cmd_roll_deg,cmd_pitch_deg,cmd_yaw_deg,meas_x_mm,meas_y_mm,meas_z_mm,"
      "meas_roll_deg,meas_pitch_deg,meas_yaw_deg,state,min_limit_margin_si,holding\n";
}

double SessionSummary::ShownAgainstTrueForceRms() const {
  // Each shown tick against the follower's true force at the time of the status it showed (the link's delay
  // removed: the status's stamp is the follower's clock), mapped as the leader maps the estimate.
  constexpr double kMatchS = 1.5e-3;  // [assumed] the true force is kept once a millisecond, the status rate
  const Eigen::Matrix3d M =
      options_.feedback_gain * options_.feedback_translation_scale * options_.feedback_R_FO.transpose();
  double sum = 0;
  std::size_t n = 0;
  for (const auto& [stamp_s, shown] : shown_at_stamp_) {
    auto it = std::upper_bound(true_force_.begin(), true_force_.end(), stamp_s + 1e-9,
                               [](double t, const auto& sample) { return t < sample.first; });
    if (it == true_force_.begin()) continue;
    --it;
    if (stamp_s - it->first > kMatchS) continue;
    sum += (shown - M * it->second).squaredNorm();
    ++n;
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : std::numeric_limits<double>::quiet_NaN();
}

void SessionSummary::AddLeader(const LeaderTickRecord& r) {
  if (leader_last_ns_ >= 0) ++leader_periods_us_[(r.t_ns - leader_last_ns_) / 1000];
  leader_last_ns_ = r.t_ns;
  if (!Finite(r.f_O) || !Finite(r.tau_O) || !Finite(r.p_sent) || !Finite(r.q_sent)) ++nonfinite_;
  max_force_n_ = std::max(max_force_n_, Norm3(r.f_O));
  max_torque_nm_ = std::max(max_torque_nm_, Norm3(r.tau_O));
  max_hand_speed_m_s_ = std::max(max_hand_speed_m_s_, Norm3(r.v_O));
  feedback_energy_j_ = r.feedback_energy_out_j - r.feedback_energy_in_j;
  feedback_in_j_ = r.feedback_energy_in_j;
  max_feedback_energy_j_ = std::max(max_feedback_energy_j_, feedback_energy_j_);
  max_feedback_force_n_ = std::max(max_feedback_force_n_, std::hypot(r.feedback_O[0], r.feedback_O[1], r.feedback_O[2]));
  if (r.feedback_shown) {
    ++feedback_ticks_;
    double e2 = 0;
    for (int i = 0; i < 3; ++i) e2 += (r.feedback_O[i] - r.feedback_wanted_O[i]) * (r.feedback_O[i] - r.feedback_wanted_O[i]);
    feedback_error_sq_sum_ += e2;
    if (options_.feedback_map_known && shown_at_stamp_.size() < kMaxDelaySamples) {
      shown_at_stamp_.emplace_back(1e-9 * static_cast<double>(r.follower_stamp_ns),
                                   Eigen::Vector3d(r.feedback_O[0], r.feedback_O[1], r.feedback_O[2]));
    }
    if (r.passivity_active) ++passivity_active_ticks_;
    if (r.taper_active) ++taper_active_ticks_;
    min_passivity_observed_j_ = std::min(min_passivity_observed_j_, r.passivity_observed_j);
  }
  if (r.let_go && let_go_detected_s_ < 0) let_go_detected_s_ = 1e-9 * static_cast<double>(r.t_ns);
  if (r.sent_this_tick && r.stopped_at_boundary) ++stopped_at_boundary_;
  if (r.sent_this_tick && t_sent_.size() < kMaxDelaySamples) {
    t_sent_.push_back(1e-9 * static_cast<double>(r.t_ns));
    ideal_.push_back(Eigen::Map<const Vector6d>(r.ideal_disp.data()));
    transfer_.push_back(Eigen::Map<const Vector6d>(r.transfer_disp.data()));
    capped_.push_back(static_cast<std::uint8_t>((r.scale_linear < 1 ? kCappedLinear : 0) |
                                                (r.scale_angular < 1 ? kCappedAngular : 0) |
                                                HeldBack(Pose(r.p_goal, r.q_goal), Pose(r.p_sent, r.q_sent))));
  }
  if (r.leader_state != leader_state_) {
    leader_transitions_.push_back({{"t_s", 1e-9 * static_cast<double>(r.t_ns)},
                                   {"to", ToString(static_cast<LeaderState>(r.leader_state))}});
    leader_state_ = r.leader_state;
  }
  if (leader_ticks_ % static_cast<std::uint64_t>(leader_decimation_) == 0) {
    Append(leader_csv_, "%.4f", 1e-9 * static_cast<double>(r.t_ns));
    AppendPose(leader_csv_, Pose(r.p_OH, r.q_OH));
    for (double v : r.f_O) Append(leader_csv_, ",%.4f", v);
    for (double v : r.tau_O) Append(leader_csv_, ",%.5f", v);
    leader_csv_ += ',';
    leader_csv_ += haptics::ToString(static_cast<haptics::HapticStatus>(r.haptic_status));
    AppendPose(leader_csv_, Pose(r.p_goal, r.q_goal));
    AppendPose(leader_csv_, Pose(r.p_sent, r.q_sent));
    leader_csv_ += r.stopped_at_boundary ? ",1," : ",0,";
    leader_csv_ += ToString(static_cast<LeaderState>(r.leader_state));
    Append(leader_csv_, ",%.4f", r.scale_linear);
    Append(leader_csv_, ",%.3f", MToMm(Norm3(r.v_O)));
    leader_csv_ += '\n';
  }
  ++leader_ticks_;
}

void SessionSummary::AddFollower(const FollowerTickRecord& r) {
  verdict_.AddFollower(r);
  // The drift (kDriftPathS): the path of the set-points taken while enabled (started over whenever the follower
  // stops following), against the measured position.
  if (r.state != OperatingState::kEnabled) {
    setpoint_path_.clear();
  } else if (r.setpoint_sequence != path_sequence_ || setpoint_path_.empty()) {
    path_sequence_ = r.setpoint_sequence;
    setpoint_path_.emplace_back(r.time_s, Eigen::Vector3d(r.setpoint_p_FM[0], r.setpoint_p_FM[1], r.setpoint_p_FM[2]));
    while (setpoint_path_.front().first < r.time_s - kDriftPathS) setpoint_path_.pop_front();
  }
  last_meas_p_ = Eigen::Vector3d(r.meas_p_FM[0], r.meas_p_FM[1], r.meas_p_FM[2]);
  // The largest once the path spans its whole window (not while the follower first catches up after enabling).
  if (!setpoint_path_.empty() && r.time_s - setpoint_path_.front().first >= kDriftPathS - kDriftEveryS &&
      r.time_s >= next_drift_s_) {
    max_position_drift_m_ = std::max(max_position_drift_m_, DriftFrom(last_meas_p_));
    next_drift_s_ = r.time_s + kDriftEveryS;
  }
  // The true force once a millisecond (the status rate), for the shown load against it.
  if (r.true_load_known && true_force_.size() < kMaxDelaySamples &&
      (true_force_.empty() || r.time_s >= true_force_.back().first + 1e-3 - 1e-9)) {
    true_force_.emplace_back(r.time_s, Eigen::Vector3d(r.true_wrench_F[0], r.true_wrench_F[1], r.true_wrench_F[2]));
  }
  // The network form's follower half: what the robot gave the environment beyond the hand's input as received.
  if (r.port_budgeted) {
    follower_port_excess_max_j_ = std::max(follower_port_excess_max_j_, r.port_energy_out_j - r.port_budget_j);
  }
  if (follower_last_s_ >= 0) ++follower_periods_us_[std::llround((r.time_s - follower_last_s_) * 1e6)];
  follower_last_s_ = r.time_s;
  if (!r.meas_feasible) ++limit_violations_;
  if (r.actuation_status == static_cast<std::uint8_t>(actuation::ActuationStatus::kRateLimit)) ++rate_limited_ticks_;
  if (r.took_setpoint && r.setpoint_verdict != SetPointVerdict::kAccepted) {
    const auto v = static_cast<std::size_t>(r.setpoint_verdict);
    if (v < rejected_by_verdict_.size()) ++rejected_by_verdict_[v];
  }
  min_margin_ = std::min(min_margin_, r.meas_min_margin);
  if (!Finite(r.cmd_p_FM) || !Finite(r.cmd_q_FM) || !Finite(r.cmd_joints)) ++nonfinite_;
  const Eigen::Isometry3d meas = Pose(r.meas_p_FM, r.meas_q_FM);
  // Speeds over 100 ticks (10 ms at 10 kHz): finite differences of the measured pose over the measurements' own
  // times. Not over the ticks' times: the Bullet back end measures at its own 1 kHz physics step and catches up in
  // bursts after a late tick, so 100 ticks can hold 11 steps of motion (1.1 times the true speed; 2 in 1 ms).
  if (follower_ticks_ >= window_.size()) {
    const auto& [t0, X0] = window_[window_next_];
    const double dt = r.meas_time_s - t0;
    if (dt > 0) {
      max_speed_m_s_ = std::max(max_speed_m_s_, (meas.translation() - X0.translation()).norm() / dt);
      max_angular_speed_rad_s_ =
          std::max(max_angular_speed_rad_s_, RotationAngleBetween(meas.linear(), X0.linear()) / dt);
    }
  }
  window_[window_next_] = {r.meas_time_s, meas};
  window_next_ = (window_next_ + 1) % window_.size();
  const int state = static_cast<int>(r.state);
  if (state != follower_state_) {
    follower_transitions_.push_back({{"t_s", r.time_s},
                                     {"from", follower_state_ < 0 ? "start" : ToString(static_cast<OperatingState>(follower_state_))},
                                     {"to", ToString(r.state)},
                                     {"reason", ToString(r.reason)}});
    if (r.reason == FaultReason::kBackEnd) {
      follower_transitions_.back()["back_end_fault"] =
          robot::ToString(static_cast<robot::FollowerFault>(r.back_end_fault));
    }
    follower_state_ = state;
  }
  if (follower_ticks_ % static_cast<std::uint64_t>(follower_decimation_) == 0) {
    Append(follower_csv_, "%.4f", r.time_s);
    AppendPose(follower_csv_, Pose(r.cmd_p_FM, r.cmd_q_FM));
    AppendPose(follower_csv_, meas);
    follower_csv_ += ',';
    follower_csv_ += ToString(r.state);
    Append(follower_csv_, ",%.6f", r.meas_min_margin);
    follower_csv_ += r.holding ? ",1\n" : ",0\n";
  }
  ++follower_ticks_;
}

double SessionSummary::DriftFrom(const Eigen::Vector3d& p) const {
  if (setpoint_path_.empty()) return std::numeric_limits<double>::quiet_NaN();
  double d = (p - setpoint_path_.front().second).norm();
  for (std::size_t i = 1; i < setpoint_path_.size(); ++i) {
    const Eigen::Vector3d& a = setpoint_path_[i - 1].second;
    const Eigen::Vector3d ab = setpoint_path_[i].second - a;
    const double l2 = ab.squaredNorm();
    const double s = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    d = std::min(d, (p - a - s * ab).norm());
  }
  return d;
}

// The hand-to-set-point delay of the motion transfer: the transfer's set-point against the eq. 10–11
// displacement (the hand's motion after the dynamic scaling, before any filter), by the one estimator. Both come
// from the leader's records alone, so a replayed log gives the same figure:
// - segments: MotionTransfer::Rebase (the leader follows the measured robot while the robot does not follow)
//   zeroes both displacements; a zero displacement starts a new segment, and velocities are never differenced
//   across it;
// - the cap: eq. 11 scales the hand down (scale < 1) exactly when it is faster than the cap's headroom; the ideal
//   speed is then held at the cap and the set-point's is the clipped one, which no single lag aligns with the
//   hand. Those ticks are not judged, nor a set-point at its cap (SummaryOptions' caps) or within kCapSettle_s after
//   the cap bound (still catching up): the lag is measured where the reference speed is below the cap, where the
//   set-point can follow it;
// - the leader's bounds: where the set-point sent was held back from the transfer's (HeldBack: a wall, the
//   acceleration caps, the motors' top speeds), the robot is not sent the transfer's set-point, so those ticks
//   count as capped too. Where it is judged, the transfer's lag is therefore the hand's lag to the set-point sent.
DelayEstimate SessionSummary::HandToSetPointDelay() const {
  const std::vector<int> segment = RebaseSegments(ideal_, transfer_);
  DelaySearch search;
  search.max_linear_speed_m_s = options_.max_linear_speed_m_s;
  search.max_angular_speed_rad_s = options_.max_angular_speed_rad_s;
  return EstimateDelay({.t_s = t_sent_, .x = ideal_, .segment = segment, .capped = capped_},
                       {.t_s = t_sent_, .x = transfer_, .segment = segment, .capped = capped_}, search);
}

nlohmann::ordered_json SessionSummary::Summary() const {
  nlohmann::ordered_json j;
  WriteRunVerdict(Verdict(), j);
  j["leader_ticks"] = leader_ticks_;
  j["follower_ticks"] = follower_ticks_;
  j["leader_overruns"] = end_.leader_overruns;
  j["follower_overruns"] = end_.follower_overruns;
  j["leader_period_jitter_us_p99"] = end_.leader_period_jitter_us_p99;
  j["follower_period_jitter_us_p99"] = end_.follower_period_jitter_us_p99;
  j["max_force_n"] = max_force_n_;
  j["max_torque_nm"] = max_torque_nm_;
  j["nonfinite_outputs"] = nonfinite_;
  j["follower_limit_violations"] = limit_violations_;
  // The share of the follower's ticks in which a motor's top step rate shortened the step (the robot fell behind
  // its set-points there): near 0 while the set-points keep within the motors' speeds.
  j["follower_rate_limited_pct"] =
      follower_ticks_ > 0 ? 100.0 * static_cast<double>(rate_limited_ticks_) / static_cast<double>(follower_ticks_) : 0.0;
  j["max_follower_speed_mm_s"] = MToMm(max_speed_m_s_);
  j["max_follower_angular_speed_deg_s"] = RadToDeg(max_angular_speed_rad_s_);
  // null unless the estimate is ok (the status says why: cap_binds, too_few_samples, ...), never a 0 that reads as
  // "no delay".
  const DelayEstimate delay = HandToSetPointDelay();
  j["hand_to_setpoint_delay_ms"] = delay.ok() ? nlohmann::ordered_json(1e3 * delay.delay_s) : nlohmann::ordered_json();
  j["hand_to_setpoint_delay_status"] = ToString(delay.status);
  j["hand_to_setpoint_delay_judged_fraction"] = delay.judged_fraction();  // of the set-points sent
  j["hand_to_setpoint_delay_correlation"] = delay.correlation;  // of the velocities at that lag (the quality)
  j["watchdog_holds"] = end_.watchdog_holds;
  // Bilateral feedback: the energy the feedback port gave the hand minus what it took (<= 0: passive), its largest
  // value at any tick, the largest load force shown, the shown force against the follower's true load where the
  // simulation says it (gain and map applied, at the time of the status shown: the link's delay removed; the
  // estimate's error, the caps and the passivity controller left in; null where not known) and against its estimate
  // as received, the follower's drift (kDriftPathS: its distance from the path of its set-points, at the end and the
  // largest over the run; null when it never followed), and the shares of the shown ticks in which the passivity
  // controller (and its taper alone) changed the shown wrench beyond its tolerance (active_tolerance_n, _nm).
  j["feedback_energy_j"] = feedback_energy_j_;
  j["feedback_energy_max_j"] = max_feedback_energy_j_;
  j["feedback_energy_in_j"] = feedback_in_j_;
  j["max_feedback_force_n"] = max_feedback_force_n_;
  const double vs_truth = ShownAgainstTrueForceRms();
  j["feedback_force_error_n_rms"] = std::isfinite(vs_truth) ? nlohmann::ordered_json(vs_truth) : nlohmann::ordered_json();
  j["feedback_force_error_vs_estimate_n_rms"] =
      feedback_ticks_ ? std::sqrt(feedback_error_sq_sum_ / static_cast<double>(feedback_ticks_)) : 0.0;
  const double drift = DriftFrom(last_meas_p_);
  j["position_drift_mm"] = std::isfinite(drift) ? nlohmann::ordered_json(MToMm(drift)) : nlohmann::ordered_json();
  j["position_drift_max_mm"] = MToMm(max_position_drift_m_);
  j["tdpa_active_fraction"] =
      feedback_ticks_ ? static_cast<double>(passivity_active_ticks_) / static_cast<double>(feedback_ticks_) : 0.0;
  j["taper_active_fraction"] =
      feedback_ticks_ ? static_cast<double>(taper_active_ticks_) / static_cast<double>(feedback_ticks_) : 0.0;
  j["passivity_observer_min_j"] = min_passivity_observed_j_;
  j["let_go_detected_s"] = let_go_detected_s_;  // when the let-go detector first believed a let-go (-1: never)
  // The follower's port under the network form's bound: its output beyond the hand's input (divided by the gain) as
  // received, largest at any tick (<= 0 but for the wrench's one-tick lag; 0 when no set-point carried the bound).
  j["follower_port_excess_max_j"] = follower_port_excess_max_j_;
  j["follower_transitions"] = follower_transitions_;
  j["leader_transitions"] = leader_transitions_;
  j["complete"] = has_end_;  // false: the log ends without its end record (the run did not finish)
  j["elapsed_s"] = end_.elapsed_s;
  j["leader_period_jitter_us_max"] = end_.leader_period_jitter_us_max;
  j["follower_period_jitter_us_max"] = end_.follower_period_jitter_us_max;
  j["leader_wake_latency_us_p99"] = end_.leader_wake_latency_us_p99;
  j["follower_wake_latency_us_p99"] = end_.follower_wake_latency_us_p99;
  j["leader_overrun_rate"] = end_.leader_loop_ticks ? static_cast<double>(end_.leader_overruns) /
                                                          static_cast<double>(end_.leader_loop_ticks) : 0.0;
  j["follower_overrun_rate"] = end_.follower_loop_ticks ? static_cast<double>(end_.follower_overruns) /
                                                              static_cast<double>(end_.follower_loop_ticks) : 0.0;
  // Overruns by cause (rt::OverrunCause), per loop: late_wake = the loop woke too late (scheduling), long_tick =
  // the tick's own duration passed its period. The simulated robot's own loop (plant) where the back end runs one.
  j["leader_overruns_late_wake"] = end_.leader_overruns_late_wake;
  j["leader_overruns_long_tick"] = end_.leader_overruns_long_tick;
  j["follower_overruns_late_wake"] = end_.follower_overruns_late_wake;
  j["follower_overruns_long_tick"] = end_.follower_overruns_long_tick;
  j["plant_ticks"] = end_.plant_loop_ticks;
  j["plant_overruns"] = end_.plant_overruns;
  j["plant_overruns_late_wake"] = end_.plant_overruns_late_wake;
  j["plant_overruns_long_tick"] = end_.plant_overruns_long_tick;
  j["setpoints_accepted"] = end_.setpoints_accepted;
  j["setpoints_rejected"] = end_.setpoints_rejected;
  nlohmann::ordered_json by_verdict = nlohmann::ordered_json::object();
  for (int v = 1; v < kNumSetPointVerdicts; ++v) {
    by_verdict[ToString(static_cast<SetPointVerdict>(v))] = rejected_by_verdict_[static_cast<std::size_t>(v)];
  }
  j["setpoints_rejected_by_reason"] = by_verdict;  // from the records (as the off-line chain's summary names it)
  j["setpoints_stopped_at_boundary"] = stopped_at_boundary_;
  j["setpoints_ik_rejected"] = end_.ik_rejected;
  j["device_failures"] = end_.device_failures;
  j["records_dropped"] = end_.leader_records_dropped + end_.follower_records_dropped;
  j["max_hand_speed_mm_s"] = MToMm(max_hand_speed_m_s_);
  j["min_follower_limit_margin_si"] = follower_ticks_ ? min_margin_ : 0.0;
  return j;
}

void SessionSummary::MoveCsvTo(std::string& leader, std::string& follower) {
  leader += leader_csv_;
  follower += follower_csv_;
  leader_csv_.clear();
  follower_csv_.clear();
}

std::string SessionSummary::PeriodsCsv() const {
  std::string out = "loop,period_us,count\n";
  for (const auto& [us, n] : leader_periods_us_) out += "leader," + std::to_string(us) + "," + std::to_string(n) + "\n";
  for (const auto& [us, n] : follower_periods_us_) {
    out += "follower," + std::to_string(us) + "," + std::to_string(n) + "\n";
  }
  return out;
}

}  // namespace robossis::teleop
