#pragma once
// The haptic-mode controls of the panel: enable/disable, clutch, the rendering method and the speed caps of eq. 11.
//
// Rules (why): the caps bound how fast the fragment follows the hand, so changing them while the robot follows
// would make it jump to a new speed under the surgeon's hand; a cap changes only while clutched (the robot holds).
// The rendering method changes the walls the hand feels, so it too changes only while the robot does not follow
// (haptic mode off, or clutched).

#include <string>
#include <vector>

#include "src/panel/panel_backend.h"

namespace robossis::panel {

enum class SpeedCapPreset { kClinical, kDemonstration };
const char* ToString(SpeedCapPreset preset);                  // "clinical", "demonstration"
SpeedCapPreset SpeedCapPresetFromString(const std::string& name);  // throws std::invalid_argument

struct SpeedCapValues {
  double max_linear_speed_m_s = 0;
  double max_angular_speed_rad_s = 0;
};
// Clinical: the paper's 2 mm/s and 0.2 deg/s. Demonstration: the transfer caps (transfer.yaml, 10 mm/s, 1 deg/s).
SpeedCapValues CapValues(SpeedCapPreset preset, const SpeedCapValues& demonstration);

class HapticModeModel {
 public:
  HapticModeModel(std::vector<std::string> methods, const SpeedCapValues& demonstration_caps);

  // Each setter returns false and says why when the rule forbids the change (nothing changes then).
  bool SetEnabled(bool enabled, std::string& reason);
  bool SetClutched(bool clutched, std::string& reason);
  bool SetMethod(const std::string& method, std::string& reason);
  bool SetCapPreset(SpeedCapPreset preset, std::string& reason);

  bool enabled() const { return enabled_; }
  bool clutched() const { return clutched_; }
  const std::string& method() const { return methods_[method_]; }
  int method_index() const { return method_; }
  const std::vector<std::string>& methods() const { return methods_; }
  SpeedCapPreset cap_preset() const { return preset_; }
  SpeedCapValues caps() const { return CapValues(preset_, demonstration_); }
  HapticModeRequest request() const;

 private:
  std::vector<std::string> methods_;
  SpeedCapValues demonstration_;
  bool enabled_ = false;
  bool clutched_ = false;
  int method_ = 0;
  SpeedCapPreset preset_ = SpeedCapPreset::kClinical;  // the safe default
};

}  // namespace robossis::panel
