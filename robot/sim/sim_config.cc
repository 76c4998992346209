#include "robot/sim/sim_config.h"

#include <stdexcept>
#include <vector>

#include "src/core/config.h"
#include "src/core/units.h"

namespace robossis::sim {

namespace {
Eigen::Vector3d Vec3(const ConfigNode& node, const std::string& key, double scale) {
  const std::vector<double> v = node.Numbers(key, 3);
  return Eigen::Vector3d(v[0], v[1], v[2]) * scale;
}
}  // namespace

SimConfig LoadSimConfig(const std::filesystem::path& file, const std::filesystem::path& data_dir) {
  return LoadSimConfig(ConfigNode::Load(file), data_dir);
}

SimConfig LoadSimConfig(const ConfigNode& root, const std::filesystem::path& data_dir) {
  SimConfig c;
  c.source = root.file();

  const ConfigNode ph = root.Child("physics");
  c.physics.step_hz = ph.NumberInRange("step_hz", 100, 100000);
  const std::string solver = ph.String("solver");
  if (solver == "pgs") {
    c.physics.solver = ConstraintSolverKind::kPgs;
  } else if (solver == "dantzig") {
    c.physics.solver = ConstraintSolverKind::kDantzig;
  } else {
    ph.Fail("solver", "expected 'pgs' or 'dantzig', got '" + solver + "'");
  }
  c.physics.solver_iterations = ph.Integer("solver_iterations");
  if (c.physics.solver_iterations < 1 || c.physics.solver_iterations > 10000) {
    ph.Fail("solver_iterations", "expected an integer in [1, 10000]");
  }
  c.physics.gravity_F_mps2 = Vec3(ph, "gravity_mps2", 1.0);
  if (c.physics.gravity_F_mps2.norm() > 100) ph.Fail("gravity_mps2", "expected a magnitude below 100 m/s^2");
  c.physics.command_extrapolation_max_s = ph.NumberInRange("command_extrapolation_max_s", 0, 1);

  const ConfigNode m = root.Child("masses");
  MassConfig& ms = c.masses;
  ms.moving_ring_kg = m.PositiveNumber("moving_ring_kg");
  ms.moving_ring_radius_m = m.PositiveNumber("moving_ring_radius_m");
  ms.rotary_link_kg = m.PositiveNumber("rotary_link_kg");
  ms.rotary_link_radius_m = m.PositiveNumber("rotary_link_radius_m");
  ms.cylinder_kg = m.PositiveNumber("cylinder_kg");
  ms.cylinder_length_m = m.PositiveNumber("cylinder_length_m");
  ms.cylinder_com_from_base_m = m.NumberInRange("cylinder_com_from_base_m", 0, 1);
  ms.piston_kg = m.PositiveNumber("piston_kg");
  ms.piston_length_m = m.PositiveNumber("piston_length_m");
  ms.piston_com_below_tip_m = m.NumberInRange("piston_com_below_tip_m", 0, 1);
  ms.link_radius_m = m.PositiveNumber("link_radius_m");
  ms.bone_density_kg_per_m3 = m.NumberInRange("bone_density_kg_per_m3", 100, 5000);

  const ConfigNode a = root.Child("actuators");
  c.actuators.linear_force_max_n = a.PositiveNumber("linear_force_max_n");
  c.actuators.rotary_torque_max_nm = a.PositiveNumber("rotary_torque_max_nm");
  const std::string mode = a.String("control");
  if (mode == "position") {
    c.actuators.mode = DriveMode::kPosition;
  } else if (mode == "velocity") {
    c.actuators.mode = DriveMode::kVelocity;
  } else {
    a.Fail("control", "expected 'position' or 'velocity', got '" + mode + "'");
  }

  const ConfigNode b = root.Child("bone");
  const std::filesystem::path mesh = b.String("mesh");
  c.bone.mesh_file = mesh.is_absolute() ? mesh : data_dir / mesh;
  if (!std::filesystem::exists(c.bone.mesh_file)) {
    b.Fail("mesh", "file " + c.bone.mesh_file.string() + " not found");
  }
  c.bone.cut_z_mesh_m = b.Number("cut_z_mesh_m");
  c.bone.fracture_site_z_m = b.NumberInRange("fracture_site_z_m", -1, 1);
  c.bone.contact_region_m = b.NumberInRange("contact_region_m", 0.005, 0.5);
  c.bone.slab_height_m = b.NumberInRange("slab_height_m", 0.001, 0.1);
  c.bone.collision_margin_m = b.NumberInRange("collision_margin_m", 0, 0.005);
  c.bone.penetration_tolerance_m = b.NumberInRange("penetration_tolerance_m", 1e-6, 0.01);

  const ConfigNode t = root.Child("traction");
  c.traction.muscle_count = t.Integer("muscle_count");
  if (c.traction.muscle_count < 3 || c.traction.muscle_count > 64) t.Fail("muscle_count", "expected 3..64");
  c.traction.muscle_radius_m = t.NumberInRange("muscle_radius_m", 0.001, 0.2);
  c.traction.anchor_distance_m = t.NumberInRange("anchor_distance_m", 0.01, 0.5);
  c.traction.axial_stiffness_n_per_m = t.PositiveNumber("axial_stiffness_n_per_mm") * 1e3;
  c.traction.torsional_stiffness_nm_per_rad = t.PositiveNumber("torsional_stiffness_nm_per_deg") * kRadToDeg;
  c.traction.damping_n_s_per_m = t.NumberInRange("damping_n_s_per_m", 0, 1e6);
  c.traction.torsional_damping_nm_s_per_rad = t.NumberInRange("torsional_damping_nm_s_per_deg", 0, 1e4) * kRadToDeg;

  const ConfigNode s = root.Child("sinusoid");
  c.sinusoid.center_offset_m = Vec3(s, "center_offset_mm", kMmToM);
  c.sinusoid.amplitude_m = Vec3(s, "amplitude_mm", kMmToM);
  c.sinusoid.amplitude_rad = Vec3(s, "amplitude_deg", kDegToRad);
  const std::vector<double> periods = s.Numbers("period_s", 6);
  for (int i = 0; i < 6; ++i) {
    if (!(periods[i] > 0)) s.Fail("period_s", "expected six positive periods");
    c.sinusoid.period_s[i] = periods[i];
  }
  c.sinusoid.ramp_s = s.NumberInRange("ramp_s", 0, 1000);

  const ConfigNode r = root.Child("reduction");
  c.reduction.shortening_m = r.NumberInRange("shortening_mm", 0, 100) * kMmToM;
  c.reduction.lateral_m = r.NumberInRange("lateral_mm", -100, 100) * kMmToM;
  c.reduction.angulation_rad = r.NumberInRange("angulation_deg", -30, 30) * kDegToRad;
  c.reduction.rotation_rad = r.NumberInRange("rotation_deg", -45, 45) * kDegToRad;
  c.reduction.clearance_m = r.NumberInRange("clearance_mm", 0, 100) * kMmToM;
  c.reduction.final_gap_m = r.NumberInRange("final_gap_mm", 0, 50) * kMmToM;
  const std::vector<double> fr = r.Numbers("phase_fractions", 3);
  double sum = 0;
  for (int i = 0; i < 3; ++i) {
    if (!(fr[i] > 0)) r.Fail("phase_fractions", "expected three positive fractions");
    c.reduction.phase_fractions[i] = fr[i];
    sum += fr[i];
  }
  if (sum > 1.0 + 1e-12) r.Fail("phase_fractions", "the three fractions must sum to at most 1");
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  return c;
}

}  // namespace robossis::sim
