#include "robot/drivers/hal_config.h"

#include <cctype>
#include <cmath>
#include <stdexcept>

#include "src/core/config.h"

namespace robossis::drivers {
namespace {

void RequirePositive(double value, const char* field) {
  if (!(std::isfinite(value) && value > 0)) {
    throw std::invalid_argument(std::string("hal config: '") + field + "' must be positive, got " +
                                std::to_string(value));
  }
}

// HAL names: letters, digits, '-', '_' (the component name prefixes every pin and signal).
bool IsHalName(const std::string& name) {
  if (name.empty() || name.size() > 32) return false;
  for (char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) return false;
  }
  return true;
}

std::uint32_t Nanoseconds(const ConfigNode& node, const std::string& key) {
  const double v = node.NumberInRange(key, 0, 1e9);
  if (v != std::floor(v)) node.Fail(key, "expected a whole number of ns");
  return static_cast<std::uint32_t>(v);
}

}  // namespace

void HalConfig::Validate() const {
  if (!IsHalName(component_name)) {
    throw std::invalid_argument("hal config: 'component_name' must be 1-32 letters, digits, '-' or '_', got '" +
                                component_name + "'");
  }
  RequirePositive(static_cast<double>(servo_period_ns), "threads.servo_period_ns");
  RequirePositive(static_cast<double>(base_period_ns), "threads.base_period_ns");
  if (base_period_ns > servo_period_ns) {
    throw std::invalid_argument("hal config: 'threads.base_period_ns' must not exceed 'threads.servo_period_ns'");
  }
  RequirePositive(accel_time_s, "accel_time_s");
  RequirePositive(follower_timeout_s, "watchdog.follower_timeout_s");
  RequirePositive(feedback_timeout_s, "watchdog.feedback_timeout_s");
  // Fewer than two servo periods cannot tell a late period from a dead thread.
  if (follower_timeout_s < 2 * servo_period_s() || feedback_timeout_s < 2 * servo_period_s()) {
    throw std::invalid_argument("hal config: the watchdog timeouts must be at least two servo periods");
  }
  RequirePositive(static_cast<double>(mesa_watchdog_timeout_ns), "mesa.card_watchdog_timeout_ns");
  if (mesa_board_ip.empty()) throw std::invalid_argument("hal config: 'mesa.board_ip' is empty");
}

HalConfig HalConfig::FromYaml(const std::filesystem::path& file) {
  return FromConfig(ConfigNode::Load(file));
}

HalConfig HalConfig::FromConfig(const ConfigNode& root) {
  HalConfig c;
  c.component_name = root.String("component_name");
  const ConfigNode threads = root.Child("threads");
  c.servo_period_ns = threads.Integer("servo_period_ns");
  c.base_period_ns = threads.Integer("base_period_ns");
  c.accel_time_s = root.PositiveNumber("accel_time_s");
  const ConfigNode timing = root.Child("stepgen_timing");
  c.timing.steplen_ns = Nanoseconds(timing, "steplen_ns");
  c.timing.stepspace_ns = Nanoseconds(timing, "stepspace_ns");
  c.timing.dirsetup_ns = Nanoseconds(timing, "dirsetup_ns");
  c.timing.dirhold_ns = Nanoseconds(timing, "dirhold_ns");
  const ConfigNode watchdog = root.Child("watchdog");
  c.follower_timeout_s = watchdog.PositiveNumber("follower_timeout_s");
  c.feedback_timeout_s = watchdog.PositiveNumber("feedback_timeout_s");
  const ConfigNode mesa = root.Child("mesa");
  c.mesa_board_ip = mesa.String("board_ip");
  c.mesa_watchdog_timeout_ns = mesa.Integer("card_watchdog_timeout_ns");
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  try {
    c.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(root.file() + ": " + e.what());
  }
  return c;
}

}  // namespace robossis::drivers
