#pragma once
// Settings of the motion transfer (paper §V, eq. 9–12), loaded once from data/config/transfer.yaml and validated
// there. Everything is SI inside; the YAML keys carry their units (mm, deg, Hz).

#include <filesystem>
#include <string>

#include <Eigen/Geometry>

#include "haptics/transfer/hc_to_rsr_frame.h"

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::transfer {

// [assumed] The range of the transfer rate (HC sampling and the incremental mapping): the paper's 1 kHz inside it.
// Below 100 Hz a set-point period (10 ms) is a third of the follower's 30 ms freshness bound; above 10 kHz the HC
// would be sampled faster than the steppers are commanded at the paper's rate, and every tick of the leader costs a
// device read (the sigma.7 runs at up to 4 kHz).
inline constexpr double kMinTransferRateHz = 100;
inline constexpr double kMaxTransferRateHz = 10000;
// [assumed] The highest actuation rate (stepper commands), twice the paper's 10 kHz: a tick of 50 µs is the period
// of LinuxCNC's software stepgen base thread (hal.yaml base_period_ns), so pulses cannot be placed finer; a faster
// tick only costs CPU. Its lowest is the transfer rate (the up-sampling ratio is a whole number >= 1).
inline constexpr double kMaxActuationRateHz = 20000;

// Tick rates. The paper samples the HC at 1 kHz (USB) and drives the steppers at 10 kHz (§V). The actuation rate
// has this one place (transfer.yaml `rates.actuation_rate_hz`): the chain, the follower unit, the panel and the
// actuation's checks (actuation::ActuationConfig::ValidateAtRate) all take it from here.
struct TransferRates {
  double transfer_rate_hz = 1000;    // [paper] HC sampling and the incremental mapping
  double actuation_rate_hz = 10000;  // [paper] stepper commands
  int upsampling_ratio() const { return static_cast<int>(actuation_rate_hz / transfer_rate_hz + 0.5); }
};

// The speed caps of eq. 11, on the norm of the linear and of the angular velocity.
struct SpeedCaps {
  double max_linear_speed_m_s = 0.010;                    // [paper] 10 mm/s in the demonstration (2 mm/s clinical)
  double max_angular_speed_rad_s = 1.0 * 3.14159265358979323846 / 180.0;  // [paper] 1 deg/s (0.2 deg/s clinical)
};

// [assumed] The largest speed caps any input may set (transfer.yaml `caps`, --max-speed-mm-s,
// --max-angular-speed-deg-s): 1 m/s and one turn per second, far beyond any surgical-robot motion (the paper's
// demonstration caps are 10 mm/s and 1 deg/s, its clinical ones 2 mm/s and 0.2 deg/s); a larger cap is a typo or an
// attack, and it would let eq. 11 scale nothing down.
inline constexpr double kMaxLinearSpeedCapMmS = 1000;
inline constexpr double kMaxAngularSpeedCapDegS = 360;

// The one check of a speed cap, wherever it comes from (transfer.yaml, the command line's caps): finite, > 0 and
// at most the maximum above. The cap is in SI (m/s, rad/s); `input` names where it came from ("--max-speed-mm-s",
// "'caps.max_linear_speed_mm_s'"). Throws std::invalid_argument
// "INPUT: expected a speed cap in (0, 1000] mm/s, got 1e+300 mm/s".
void CheckLinearSpeedCap(double cap_m_s, const std::string& input);
void CheckAngularSpeedCap(double cap_rad_s, const std::string& input);

// The clinical caps of the paper (§V): 2 mm/s and 0.2 deg/s. The one place they are written.
inline SpeedCaps ClinicalSpeedCaps() {
  SpeedCaps caps;
  caps.max_linear_speed_m_s = 0.002;                                          // [paper] 2 mm/s
  caps.max_angular_speed_rad_s = 0.2 * 3.14159265358979323846 / 180.0;        // [paper] 0.2 deg/s
  return caps;
}

// Incremental mapping (eq. 10–11) and input hygiene. The frame part (R_FO and the nominal scales) is the one HC → RSR
// frame map the walls use too (hc_to_rsr_frame.h); this section of transfer.yaml is its only source.
struct MappingConfig : HcToRsrFrame {
  // [assumed] The mapping scales increments to this fraction of the caps, leaving the final guard headroom so
  // that it rarely has to saturate (it still guarantees the caps on its own).
  double cap_headroom = 0.95;
  // [assumed] After a USB stall the accumulated increment is released at the cap; at most this many seconds of
  // motion at the cap are kept waiting, the rest is dropped (like a short clutch release) so the delay stays bounded.
  double max_backlog_s = 0.10;
  // [assumed] While no new HC sample arrives (dropout, frozen driver), the Kalman filter predicts without a
  // measurement for at most this long, so a short gap does not brake the RSR; after it, the held target is measured
  // again and the RSR comes to rest.
  double max_prediction_s = 0.0;

  const HcToRsrFrame& frame() const noexcept { return *this; }
};

// The 10 kHz chain: moving average, Kalman filter (eq. 12), cap guard.
struct FilterConfig {
  int moving_average_window = 50;         // [assumed] samples at 10 kHz (5 ms); 1 disables it
  bool kalman_enabled = true;             // [paper] eq. 12
  double kalman_jerk_psd = 1.0e-5;        // [assumed] white-jerk spectral density q of the constant-acceleration model
  double kalman_measurement_std_m = 1.0e-4;  // [assumed] r: std of the up-sampled position "measurement"
  // Cap guard: velocity feed-forward plus position feedback, clamped to the caps, then two first-order low-passes
  // (a convex combination: the clamped ball is never left) so that acceleration stays continuous.
  double guard_position_gain_per_s = 60;  // [assumed] k_p; stable for k_p < 2 / tau
  double guard_time_constant_s = 0.003;   // [assumed] tau of each low-pass
};

struct TransferConfig {
  TransferRates rates;
  SpeedCaps caps;
  MappingConfig mapping;
  FilterConfig filter;

  // Throws std::invalid_argument naming the field if a value is out of range.
  void Validate() const;
  // Loads transfer.yaml; throws std::runtime_error naming the file and key.
  static TransferConfig FromYaml(const std::filesystem::path& file);
  // The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
  static TransferConfig FromConfig(const ConfigNode& root);
};

inline constexpr int kMaxMovingAverageWindow = 1024;

}  // namespace robossis::transfer
