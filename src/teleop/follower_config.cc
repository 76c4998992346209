#include "src/teleop/follower_config.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "src/core/config.h"
#include "src/core/units.h"

namespace robossis::teleop {

void FollowerConfig::Validate() const {
  setpoint.Validate();
  guard.Validate();
  const auto require = [](bool ok, const char* field, double value, const char* expected) {
    if (!ok) {
      throw std::invalid_argument(std::string("follower config: ") + field + " is " + std::to_string(value) +
                                  "; expected " + expected);
    }
  };
  const FollowerWatchdogConfig& w = watchdog;
  require(std::isfinite(w.hold_after_s) && w.hold_after_s > 0 && w.hold_after_s <= 1.0, "watchdog.hold_after",
          w.hold_after_s, "0 < t <= 1 s");
  require(std::isfinite(w.leader_lost_after_s) && w.leader_lost_after_s >= w.hold_after_s &&
              w.leader_lost_after_s <= 60.0,
          "watchdog.leader_lost_after", w.leader_lost_after_s, "hold_after <= t <= 60 s");
  require(std::isfinite(w.max_extrapolation_s) && w.max_extrapolation_s >= 0 && w.max_extrapolation_s <= 0.1,
          "watchdog.max_extrapolation", w.max_extrapolation_s, "0..0.1 s");
  require(std::isfinite(w.max_tick_interval_s) && w.max_tick_interval_s >= 1e-5 && w.max_tick_interval_s <= 0.1,
          "watchdog.max_tick_interval", w.max_tick_interval_s, "0.01..100 ms");
  require(std::isfinite(status_rate_hz) && status_rate_hz >= 100 && status_rate_hz <= 100000, "status.rate_hz",
          status_rate_hz, "100..100000 Hz");
  require(recorder_capacity >= 16 && recorder_capacity <= (1u << 24), "recorder.capacity",
          static_cast<double>(recorder_capacity), "16..16777216");
}

FollowerConfig FollowerConfig::FromYaml(const std::filesystem::path& file, const transfer::SpeedCaps& caps) {
  return FromConfig(ConfigNode::Load(file), caps);
}

FollowerConfig FollowerConfig::FromConfig(const ConfigNode& root, const transfer::SpeedCaps& caps) {
  FollowerConfig c;
  const ConfigNode sp = root.Child("setpoint");
  c.setpoint.caps = caps;
  c.setpoint.max_age_s = 1e-3 * sp.PositiveNumber("max_age_ms");
  c.setpoint.max_linear_accel_m_s2 = MmToM(sp.PositiveNumber("max_linear_accel_mm_s2"));
  c.setpoint.max_angular_accel_rad_s2 = DegToRad(sp.PositiveNumber("max_angular_accel_deg_s2"));
  c.setpoint.cap_tolerance = sp.NumberInRange("cap_tolerance", 0.0, 0.5);
  c.setpoint.stamp_jitter_s = 1e-3 * sp.NumberInRange("stamp_jitter_ms", 0.0, 10.0);
  c.setpoint.arrival_allowance_s = 1e-3 * sp.NumberInRange("arrival_allowance_ms", 0.0, 100.0);
  const ConfigNode wd = root.Child("watchdog");
  c.watchdog.hold_after_s = 1e-3 * wd.PositiveNumber("hold_after_ms");
  c.watchdog.leader_lost_after_s = 1e-3 * wd.PositiveNumber("leader_lost_after_ms");
  c.watchdog.max_extrapolation_s = 1e-3 * wd.NumberInRange("max_extrapolation_ms", 0.0, 100.0);
  c.watchdog.max_tick_interval_s = 1e-3 * wd.NumberInRange("max_tick_interval_ms", 0.01, 100.0);
  c.status_rate_hz = root.Child("status").NumberInRange("rate_hz", 100.0, 100000.0);
  c.recorder_capacity = static_cast<std::size_t>(root.Child("recorder").NumberInRange("capacity", 16, 1 << 24));
  const ConfigNode g = root.Child("guard");
  c.guard.rotation_length_m = MmToM(g.PositiveNumber("rotation_length_mm"));
  c.guard.stroke_buffer_m = MmToM(g.NumberInRange("stroke_buffer_mm", 0.0, 1.0));
  c.guard.angle_buffer_rad = DegToRad(g.NumberInRange("angle_buffer_deg", 0.0, 0.5));
  c.guard.approach_gain = g.NumberInRange("approach_gain", 1e-6, 1.0);
  c.guard.max_relinearizations = g.Integer("max_relinearizations");
  c.guard.max_halvings = g.Integer("max_halvings");
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  try {
    c.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(root.file() + ": " + e.what());
  }
  return c;
}

}  // namespace robossis::teleop
