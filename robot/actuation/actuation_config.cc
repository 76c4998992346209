#include "robot/actuation/actuation_config.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "src/core/config.h"
#include "src/core/parse.h"
#include "src/core/units.h"

namespace robossis::actuation {

namespace {
std::string Num(double v) { return FormatNumber(v); }
}  // namespace

std::array<double, kNumMotors> ActuationConfig::MaxJointSpeeds() const {
  std::array<double, kNumMotors> speeds{};
  for (int i = 0; i < kNumMotors; ++i) speeds[i] = motors[i].max_step_rate_hz / motors[i].steps_per_unit;
  return speeds;
}

void ActuationConfig::Validate() const {
  if (!(std::isfinite(ik_correction_gain_per_s) && ik_correction_gain_per_s >= 0)) {
    throw std::invalid_argument("actuation config: 'ik_correction_gain_per_s' must be finite and >= 0");
  }
  for (int i = 0; i < kNumMotors; ++i) {
    const MotorConfig& m = motors[i];
    const std::string name = "motor " + std::to_string(i + 1);
    if (!(std::isfinite(m.steps_per_unit) && m.steps_per_unit > 0)) {
      throw std::invalid_argument("actuation config: " + name + ": steps per unit must be positive");
    }
    if (!(std::isfinite(m.max_step_rate_hz) && m.max_step_rate_hz > 0)) {
      throw std::invalid_argument("actuation config: " + name + ": 'max_step_rate_hz' must be positive");
    }
  }
}

void ActuationConfig::ValidateAtRate(double actuation_rate_hz) const {
  Validate();
  const std::string rate = Num(actuation_rate_hz) + " Hz (transfer.yaml 'rates.actuation_rate_hz')";
  if (!(std::isfinite(actuation_rate_hz) && actuation_rate_hz > 0)) {
    throw std::invalid_argument("actuation config: the actuation rate " + rate + " must be positive");
  }
  if (!(ik_correction_gain_per_s * (1.0 / actuation_rate_hz) < 1.0)) {
    throw std::invalid_argument("actuation config: 'ik_correction_gain_per_s' must be below the actuation rate " +
                                rate);
  }
  for (int i = 0; i < kNumMotors; ++i) {
    const MotorConfig& m = motors[i];
    // One more crossing than the rate allows can fall in a tick; the per-tick event buffer must hold it.
    if (m.max_step_rate_hz / actuation_rate_hz + 1 > kMaxStepsPerTickPerMotor) {
      throw std::invalid_argument("actuation config: motor " + std::to_string(i + 1) + ": 'max_step_rate_hz' " +
                                  Num(m.max_step_rate_hz) + " exceeds " +
                                  Num((kMaxStepsPerTickPerMotor - 1) * actuation_rate_hz) +
                                  " (the per-tick pulse buffer at the actuation rate " + rate + ")");
    }
  }
}

ActuationConfig ActuationConfig::FromYaml(const std::filesystem::path& file) {
  return FromConfig(ConfigNode::Load(file));
}

ActuationConfig ActuationConfig::FromYaml(const std::filesystem::path& file, double actuation_rate_hz) {
  ActuationConfig c = FromYaml(file);
  try {
    c.ValidateAtRate(actuation_rate_hz);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
  return c;
}

ActuationConfig ActuationConfig::FromConfig(const ConfigNode& root) {
  ActuationConfig c;
  // The rate's one place is transfer.yaml; a copy here could disagree with it silently.
  if (root.Has("actuation_rate_hz")) {
    root.Fail("actuation_rate_hz", "this key moved to transfer.yaml 'rates.actuation_rate_hz' (the one actuation "
                                   "rate); remove it here");
  }
  c.ik_correction_gain_per_s = root.NumberInRange("ik_correction_gain_per_s", 0.0, 1e4);
  const ConfigNode rotary = root.Child("rotary_motor");
  const ConfigNode linear = root.Child("linear_motor");
  // Rotary joint theta_i: motor steps per motor revolution times the gear ratio, per 2 pi of joint angle.
  const double rotary_steps_per_rev = rotary.PositiveNumber("full_steps_per_rev") * rotary.PositiveNumber("microsteps");
  const double rotary_steps_per_rad = rotary_steps_per_rev * rotary.PositiveNumber("gear_ratio") / (2 * kPi);
  // Linear actuator d_i: steps per revolution per lead-screw lead.
  const double linear_steps_per_rev = linear.PositiveNumber("full_steps_per_rev") * linear.PositiveNumber("microsteps");
  const double linear_steps_per_m = linear_steps_per_rev / MmToM(linear.PositiveNumber("lead_mm_per_rev"));
  for (int i = 0; i < 3; ++i) {
    c.motors[i] = {rotary_steps_per_rad, rotary.PositiveNumber("max_step_rate_hz")};
    c.motors[3 + i] = {linear_steps_per_m, linear.PositiveNumber("max_step_rate_hz")};
  }
  try {
    c.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(root.file() + ": " + e.what());
  }
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  return c;
}

}  // namespace robossis::actuation
