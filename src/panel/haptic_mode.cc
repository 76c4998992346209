#include "src/panel/haptic_mode.h"

#include <stdexcept>

#include "haptics/transfer/transfer_config.h"

namespace robossis::panel {

const char* ToString(SpeedCapPreset preset) {
  return preset == SpeedCapPreset::kClinical ? "clinical" : "demonstration";
}

SpeedCapPreset SpeedCapPresetFromString(const std::string& name) {
  if (name == "clinical") return SpeedCapPreset::kClinical;
  if (name == "demonstration") return SpeedCapPreset::kDemonstration;
  throw std::invalid_argument("speed cap: '" + name + "' is not one of clinical, demonstration");
}

SpeedCapValues CapValues(SpeedCapPreset preset, const SpeedCapValues& demonstration) {
  if (preset == SpeedCapPreset::kDemonstration) return demonstration;
  const transfer::SpeedCaps clinical = transfer::ClinicalSpeedCaps();  // [paper §V] 2 mm/s, 0.2 deg/s
  return {clinical.max_linear_speed_m_s, clinical.max_angular_speed_rad_s};
}

HapticModeModel::HapticModeModel(std::vector<std::string> methods, const SpeedCapValues& demonstration_caps)
    : methods_(std::move(methods)), demonstration_(demonstration_caps) {
  if (methods_.empty()) throw std::invalid_argument("haptic mode: no rendering method is known");
}

bool HapticModeModel::SetEnabled(bool enabled, std::string& reason) {
  reason.clear();
  enabled_ = enabled;
  if (!enabled) clutched_ = false;
  return true;
}

bool HapticModeModel::SetClutched(bool clutched, std::string& reason) {
  reason.clear();
  if (clutched && !enabled_) {
    reason = "clutch: haptic mode is off";
    return false;
  }
  clutched_ = clutched;
  return true;
}

bool HapticModeModel::SetMethod(const std::string& method, std::string& reason) {
  reason.clear();
  for (int i = 0; i < static_cast<int>(methods_.size()); ++i) {
    if (methods_[i] != method) continue;
    if (enabled_ && !clutched_ && i != method_) {
      reason = "rendering method: changes only while clutched or with haptic mode off";
      return false;
    }
    method_ = i;
    return true;
  }
  reason = "rendering method: '" + method + "' is not known";
  return false;
}

bool HapticModeModel::SetCapPreset(SpeedCapPreset preset, std::string& reason) {
  reason.clear();
  if (preset == preset_) return true;
  if (!(enabled_ && clutched_)) {
    reason = "speed cap: changes only while clutched";
    return false;
  }
  preset_ = preset;
  return true;
}

HapticModeRequest HapticModeModel::request() const {
  const SpeedCapValues values = caps();
  return {enabled_, clutched_, method_, values.max_linear_speed_m_s, values.max_angular_speed_rad_s};
}

}  // namespace robossis::panel
