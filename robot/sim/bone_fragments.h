#pragma once
// The two femur fragments of the simulation: FemurR.stl cut at mid-shaft (altered versions of the original, see
// data/femur/README.md), placed along the robot axis with the fracture site at bone.fracture_site_z_m. The
// proximal fragment is fixed in F; the distal one is fixed to the moving ring (frame M) and aligned with the
// proximal one when the ring is at the home pose.

#include <vector>

#include "robot/rsr_model.h"
#include "robot/sim/bone_mesh.h"
#include "robot/sim/sim_config.h"

namespace robossis::sim {

struct BoneFragments {
  TriangleMesh proximal_F;  // closed, in F
  TriangleMesh distal_M;    // closed, in M
  Eigen::Vector3d fracture_site_F = Eigen::Vector3d::Zero();  // cut centroid in F (ring at home)
  Eigen::Isometry3d X_F_mesh = Eigen::Isometry3d::Identity();   // original mesh frame → F
  MassProperties distal_mass_M;  // per unit density, in M
  // Convex collision pieces near the cut (point sets; their convex hulls collide).
  std::vector<std::vector<Eigen::Vector3d>> proximal_hulls_F;
  std::vector<std::vector<Eigen::Vector3d>> distal_hulls_M;
};

// Reads config.bone.mesh_file and builds both fragments. Throws std::runtime_error naming the mesh file.
BoneFragments BuildBoneFragments(const SimConfig& config, const robot::RsrModel& model);

// The notice that goes beside every written fragment (zlib licence, clause 2: altered versions marked plainly).
std::string FragmentNotice(const SimConfig& config);

}  // namespace robossis::sim
