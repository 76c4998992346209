#pragma once
// Rendering methods by name, as the command line and the comparison use them.
//
//   pointcloud       the paper's method (Algorithm 1, eq. 18–21) with the paper's constants
//   pointcloud-safe  the same with the device-safe preset (torque stiffness the sigma.7 renders stably)
//   pointcloud-pc    the paper's method with the time-domain passivity observer + controller
//   proxy            ours: god-object on the true boundary, virtual coupling, the paper's constants
//   proxy-safe       ours with the device-safe preset
//   proxy-pc         ours, device-safe preset, with the passivity observer + controller
//   mesh             the paper's spring-damper law on the FCL signed penetration against the boundary atlas
//                    (needs an atlas: `robossis workspace atlas --out DIR`)
//   mesh-live        the same on slices regenerated at the current pose in the background (geometry/live_boundary.h),
//                    the atlas (optional) answering until the first refresh lands
//   mesh-proxy       a god-object on the same meshes (slices regenerated around the proxy, the atlas optional): the
//                    mesh gives the direction back inside, the exact IK the true boundary along it; the wall law of
//                    proxy (haptics/rendering/mesh_proxy_renderer.h)

#include <memory>
#include <string>
#include <vector>

#include "geometry/boundary_atlas.h"
#include "haptics/haptics_config.h"
#include "haptics/rendering/haptic_types.h"
#include "haptics/rendering/method_names.h"

namespace robossis::haptics {

// Where a method's background work (mesh-live: the slice refresh) runs: in simulated time through
// HapticRenderer::StepSimulatedBackground (deterministic closed-loop simulations), or on a thread of its own (a real
// haptic loop).
enum class BackgroundWork { kSimulated, kThread };

// Throws std::invalid_argument naming the method and listing the known ones (ParseMethodName). `atlas` is needed
// by "mesh" (and used by "mesh-live" until its first refresh).
std::unique_ptr<HapticRenderer> MakeRenderer(const std::string& method, const HapticsConfig& config,
                                             const robot::RsrModel& model, const HcToRsrMap& map, double rate_hz,
                                             std::shared_ptr<const geometry::BoundaryAtlas> atlas = nullptr,
                                             BackgroundWork background = BackgroundWork::kSimulated);

}  // namespace robossis::haptics
