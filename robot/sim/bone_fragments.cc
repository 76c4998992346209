#include "robot/sim/bone_fragments.h"

#include <stdexcept>

#include "src/core/units.h"

namespace robossis::sim {

BoneFragments BuildBoneFragments(const SimConfig& config, const robot::RsrModel& model) {
  const BoneConfig& bc = config.bone;
  const TriangleMesh femur = ReadStl(bc.mesh_file);
  CutMesh cut;
  try {
    cut = CutMeshAtZ(femur, bc.cut_z_mesh_m);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(bc.mesh_file.string() + " cut at bone.cut_z_mesh_m = " +
                             std::to_string(bc.cut_z_mesh_m) + ": " + e.what());
  }
  BoneFragments f;
  // The femur head (mesh +z) points to the fixed ring (F -z): turn the mesh half a turn about x, then move the cut
  // centroid onto the robot axis at the fracture site.
  f.fracture_site_F = Eigen::Vector3d(0, 0, bc.fracture_site_z_m);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()).toRotationMatrix();
  X.translation() = f.fracture_site_F - X.linear() * cut.cap_centroid;
  f.X_F_mesh = X;

  f.proximal_F = cut.above;  // mesh z above the cut: the head side
  f.proximal_F.Transform(X);
  TriangleMesh distal_F = cut.below;
  distal_F.Transform(X);

  const double zc = bc.fracture_site_z_m;
  f.proximal_hulls_F = SlabPointSets(f.proximal_F, zc - bc.contact_region_m, zc, bc.slab_height_m);
  std::vector<std::vector<Eigen::Vector3d>> distal_hulls_F =
      SlabPointSets(distal_F, zc, zc + bc.contact_region_m, bc.slab_height_m);

  const Eigen::Isometry3d X_MF = model.geometry().X_FM_home.inverse();
  f.distal_M = distal_F;
  f.distal_M.Transform(X_MF);
  for (auto& hull : distal_hulls_F) {
    for (Eigen::Vector3d& p : hull) p = X_MF * p;
  }
  f.distal_hulls_M = std::move(distal_hulls_F);
  f.distal_mass_M = CalcMassProperties(f.distal_M);
  if (!(f.distal_mass_M.volume_m3 > 0) || f.proximal_hulls_F.empty() || f.distal_hulls_M.empty()) {
    throw std::runtime_error(bc.mesh_file.string() + ": the cut fragments are empty or inside out");
  }
  return f;
}

std::string FragmentNotice(const SimConfig& config) {
  return "ALTERED VERSIONS of FemurR.stl (Bone Mesh Female Toolkit, Copyright (c) 2017 Manish Sreenivasa, Daniel "
         "Gonzalez Alvarado, Heidelberg University; zlib licence, see LICENSE_BMFToolkit.txt in data/femur/).\n"
         "fragment_proximal.stl and fragment_distal.stl were made by the Robossis workbench (robossis sim): the "
         "original mesh " + config.bone.mesh_file.filename().string() +
         " was cut at the plane z = " + std::to_string(config.bone.cut_z_mesh_m) +
         " m (mesh frame), each part closed with a flat cap face, and placed in the robot's fixed-ring frame F "
         "(proximal) and moving-ring frame M (distal). They are not the original software/data.\n";
}

}  // namespace robossis::sim
