#include "src/teleop/leader_config.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "src/core/config.h"
#include "src/core/units.h"

namespace robossis::teleop {

const char* ToString(FeedbackMode mode) {
  return mode == FeedbackMode::kBilateral ? "bilateral" : "walls";
}

FeedbackMode ParseFeedbackMode(const char* where, const std::string& value) {
  if (value == "walls") return FeedbackMode::kWalls;
  if (value == "bilateral") return FeedbackMode::kBilateral;
  throw std::invalid_argument(std::string(where) + " is '" + value + "'; expected walls or bilateral");
}

void LeaderFeedbackConfig::Validate() const {
  if (!(std::isfinite(gain) && gain >= 0 && gain <= 1)) {
    throw std::invalid_argument("feedback.gain: expected 0 <= G <= 1, got " + std::to_string(gain));
  }
  if (!(std::isfinite(max_force_n) && max_force_n > 0) || !(std::isfinite(max_torque_nm) && max_torque_nm > 0)) {
    throw std::invalid_argument("feedback: the force and torque caps must be finite and positive");
  }
  passivity.Validate();
  let_go.Validate();
}

void LeaderConfig::Validate() const {
  feedback.Validate();
  if (!(rate_hz >= 100 && rate_hz <= 10000)) {
    throw std::invalid_argument("rate_hz: expected 100–10000 Hz, got " + std::to_string(rate_hz));
  }
  if (!(device.max_force_n > 0) || !(device.max_torque_nm > 0) || !(device.max_gripper_force_n >= 0) ||
      !(device.stale_after_s > 0)) {
    throw std::invalid_argument("device: limits and stale_after_s must be positive");
  }
  if (boundary_bisection_steps < 1 || boundary_bisection_steps > 40) {
    throw std::invalid_argument("setpoint.boundary_bisection_steps: expected 1–40");
  }
  if (!(std::isfinite(max_linear_accel_m_s2) && max_linear_accel_m_s2 > 0) ||
      !(std::isfinite(max_angular_accel_rad_s2) && max_angular_accel_rad_s2 > 0)) {
    throw std::invalid_argument("the follower's acceleration caps must be finite and positive");
  }
  if (!(max_joint_speed.array() > 0).all()) {
    throw std::invalid_argument("the follower's motors' top speeds must be positive");
  }
  if (!(motor_speed_share >= 0.1 && motor_speed_share <= 1.0)) {
    throw std::invalid_argument("setpoint.motor_speed_share: expected 0.1–1");
  }
  if (!(follower_status_timeout_s > 0 && follower_status_timeout_s <= 10)) {
    throw std::invalid_argument("setpoint.follower_status_timeout_ms: expected 0 < T <= 10000 ms");
  }
  if (record_queue_capacity < 16) throw std::invalid_argument("recorder.queue_capacity: expected at least 16");
}

LeaderConfig LeaderConfig::FromYaml(const std::filesystem::path& file) {
  return FromConfig(ConfigNode::Load(file));
}

LeaderConfig LeaderConfig::FromConfig(const ConfigNode& root) {
  LeaderConfig c;
  c.rate_hz = root.PositiveNumber("rate_hz");
  const ConfigNode device = root.Child("device");
  c.device.max_force_n = device.PositiveNumber("max_force_n");
  c.device.max_torque_nm = device.PositiveNumber("max_torque_nm");
  c.device.max_gripper_force_n = device.NumberInRange("max_gripper_force_n", 0.0, 100.0);
  c.device.stale_after_s = device.PositiveNumber("stale_after_s");
  const ConfigNode setpoint = root.Child("setpoint");
  c.boundary_bisection_steps = setpoint.Integer("boundary_bisection_steps");
  c.follower_status_timeout_s = 1e-3 * setpoint.PositiveNumber("follower_status_timeout_ms");
  c.motor_speed_share = setpoint.NumberInRange("motor_speed_share", 0.1, 1.0);
  c.guard.Validate();
  const int capacity = root.Child("recorder").Integer("queue_capacity");
  if (capacity < 16) root.Fail("recorder.queue_capacity", "expected an integer >= 16");
  c.record_queue_capacity = static_cast<std::size_t>(capacity);
  const ConfigNode sim = root.Child("sim_script");
  c.sim_script.sim_radius_m = MmToM(sim.NumberInRange("radius_mm", 0.0, 200.0));
  c.sim_script.sim_frequency_hz = sim.PositiveNumber("frequency_hz");
  c.sim_script.sim_yaw_amplitude_rad = DegToRad(sim.NumberInRange("yaw_amplitude_deg", 0.0, 90.0));
  const ConfigNode feedback = root.Child("feedback");
  c.feedback.mode = ParseFeedbackMode("feedback.mode", feedback.String("mode"));
  c.feedback.gain = feedback.NumberInRange("gain", 0.0, 1.0);
  c.feedback.passivity.scheme = ParseFeedbackPassivityScheme("feedback.passivity", feedback.String("passivity"));
  c.feedback.passivity.max_damping_n_s_per_m = feedback.NumberInRange("max_damping_n_s_per_m", 0.0, 1000.0);
  c.feedback.passivity.max_damping_nm_s_per_rad = feedback.NumberInRange("max_damping_nm_s_per_rad", 0.0, 10.0);
  c.feedback.passivity.release_s = feedback.NumberInRange("release_s", 0.0, 10.0);
  c.feedback.passivity.active_tolerance_n = feedback.PositiveNumber("active_tolerance_n");
  c.feedback.passivity.active_tolerance_nm = feedback.PositiveNumber("active_tolerance_nm");
  const ConfigNode taper = feedback.Child("taper");
  c.feedback.passivity.reserve_j = taper.NumberInRange("reserve_j", 0.0, 10.0);
  c.feedback.passivity.rise_s = taper.NumberInRange("rise_s", 0.0, 10.0);
  c.feedback.passivity.rest_damping_n_s_per_m = taper.NumberInRange("rest_damping_n_s_per_m", 0.0, 1000.0);
  c.feedback.passivity.rest_hold_s = taper.NumberInRange("rest_hold_s", 0.0, 10.0);
  c.feedback.passivity.still_m_s = MmToM(taper.PositiveNumber("still_mm_s"));
  c.feedback.passivity.still_rad_s = DegToRad(taper.PositiveNumber("still_deg_s"));
  c.feedback.detect_let_go = feedback.Bool("detect_let_go");
  const ConfigNode let_go = feedback.Child("let_go");
  c.feedback.let_go.device_mass_kg = let_go.PositiveNumber("device_mass_kg");
  c.feedback.let_go.mass_ratio = let_go.PositiveNumber("mass_ratio");
  c.feedback.let_go.min_force_n = let_go.PositiveNumber("min_force_n");
  c.feedback.let_go.confirm_s = let_go.PositiveNumber("confirm_s");
  c.feedback.let_go.rest_damping_n_s_per_m = let_go.PositiveNumber("rest_damping_n_s_per_m");
  c.feedback.let_go.max_damper_share = let_go.PositiveNumber("max_damper_share");
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  try {
    c.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(root.file() + ": " + e.what());
  }
  return c;
}

}  // namespace robossis::teleop
