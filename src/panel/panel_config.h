#pragma once
// Settings of the control panel, loaded once from data/config/panel.yaml and validated there.

#include <filesystem>

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::panel {

struct PanelConfig {
  int window_width_px = 1600;
  int window_height_px = 900;
  double plot_window_s = 10;
  int plot_capacity_samples = 2000;

  // Throws std::runtime_error naming the file and key.
  static PanelConfig FromYaml(const std::filesystem::path& file);
  // The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
  static PanelConfig FromConfig(const ConfigNode& root);
};

}  // namespace robossis::panel
