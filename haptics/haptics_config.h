#pragma once
// Configuration of the haptics module: data/config/haptics.yaml (paper values marked [paper], assumptions
// [assumed]). Loaded and validated once; the real-time code only reads the resulting structs.

#include <filesystem>
#include <string>

#include "geometry/live_boundary.h"
#include "haptics/device/device_sim.h"
#include "haptics/rendering/haptic_types.h"
#include "haptics/rendering/mesh_proxy_renderer.h"
#include "haptics/rendering/point_cloud_renderer.h"
#include "haptics/rendering/proxy_renderer.h"
#include "haptics/rendering/wall_law.h"

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::haptics {

struct HapticsConfig {
  WallLawParams wall;              // the paper's eq. 18–19 constants
  WallLawParams device_safe_wall;  // the device-safe preset
  WrenchLimits limits;
  PointCloudParams cloud;
  ProxyParams proxy;
  PassivityParams passivity;       // enabled per method by the factory
  HandParams hand;
  double strike_hand_stiffness_n_per_m = 1200;
  DeviceSimParams device;
  geometry::LiveBoundaryOptions live;   // mesh-live: the slices regenerated at the current pose
  double live_refresh_latency_s = 0.15;  // mesh-live in simulation: modelled time of one refresh (both slices)
  double live_switch_blend_s = 0.1;      // mesh-live: a new slice's wall is blended in over this time
  MeshProxyParams mesh_proxy;            // mesh-proxy: the god-object on the meshes (slices: `live` above)
  // The rendering method a hardware leader uses unless told otherwise (the runtime reads it; a KnownMethods name).
  std::string hardware_default_method = "proxy";

  // Throws std::runtime_error naming the file and key.
  static HapticsConfig FromYaml(const std::filesystem::path& file);
  // The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
  static HapticsConfig FromConfig(const ConfigNode& root);
};

}  // namespace robossis::haptics
