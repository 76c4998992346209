#include "src/teleop/let_go_detector.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace robossis::teleop {

void LetGoConfig::Validate() const {
  auto positive = [](double v, const char* field) {
    if (!(std::isfinite(v) && v > 0)) {
      throw std::invalid_argument(std::string("let-go detector: ") + field + " must be finite and > 0");
    }
  };
  positive(device_mass_kg, "device_mass_kg");
  positive(mass_ratio, "mass_ratio");
  positive(min_force_n, "min_force_n");
  positive(confirm_s, "confirm_s");
  positive(rest_damping_n_s_per_m, "rest_damping_n_s_per_m");
  positive(max_damper_share, "max_damper_share");
}

LetGoDetector::LetGoDetector(const LetGoConfig& config) : config_(config) { config.Validate(); }

void LetGoDetector::Reset() noexcept {
  free_s_ = 0;
  let_go_ = false;
}

bool LetGoDetector::Update(const Eigen::Vector3d& force_O, const Eigen::Vector3d& v_before_O,
                           const Eigen::Vector3d& v_after_O, double dt, double damping_n_s_per_m) noexcept {
  if (let_go_) return true;
  // Nobody holds the device when its own mass explains its motion: m·a = f, the force it displayed, in every
  // direction, within a share 1 − 1/mass_ratio of |f| (along the force the apparent mass |f|²/(f·a) then lies within
  // m/(2 − 1/mass_ratio) .. mass_ratio·m; across it no other force pushes). A held device's acceleration is the
  // hand's push too. Judged along the force alone ("lighter than mass_ratio·m"), a small displayed force (1-2 N,
  // where the taper fades the load along the motion) with the hand's push along it passed on single ticks in the
  // runtime, the acceleration across the force half as large as along it; those ticks no longer pass.
  const double f2 = force_O.squaredNorm();
  const double m = config_.device_mass_kg;
  const Eigen::Vector3d a = (v_after_O - v_before_O) / dt;
  const double tolerance = 1 - 1 / config_.mass_ratio;
  const double damper = damping_n_s_per_m * v_before_O.norm();
  const bool free = f2 >= config_.min_force_n * config_.min_force_n &&
                    damper * damper <= config_.max_damper_share * config_.max_damper_share * f2 &&
                    (m * a - force_O).squaredNorm() < tolerance * tolerance * f2;
  free_s_ = free ? free_s_ + dt : 0.0;
  let_go_ = free_s_ >= config_.confirm_s;
  return let_go_;
}

}  // namespace robossis::teleop
