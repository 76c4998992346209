#include "haptics/haptics_config.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "haptics/rendering/method_names.h"
#include "src/core/config.h"
#include "src/core/units.h"

namespace robossis::haptics {

namespace {
WallLawParams ReadWall(const ConfigNode& node) {
  WallLawParams w;
  w.k_f_n_per_m = node.PositiveNumber("k_f_n_per_m");
  w.c_f_ns_per_m = node.NumberInRange("c_f_ns_per_m", 0, 1e4);
  w.k_tau_nm_per_rad = node.PositiveNumber("k_tau_nm_per_deg") * kRadToDeg;
  w.c_tau_nms_per_rad = node.NumberInRange("c_tau_nms_per_deg", 0, 1e3) * kRadToDeg;
  return w;
}
}  // namespace

HapticsConfig HapticsConfig::FromYaml(const std::filesystem::path& file) {
  return FromConfig(ConfigNode::Load(file));
}

HapticsConfig HapticsConfig::FromConfig(const ConfigNode& root) {
  HapticsConfig c;
  c.wall = ReadWall(root.Child("wall"));
  c.device_safe_wall = ReadWall(root.Child("device_safe"));
  const ConfigNode limits = root.Child("limits");
  c.limits.max_force_n = limits.PositiveNumber("max_force_n");
  c.limits.max_torque_nm = limits.PositiveNumber("max_torque_nm");
  const ConfigNode cloud = root.Child("point_cloud");
  c.cloud.translation_radius_m = MmToM(cloud.PositiveNumber("translation_radius_mm"));
  c.cloud.rotation_radius_rad = DegToRad(cloud.PositiveNumber("rotation_radius_deg"));
  c.cloud.translation_points = cloud.IntegerInRange("translation_points", 2, 100000);
  c.cloud.rotation_points = cloud.IntegerInRange("rotation_points", 2, 100000);
  c.cloud.moving_average_window =
      cloud.IntegerInRange("moving_average_window", 1, WeightedMovingAverage::kMaxWindow);
  c.cloud.decouple_soft_torque_wall = cloud.Bool("decouple_soft_torque_wall");
  const ConfigNode proxy = root.Child("proxy");
  c.proxy.bisection_steps = proxy.IntegerInRange("bisection_steps", 1, 60);
  c.proxy.max_slides = proxy.IntegerInRange("max_slides", 1, 10);
  const ConfigNode pc = root.Child("passivity");
  c.passivity.max_damping_ns_per_m = pc.PositiveNumber("max_damping_ns_per_m");
  c.passivity.max_damping_nms_per_rad = pc.PositiveNumber("max_damping_nms_per_rad");
  // The HC -> RSR scale's one place is transfer.yaml (the frame map the set-points use); a copy here could
  // disagree with it silently, as haptics.yaml's old `mapping.scale` did with R_FO.
  if (root.Has("mapping")) {
    root.Fail("mapping", "this section moved to transfer.yaml 'mapping' (translation_scale, rotation_scale, "
                         "rsr_from_hc_rpy_deg: the one HC -> RSR map of the walls and the set-points); remove it here");
  }
  const ConfigNode hand = root.Child("hand");
  c.hand.mass_kg = hand.PositiveNumber("mass_kg");
  c.hand.stiffness_n_per_m = hand.PositiveNumber("stiffness_n_per_m");
  c.hand.damping_ns_per_m = hand.NumberInRange("damping_ns_per_m", 0, 1e4);
  c.hand.inertia_kgm2 = hand.PositiveNumber("inertia_kgm2");
  c.hand.rot_stiffness_nm_per_rad = hand.PositiveNumber("rot_stiffness_nm_per_rad");
  c.hand.rot_damping_nms_per_rad = hand.NumberInRange("rot_damping_nms_per_rad", 0, 1e3);
  c.strike_hand_stiffness_n_per_m = hand.PositiveNumber("strike_stiffness_n_per_m");
  const ConfigNode dev = root.Child("device_sim");
  c.device.damping_ns_per_m = dev.NumberInRange("damping_ns_per_m", 0, 1e4);
  c.device.rot_damping_nms_per_rad = dev.NumberInRange("rot_damping_nms_per_rad", 0, 1e3);
  c.device.physics_rate_hz = dev.NumberInRange("physics_rate_hz", 100, 1e6);
  const ConfigNode live = root.Child("mesh_live");
  c.live.dexterous_resolution_m = MmToM(live.PositiveNumber("dexterous_resolution_mm"));
  c.live.rotational_resolution_rad = DegToRad(live.PositiveNumber("rotational_resolution_deg"));
  c.live.orientation_tolerance_rad = DegToRad(live.PositiveNumber("orientation_tolerance_deg"));
  c.live.position_tolerance_m = MmToM(live.PositiveNumber("position_tolerance_mm"));
  c.live_refresh_latency_s = live.PositiveNumber("simulated_refresh_latency_s");
  c.live_switch_blend_s = live.PositiveNumber("switch_blend_s");
  const ConfigNode mp = root.Child("mesh_proxy");
  c.mesh_proxy.bisection_steps = static_cast<int>(mp.NumberInRange("bisection_steps", 1, 60));
  c.mesh_proxy.search_step_m = MmToM(mp.PositiveNumber("search_step_mm"));
  c.mesh_proxy.search_step_rad = DegToRad(mp.PositiveNumber("search_step_deg"));
  c.mesh_proxy.search_expansions = static_cast<int>(mp.NumberInRange("search_expansions", 1, 20));
  c.mesh_proxy.max_extra_step_m = MmToM(mp.NumberInRange("max_extra_step_mm", 0, 100));
  c.mesh_proxy.max_extra_step_rad = DegToRad(mp.NumberInRange("max_extra_step_deg", 0, 90));
  c.mesh_proxy.damping_fade_m = MmToM(mp.NumberInRange("damping_fade_mm", 0, 100));
  c.mesh_proxy.damping_fade_rad = DegToRad(mp.NumberInRange("damping_fade_deg", 0, 90));
  c.mesh_proxy.max_direction_step_rad = DegToRad(mp.NumberInRange("max_direction_step_deg", 0, 180));
  c.mesh_proxy.force_rate.max_rate_n_per_s = mp.NumberInRange("max_force_rate_n_per_s", 0, 1e6);
  c.mesh_proxy.force_rate.free_space_force_n = mp.NumberInRange("free_space_force_n", 0, 20);
  c.mesh_proxy.force_rate.exit_speed_margin = mp.NumberInRange("exit_speed_margin", 1, 100);
  c.mesh_proxy.force_rate.max_damping_ns_per_m = mp.NumberInRange("max_shaper_damping_ns_per_m", 0, 1000);
  try {
    c.hardware_default_method = ParseMethodName(root.String("hardware_default_method"), "hardware_default_method");
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(root.file() + ": " + e.what());
  }
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  return c;
}

}  // namespace robossis::haptics
