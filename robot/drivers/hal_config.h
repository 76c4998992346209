#pragma once
// Settings of the follower's LinuxCNC HAL back end, from data/config/hal.yaml. The paper gives none of them (its
// real-time target is not LinuxCNC): all are assumptions, marked so in the YAML. The motors' steps per unit and
// step-rate caps are not repeated here; they come from actuation::ActuationConfig.

#include <cstdint>
#include <filesystem>
#include <string>

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::drivers {

// Step/direction timing a driver needs (its datasheet's minimums), in ns, as stepgen(9) and hostmot2(9) take them.
struct StepgenTiming {
  std::uint32_t steplen_ns = 5000;
  std::uint32_t stepspace_ns = 5000;
  std::uint32_t dirsetup_ns = 20000;
  std::uint32_t dirhold_ns = 20000;
};

struct HalConfig {
  std::string component_name = "robossis";  // the HAL component; its pins are <name>.joint.N.pos-cmd, ...
  std::int64_t servo_period_ns = 1000000;   // servo thread: the follower's Service() rate
  std::int64_t base_period_ns = 50000;      // base thread: the software stepgen's pulse resolution
  double accel_time_s = 0.1;                // rest to the step-rate cap: maxaccel = maxvel / accel_time_s
  StepgenTiming timing;
  double follower_timeout_s = 0.1;   // HAL's watchdog cuts the drives after this long without a toggle
  double feedback_timeout_s = 0.1;   // the follower reports lost feedback after this long without an echo
  std::string mesa_board_ip = "10.10.10.10";
  std::int64_t mesa_watchdog_timeout_ns = 5000000;

  double servo_period_s() const { return servo_period_ns * 1e-9; }
  void Validate() const;  // throws std::invalid_argument naming the field
  static HalConfig FromYaml(const std::filesystem::path& file);  // throws std::runtime_error naming file and key
  // The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
  static HalConfig FromConfig(const ConfigNode& root);
};

}  // namespace robossis::drivers
