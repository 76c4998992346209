#include "haptics/transfer/transfer_config.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "src/core/config.h"
#include "src/core/parse.h"
#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::transfer {

namespace {
std::string Num(double v) { return FormatNumber(v); }

void Require(bool ok, const std::string& field, const std::string& expected, double value) {
  if (!ok) {
    throw std::invalid_argument("transfer config: '" + field + "': expected " + expected + ", got " + Num(value));
  }
}

// Both caps' check: `shown` is the cap in the unit of the message, `max_shown` its maximum in that unit, `max_si`
// the same in SI (compared in SI: the conversion is monotone, so a cap given as exactly the maximum passes).
void CheckSpeedCap(double cap_si, double shown, double max_si, double max_shown, const char* unit,
                   const std::string& input) {
  if (!(std::isfinite(cap_si) && cap_si > 0 && cap_si <= max_si)) {
    throw std::invalid_argument(input + ": expected a speed cap in (0, " + Num(max_shown) + "] " + unit + ", got " +
                                Num(shown) + " " + unit);
  }
}
}  // namespace

void CheckLinearSpeedCap(double cap_m_s, const std::string& input) {
  CheckSpeedCap(cap_m_s, MToMm(cap_m_s), MmToM(kMaxLinearSpeedCapMmS), kMaxLinearSpeedCapMmS, "mm/s", input);
}

void CheckAngularSpeedCap(double cap_rad_s, const std::string& input) {
  CheckSpeedCap(cap_rad_s, RadToDeg(cap_rad_s), DegToRad(kMaxAngularSpeedCapDegS), kMaxAngularSpeedCapDegS, "deg/s",
                input);
}

void TransferConfig::Validate() const {
  Require(rates.transfer_rate_hz >= kMinTransferRateHz && rates.transfer_rate_hz <= kMaxTransferRateHz,
          "rates.transfer_rate_hz", "a rate in [" + Num(kMinTransferRateHz) + ", " + Num(kMaxTransferRateHz) + "] Hz",
          rates.transfer_rate_hz);
  Require(rates.actuation_rate_hz >= rates.transfer_rate_hz && rates.actuation_rate_hz <= kMaxActuationRateHz,
          "rates.actuation_rate_hz",
          "a rate in [transfer_rate_hz, " + Num(kMaxActuationRateHz) + "] Hz (transfer_rate_hz is " +
              Num(rates.transfer_rate_hz) + ")",
          rates.actuation_rate_hz);
  const double ratio = rates.actuation_rate_hz / rates.transfer_rate_hz;
  Require(std::abs(ratio - std::round(ratio)) < 1e-9, "rates.actuation_rate_hz",
          "an integer multiple of transfer_rate_hz", rates.actuation_rate_hz);
  CheckLinearSpeedCap(caps.max_linear_speed_m_s, "transfer config: 'caps.max_linear_speed_mm_s'");
  CheckAngularSpeedCap(caps.max_angular_speed_rad_s, "transfer config: 'caps.max_angular_speed_deg_s'");
  try {
    mapping.frame().Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("transfer config: ") + e.what());
  }
  Require(mapping.cap_headroom > 0 && mapping.cap_headroom <= 1, "mapping.cap_headroom", "a value in (0, 1]",
          mapping.cap_headroom);
  Require(std::isfinite(mapping.max_backlog_s) && mapping.max_backlog_s >= 0, "mapping.max_backlog_s",
          "a non-negative duration", mapping.max_backlog_s);
  Require(std::isfinite(mapping.max_prediction_s) && mapping.max_prediction_s >= 0, "mapping.max_prediction_s",
          "a non-negative duration", mapping.max_prediction_s);
  Require(filter.moving_average_window >= 1 && filter.moving_average_window <= kMaxMovingAverageWindow,
          "filter.moving_average_window", "an integer in [1, 1024]", filter.moving_average_window);
  Require(std::isfinite(filter.kalman_jerk_psd) && filter.kalman_jerk_psd > 0, "filter.kalman_jerk_psd",
          "a positive spectral density", filter.kalman_jerk_psd);
  Require(std::isfinite(filter.kalman_measurement_std_m) && filter.kalman_measurement_std_m > 0,
          "filter.kalman_measurement_std_mm", "a positive std", MToMm(filter.kalman_measurement_std_m));
  Require(std::isfinite(filter.guard_time_constant_s) && filter.guard_time_constant_s >= 0,
          "filter.guard_time_constant_s", "a non-negative time constant", filter.guard_time_constant_s);
  Require(std::isfinite(filter.guard_position_gain_per_s) && filter.guard_position_gain_per_s >= 0 &&
              (filter.guard_time_constant_s == 0 || filter.guard_position_gain_per_s * filter.guard_time_constant_s < 2),
          "filter.guard_position_gain_per_s", "a gain in [0, 2 / guard_time_constant_s) for stability",
          filter.guard_position_gain_per_s);
}

TransferConfig TransferConfig::FromYaml(const std::filesystem::path& file) {
  return FromConfig(ConfigNode::Load(file));
}

TransferConfig TransferConfig::FromConfig(const ConfigNode& root) {
  TransferConfig c;
  const ConfigNode rates = root.Child("rates");
  // Read as numbers; their ranges (the rates', the caps' one checker) are Validate()'s.
  c.rates.transfer_rate_hz = rates.Number("transfer_rate_hz");
  c.rates.actuation_rate_hz = rates.Number("actuation_rate_hz");
  const ConfigNode caps = root.Child("caps");
  c.caps.max_linear_speed_m_s = MmToM(caps.Number("max_linear_speed_mm_s"));
  c.caps.max_angular_speed_rad_s = DegToRad(caps.Number("max_angular_speed_deg_s"));
  const ConfigNode mapping = root.Child("mapping");
  const std::vector<double> rpy = mapping.Numbers("rsr_from_hc_rpy_deg", 3);
  c.mapping.R_FO = RotationFromRpy(Eigen::Vector3d(DegToRad(rpy[0]), DegToRad(rpy[1]), DegToRad(rpy[2])));
  c.mapping.translation_scale = mapping.PositiveNumber("translation_scale");
  c.mapping.rotation_scale = mapping.PositiveNumber("rotation_scale");
  c.mapping.cap_headroom = mapping.NumberInRange("cap_headroom", 1e-6, 1.0);
  c.mapping.max_backlog_s = mapping.NumberInRange("max_backlog_s", 0.0, 10.0);
  c.mapping.max_prediction_s = mapping.NumberInRange("max_prediction_s", 0.0, 1.0);
  const ConfigNode filter = root.Child("filter");
  c.filter.moving_average_window = filter.Integer("moving_average_window");
  c.filter.kalman_enabled = filter.Bool("kalman_enabled");
  c.filter.kalman_jerk_psd = filter.PositiveNumber("kalman_jerk_psd");
  c.filter.kalman_measurement_std_m = MmToM(filter.PositiveNumber("kalman_measurement_std_mm"));
  c.filter.guard_position_gain_per_s = filter.NumberInRange("guard_position_gain_per_s", 0.0, 1e6);
  c.filter.guard_time_constant_s = filter.NumberInRange("guard_time_constant_s", 0.0, 1.0);
  try {
    c.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(root.file() + ": " + e.what());
  }
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  return c;
}

}  // namespace robossis::transfer
