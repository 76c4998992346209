#pragma once
// Configuration of the Bullet simulation (data/config/sim.yaml). Every value the paper does not give is an
// assumption named in that file; the struct defaults here are only placeholders until loaded.

#include <array>
#include <filesystem>
#include <string>

#include <Eigen/Core>

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::sim {

enum class DriveMode { kPosition, kVelocity };
enum class ConstraintSolverKind { kPgs, kDantzig };

struct PhysicsConfig {
  double step_hz = 1000;
  ConstraintSolverKind solver = ConstraintSolverKind::kDantzig;
  int solver_iterations = 100;
  Eigen::Vector3d gravity_F_mps2 = Eigen::Vector3d(0, -9.81, 0);
  double command_extrapolation_max_s = 0.02;
  double step_s() const { return 1.0 / step_hz; }
};

struct MassConfig {
  double moving_ring_kg = 2.5;
  double moving_ring_radius_m = 0.22;
  double rotary_link_kg = 0.4;
  double rotary_link_radius_m = 0.03;
  double cylinder_kg = 1.5;
  double cylinder_length_m = 0.2;
  double cylinder_com_from_base_m = 0.1;
  double piston_kg = 0.5;
  double piston_length_m = 0.2;
  double piston_com_below_tip_m = 0.1;
  double link_radius_m = 0.02;
  double bone_density_kg_per_m3 = 1400;
};

struct ActuatorConfig {
  double linear_force_max_n = 1100;
  double rotary_torque_max_nm = 120;
  DriveMode mode = DriveMode::kPosition;
};

struct BoneConfig {
  std::filesystem::path mesh_file;  // absolute after loading
  double cut_z_mesh_m = -0.102;
  double fracture_site_z_m = 0.142;
  double contact_region_m = 0.08;
  double slab_height_m = 0.008;
  double collision_margin_m = 1e-4;
  double penetration_tolerance_m = 5e-4;
};

struct TractionConfig {
  int muscle_count = 6;
  double muscle_radius_m = 0.035;
  double anchor_distance_m = 0.12;
  double axial_stiffness_n_per_m = 20680;
  double torsional_stiffness_nm_per_rad = 282.6;
  double damping_n_s_per_m = 300;
  double torsional_damping_nm_s_per_rad = 28.6;
};

struct SinusoidConfig {
  Eigen::Vector3d center_offset_m = Eigen::Vector3d(0, 0, 0.03);
  Eigen::Vector3d amplitude_m = Eigen::Vector3d(0.02, 0.015, 0.005);
  Eigen::Vector3d amplitude_rad = Eigen::Vector3d::Zero();
  std::array<double, 6> period_s{20, 16, 12, 18, 14, 10};
  double ramp_s = 2;
};

struct ReductionConfig {
  double shortening_m = 0.02;
  double lateral_m = 0.034;
  double angulation_rad = 0;
  double rotation_rad = 0;
  double clearance_m = 0.008;
  double final_gap_m = 0.0005;
  std::array<double, 3> phase_fractions{0.3, 0.4, 0.2};
};

struct SimConfig {
  PhysicsConfig physics;
  MassConfig masses;
  ActuatorConfig actuators;
  BoneConfig bone;
  TractionConfig traction;
  SinusoidConfig sinusoid;
  ReductionConfig reduction;
  std::string source = "defaults";  // the file it came from, for error messages
};

// Loads and validates sim.yaml; relative mesh paths are resolved against data_dir. Throws std::runtime_error
// naming the file, the key and what was expected.
SimConfig LoadSimConfig(const std::filesystem::path& file, const std::filesystem::path& data_dir);
// The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
SimConfig LoadSimConfig(const ConfigNode& root, const std::filesystem::path& data_dir);

}  // namespace robossis::sim
