#include "src/teleop/flight_recorder.h"

#include <chrono>
#include <exception>

namespace robossis::teleop {

StreamSpec LeaderStreamSpec() {
  using R = LeaderTickRecord;
  StreamSpec s;
  s.id = kLeaderStream;
  s.name = "leader";
  s.record_size = sizeof(R);
  s.fields = {
      ROBOSSIS_LOG_FIELD(R, t_ns, "ns"),          ROBOSSIS_LOG_FIELD(R, sample_ns, "ns"),
      ROBOSSIS_LOG_FIELD(R, tick, ""),            ROBOSSIS_LOG_FIELD(R, p_OH, "m"),
      ROBOSSIS_LOG_FIELD(R, q_OH, ""),            ROBOSSIS_LOG_FIELD(R, v_O, "m/s"),
      ROBOSSIS_LOG_FIELD(R, w_O, "rad/s"),        ROBOSSIS_LOG_FIELD(R, f_O, "N"),
      ROBOSSIS_LOG_FIELD(R, tau_O, "N.m"),        ROBOSSIS_LOG_FIELD(R, p_goal, "m"),
      ROBOSSIS_LOG_FIELD(R, q_goal, ""),          ROBOSSIS_LOG_FIELD(R, p_sent, "m"),
      ROBOSSIS_LOG_FIELD(R, q_sent, ""),          ROBOSSIS_LOG_FIELD(R, p_follower, "m"),
      ROBOSSIS_LOG_FIELD(R, q_follower, ""),      ROBOSSIS_LOG_FIELD(R, ideal_disp, "m|rad"),
      ROBOSSIS_LOG_FIELD(R, transfer_disp, "m|rad"),  ROBOSSIS_LOG_FIELD(R, scale_linear, ""),
      ROBOSSIS_LOG_FIELD(R, scale_angular, ""),   ROBOSSIS_LOG_FIELD(R, hc_speed_m_s, "m/s"),
      ROBOSSIS_LOG_FIELD(R, sequence, ""),        ROBOSSIS_LOG_FIELD(R, buttons, ""),
      ROBOSSIS_LOG_FIELD(R, device_status, ""),   ROBOSSIS_LOG_FIELD(R, haptic_status, ""),
      ROBOSSIS_LOG_FIELD(R, leader_state, ""),    ROBOSSIS_LOG_FIELD(R, follower_state, ""),
      ROBOSSIS_LOG_FIELD(R, flags, ""),           ROBOSSIS_LOG_FIELD(R, sent_this_tick, ""),
      ROBOSSIS_LOG_FIELD(R, stopped_at_boundary, ""), ROBOSSIS_LOG_FIELD(R, force_zeroed, ""),
      ROBOSSIS_LOG_FIELD(R, follower_wrench_F, "N|N.m"), ROBOSSIS_LOG_FIELD(R, feedback_wanted_O, "N|N.m"),
      ROBOSSIS_LOG_FIELD(R, feedback_O, "N|N.m"),        ROBOSSIS_LOG_FIELD(R, feedback_shown, ""),
      ROBOSSIS_LOG_FIELD(R, feedback_energy_in_j, "J"),  ROBOSSIS_LOG_FIELD(R, feedback_energy_out_j, "J"),
      ROBOSSIS_LOG_FIELD(R, passivity_observed_j, "J"),  ROBOSSIS_LOG_FIELD(R, passivity_active, ""),
      ROBOSSIS_LOG_FIELD(R, taper_active, ""),
      ROBOSSIS_LOG_FIELD(R, let_go, ""),                 ROBOSSIS_LOG_FIELD(R, follower_stamp_ns, "ns"),
  };
  return s;
}

StreamSpec FollowerStreamSpec() {
  using R = FollowerTickRecord;
  StreamSpec s;
  s.id = kFollowerStream;
  s.name = "follower";
  s.record_size = sizeof(R);
  s.fields = {
      ROBOSSIS_LOG_FIELD(R, tick, ""),                 ROBOSSIS_LOG_FIELD(R, time_s, "s"),
      ROBOSSIS_LOG_FIELD(R, setpoint_sequence, ""),    ROBOSSIS_LOG_FIELD(R, setpoint_p_FM, "m"),
      ROBOSSIS_LOG_FIELD(R, setpoint_q_FM, ""),        ROBOSSIS_LOG_FIELD(R, setpoint_twist_F, "m/s|rad/s"),
      ROBOSSIS_LOG_FIELD(R, setpoint_flags, ""),       ROBOSSIS_LOG_FIELD(R, cmd_p_FM, "m"),
      ROBOSSIS_LOG_FIELD(R, cmd_q_FM, ""),             ROBOSSIS_LOG_FIELD(R, cmd_twist_F, "m/s|rad/s"),
      ROBOSSIS_LOG_FIELD(R, cmd_joints, "rad|m"),      ROBOSSIS_LOG_FIELD(R, meas_time_s, "s"),
      ROBOSSIS_LOG_FIELD(R, meas_p_FM, "m"),
      ROBOSSIS_LOG_FIELD(R, meas_q_FM, ""),            ROBOSSIS_LOG_FIELD(R, meas_joints, "rad|m"),
      ROBOSSIS_LOG_FIELD(R, effort, "N.m|N"),          ROBOSSIS_LOG_FIELD(R, meas_min_margin, "m|rad"),
      ROBOSSIS_LOG_FIELD(R, state, ""),                ROBOSSIS_LOG_FIELD(R, reason, ""),
      ROBOSSIS_LOG_FIELD(R, back_end_fault, ""),       ROBOSSIS_LOG_FIELD(R, took_setpoint, ""),
      ROBOSSIS_LOG_FIELD(R, setpoint_verdict, ""),     ROBOSSIS_LOG_FIELD(R, guard_status, ""),
      ROBOSSIS_LOG_FIELD(R, actuation_status, ""),     ROBOSSIS_LOG_FIELD(R, holding, ""),
      ROBOSSIS_LOG_FIELD(R, meas_feasible, ""),        ROBOSSIS_LOG_FIELD(R, setpoint_stamp_ns, "ns"),
      ROBOSSIS_LOG_FIELD(R, command_time_s, "s"),
      ROBOSSIS_LOG_FIELD(R, wrench_F, "N|N.m"),        ROBOSSIS_LOG_FIELD(R, port_energy_in_j, "J"),
      ROBOSSIS_LOG_FIELD(R, port_energy_out_j, "J"),
      ROBOSSIS_LOG_FIELD(R, port_budgeted, ""),        ROBOSSIS_LOG_FIELD(R, port_budget_j, "J"),
      ROBOSSIS_LOG_FIELD(R, true_load_known, ""),      ROBOSSIS_LOG_FIELD(R, true_wrench_F, "N|N.m"),
  };
  return s;
}

StreamSpec EndStreamSpec() {
  using R = SessionEndRecord;
  StreamSpec s;
  s.id = kEndStream;
  s.name = "end";
  s.record_size = sizeof(R);
  s.fields = {
      ROBOSSIS_LOG_FIELD(R, elapsed_s, "s"),
      ROBOSSIS_LOG_FIELD(R, leader_loop_ticks, ""),
      ROBOSSIS_LOG_FIELD(R, leader_overruns, ""),
      ROBOSSIS_LOG_FIELD(R, leader_overruns_late_wake, ""),
      ROBOSSIS_LOG_FIELD(R, leader_overruns_long_tick, ""),
      ROBOSSIS_LOG_FIELD(R, leader_period_jitter_us_p99, "us"),
      ROBOSSIS_LOG_FIELD(R, leader_period_jitter_us_max, "us"),
      ROBOSSIS_LOG_FIELD(R, leader_wake_latency_us_p99, "us"),
      ROBOSSIS_LOG_FIELD(R, follower_loop_ticks, ""),
      ROBOSSIS_LOG_FIELD(R, follower_overruns, ""),
      ROBOSSIS_LOG_FIELD(R, follower_overruns_late_wake, ""),
      ROBOSSIS_LOG_FIELD(R, follower_overruns_long_tick, ""),
      ROBOSSIS_LOG_FIELD(R, follower_period_jitter_us_p99, "us"),
      ROBOSSIS_LOG_FIELD(R, follower_period_jitter_us_max, "us"),
      ROBOSSIS_LOG_FIELD(R, follower_wake_latency_us_p99, "us"),
      ROBOSSIS_LOG_FIELD(R, watchdog_holds, ""),
      ROBOSSIS_LOG_FIELD(R, setpoints_accepted, ""),
      ROBOSSIS_LOG_FIELD(R, setpoints_rejected, ""),
      ROBOSSIS_LOG_FIELD(R, leader_records_dropped, ""),
      ROBOSSIS_LOG_FIELD(R, follower_records_dropped, ""),
      ROBOSSIS_LOG_FIELD(R, device_failures, ""),
      ROBOSSIS_LOG_FIELD(R, ik_rejected, ""),
      ROBOSSIS_LOG_FIELD(R, plant_loop_ticks, ""),
      ROBOSSIS_LOG_FIELD(R, plant_overruns, ""),
      ROBOSSIS_LOG_FIELD(R, plant_overruns_late_wake, ""),
      ROBOSSIS_LOG_FIELD(R, plant_overruns_long_tick, ""),
  };
  return s;
}

FlightRecorder::FlightRecorder(SessionLogWriter& log, Drain drain, double flush_period_s, std::atomic<bool>* failed)
    : log_(log), drain_(std::move(drain)), flush_period_s_(flush_period_s), failed_(failed) {}

FlightRecorder::~FlightRecorder() { Stop(); }

void FlightRecorder::Start() {
  stop_.store(false);
  thread_ = std::thread([this] { Run(); });
}

void FlightRecorder::Run() {
  const auto period = std::chrono::duration<double>(flush_period_s_);
  auto next = std::chrono::steady_clock::now();
  try {
    while (!stop_.load(std::memory_order_relaxed)) {
      next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
      std::this_thread::sleep_until(next);
      drain_(log_);
      log_.Flush();
    }
  } catch (const std::exception& e) {
    error_ = e.what();
    if (failed_ != nullptr) failed_->store(true);
  }
}

std::string FlightRecorder::Stop() {
  if (thread_.joinable()) {
    stop_.store(true);
    thread_.join();
    try {
      drain_(log_);
      log_.Flush();
    } catch (const std::exception& e) {
      if (error_.empty()) error_ = e.what();
      if (failed_ != nullptr) failed_->store(true);
    }
  }
  return error_;
}

}  // namespace robossis::teleop
