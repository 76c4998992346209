#include "src/panel/panel_config.h"

#include "src/core/config.h"

namespace robossis::panel {

PanelConfig PanelConfig::FromYaml(const std::filesystem::path& file) {
  return FromConfig(ConfigNode::Load(file));
}

PanelConfig PanelConfig::FromConfig(const ConfigNode& root) {
  PanelConfig config;
  const ConfigNode window = root.Child("window");
  config.window_width_px = static_cast<int>(window.NumberInRange("width_px", 320, 7680));
  config.window_height_px = static_cast<int>(window.NumberInRange("height_px", 240, 4320));
  const ConfigNode plots = root.Child("plots");
  config.plot_window_s = plots.NumberInRange("window_s", 0.5, 600);
  config.plot_capacity_samples = static_cast<int>(plots.NumberInRange("capacity_samples", 16, 1e6));
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  return config;
}

}  // namespace robossis::panel
