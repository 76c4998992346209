#include "haptics/rendering/renderer_factory.h"

#include <stdexcept>

#include "haptics/rendering/mesh_proxy_renderer.h"
#include "haptics/rendering/mesh_wall_renderer.h"
#include "haptics/rendering/point_cloud_renderer.h"
#include "haptics/rendering/proxy_renderer.h"

namespace robossis::haptics {

std::unique_ptr<HapticRenderer> MakeRenderer(const std::string& method, const HapticsConfig& config,
                                             const robot::RsrModel& model, const HcToRsrMap& map, double rate_hz,
                                             std::shared_ptr<const geometry::BoundaryAtlas> atlas,
                                             BackgroundWork background) {
  PassivityParams passive = config.passivity;
  passive.enabled = true;
  std::unique_ptr<HapticRenderer> r;
  if (method == "pointcloud") {
    r = std::make_unique<PointCloudRenderer>(model, map, config.limits, rate_hz, config.wall, config.cloud,
                                             "pointcloud");
  } else if (method == "pointcloud-safe") {
    r = std::make_unique<PointCloudRenderer>(model, map, config.limits, rate_hz, config.device_safe_wall,
                                             config.cloud, "pointcloud-safe");
  } else if (method == "pointcloud-pc") {
    r = std::make_unique<PointCloudRenderer>(model, map, config.limits, rate_hz, config.wall, config.cloud,
                                             "pointcloud-pc");
    r->SetPassivity(passive);
  } else if (method == "mesh") {
    if (!atlas) {
      throw std::invalid_argument("method 'mesh' needs a boundary atlas (build one with `robossis workspace atlas "
                                  "--out DIR` and pass --atlas DIR)");
    }
    r = std::make_unique<MeshWallRenderer>(model, map, config.limits, rate_hz, config.wall,
                                           config.cloud.moving_average_window, std::move(atlas), "mesh");
  } else if (method == "mesh-live") {
    auto mesh = std::make_unique<MeshWallRenderer>(model, map, config.limits, rate_hz, config.wall,
                                                   config.cloud.moving_average_window, std::move(atlas), "mesh-live");
    // (The HC model is not used by the RSR slices a live boundary regenerates.)
    auto live = std::make_shared<geometry::LiveBoundary>(model, robot::Sigma7Model::Default(), config.live);
    if (background == BackgroundWork::kThread) {
      live->Start();
      mesh->UseLiveBoundary(std::move(live), -1, config.live_switch_blend_s);
    } else {
      mesh->UseLiveBoundary(std::move(live), config.live_refresh_latency_s, config.live_switch_blend_s);
    }
    r = std::move(mesh);
  } else if (method == "mesh-proxy" || method == "mesh-proxy-safe") {
    // -safe: the device-safe wall (the torque stiffness the sigma.7 renders stably), as proxy-safe.
    const bool safe = method == "mesh-proxy-safe";
    auto live = std::make_shared<geometry::LiveBoundary>(model, robot::Sigma7Model::Default(), config.live);
    const bool thread = background == BackgroundWork::kThread;
    if (thread) live->Start();
    r = std::make_unique<MeshProxyRenderer>(model, map, config.limits, rate_hz,
                                            safe ? config.device_safe_wall : config.wall, config.mesh_proxy,
                                            std::move(atlas), std::move(live),
                                            thread ? -1.0 : config.live_refresh_latency_s,
                                            safe ? "mesh-proxy-safe" : "mesh-proxy");
  } else if (method == "proxy") {
    r = std::make_unique<ProxyRenderer>(model, map, config.limits, rate_hz, config.wall, config.proxy, "proxy");
  } else if (method == "proxy-safe") {
    r = std::make_unique<ProxyRenderer>(model, map, config.limits, rate_hz, config.device_safe_wall, config.proxy,
                                        "proxy-safe");
  } else if (method == "proxy-pc") {
    r = std::make_unique<ProxyRenderer>(model, map, config.limits, rate_hz, config.device_safe_wall, config.proxy,
                                        "proxy-pc");
    r->SetPassivity(passive);
  } else {
    ParseMethodName(method, "rendering method");  // throws for a name that is not known
    throw std::logic_error("rendering method '" + method + "' is known but has no renderer");
  }
  return r;
}

}  // namespace robossis::haptics
