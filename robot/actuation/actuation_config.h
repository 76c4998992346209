#pragma once
// Motor and drive settings of the RSR actuation (paper §V-A, eq. 13–17), from data/config/actuation.yaml. The
// paper gives none of the drive numbers: steps per revolution, microstepping, gear ratios, lead-screw pitch and the
// maximum step rate are all assumptions, marked so in the YAML.

#include <array>
#include <filesystem>

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::actuation {

inline constexpr int kNumMotors = 6;  // eq. 13 order: theta_1..3 (rotary), d_1..3 (linear)
// The pulse stream holds at most this many steps per motor per 10 kHz tick (sized at compile time).
inline constexpr int kMaxStepsPerTickPerMotor = 8;

struct MotorConfig {
  double steps_per_unit = 1;     // steps per rad (rotary) or per m (linear): eq. 17's resolution
  double max_step_rate_hz = 1;   // the driver's or motor's limit
};

// The actuation's tick rate is not here: it is transfer.yaml's `rates.actuation_rate_hz` (the rate the chain, the
// follower unit and the panel tick at), its one place. actuation.yaml refuses an `actuation_rate_hz` key, saying so.
struct ActuationConfig {
  std::array<MotorConfig, kNumMotors> motors;  // eq. 13 order
  // eq. 16 integrates q_dot = J x_dot (Euler backward); this gain pulls q toward IK(x) so that the integration's
  // first-order error cannot accumulate (closed-loop inverse kinematics). 0 gives the paper's pure eq. 16.
  double ik_correction_gain_per_s = 20;  // [assumed]

  void Validate() const;  // throws std::invalid_argument naming the field
  // The motors' top speeds in joint units (rad/s rotary, m/s linear), eq. 13 order: max_step_rate_hz over
  // steps_per_unit.
  std::array<double, kNumMotors> MaxJointSpeeds() const;
  // The checks that need the tick rate (transfer.yaml `rates.actuation_rate_hz`): the IK correction within one
  // tick, and the per-tick pulse buffer. Throws std::invalid_argument naming the field and the rate.
  void ValidateAtRate(double actuation_rate_hz) const;
  static ActuationConfig FromYaml(const std::filesystem::path& file);  // throws std::runtime_error
  // The same, then ValidateAtRate(actuation_rate_hz), the error naming the file: how the runtime loads it.
  static ActuationConfig FromYaml(const std::filesystem::path& file, double actuation_rate_hz);
  // The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
  static ActuationConfig FromConfig(const ConfigNode& root);
};

}  // namespace robossis::actuation
