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
}

LetGoDetector::LetGoDetector(const LetGoConfig& config) : config_(config) { config.Validate(); }

void LetGoDetector::Reset() noexcept {
  free_s_ = 0;
  let_go_ = false;
}

bool LetGoDetector::Update(const Eigen::Vector3d& force_O, const Eigen::Vector3d& v_before_O,
                           const Eigen::Vector3d& v_after_O, double dt) noexcept {
  if (let_go_) return true;
  // The apparent mass along the force: |f|² / (f·Δv/dt); a held device's is the hand's and the device's together.
  const double f2 = force_O.squaredNorm();
  const double push = force_O.dot(v_after_O - v_before_O) / dt;  // f·a
  const bool free = f2 >= config_.min_force_n * config_.min_force_n && push > 0 &&
                    f2 < config_.mass_ratio * config_.device_mass_kg * push;
  free_s_ = free ? free_s_ + dt : 0.0;
  let_go_ = free_s_ >= config_.confirm_s;
  return let_go_;
}

}  // namespace robossis::teleop
