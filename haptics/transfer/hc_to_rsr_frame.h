#pragma once
// The one HC → RSR frame map: how a hand motion in the HC base frame O becomes a motion of the moving ring in the
// RSR fixed frame F, and how a wrench the walls render in F is displayed on the hand in O. Its values have one
// place, transfer.yaml's `mapping` section (MappingConfig is this map plus the eq. 11 hygiene). The incremental
// mapping (eq. 10), the walls (haptics::HcToRsrMap, every renderer), the leader unit and the panel's view all go
// through these functions, so the set-points and the walls cannot disagree on a direction or a scale.
//
// The paper gives neither the rotation between the two bases nor a nominal scale: both are [assumed] values of
// transfer.yaml (identity and 1). A wrench is rotated back but not scaled: the wall is felt at the hand with the
// force it has in RSR space (the renderers' convention since the first walls).

#include <Eigen/Core>

namespace robossis::transfer {

struct HcToRsrFrame {
  // Rotation taking HC-base directions into RSR fixed-frame directions (R_FO). [assumed] identity.
  Eigen::Matrix3d R_FO = Eigen::Matrix3d::Identity();
  double translation_scale = 1.0;  // [assumed] nominal motion scaling before the dynamic scaling of eq. 11
  double rotation_scale = 1.0;     // [assumed]

  // eq. 10, the frame part: a hand displacement (or velocity) in O as the ring's in F.
  Eigen::Vector3d LinearToRsr(const Eigen::Vector3d& d_O) const noexcept { return translation_scale * (R_FO * d_O); }
  // eq. 10, the frame part: a handle rotation vector (or angular velocity) in O as the ring's in F.
  Eigen::Vector3d AngularToRsr(const Eigen::Vector3d& phi_O) const noexcept {
    return rotation_scale * (R_FO * phi_O);
  }
  // The inverses: a ring motion in F as the hand motion in O that commands it.
  Eigen::Vector3d LinearToHc(const Eigen::Vector3d& d_F) const noexcept {
    return (R_FO.transpose() * d_F) / translation_scale;
  }
  Eigen::Vector3d AngularToHc(const Eigen::Vector3d& phi_F) const noexcept {
    return (R_FO.transpose() * phi_F) / rotation_scale;
  }
  // A fixed-frame rotation increment of the handle (R_OH,new · R_OH,oldᵀ, in O) as the ring's (in F), and back.
  // At rotation_scale 1 it is the exact conjugation R_FO · dR · R_FOᵀ (no log near a half turn).
  Eigen::Matrix3d RotationToRsr(const Eigen::Matrix3d& dR_O) const noexcept;
  Eigen::Matrix3d RotationToHc(const Eigen::Matrix3d& dR_F) const noexcept;
  // A force or torque rendered in F as displayed on the hand in O (R_FOᵀ), and a hand-side wrench drawn in F.
  Eigen::Vector3d WrenchToHc(const Eigen::Vector3d& w_F) const noexcept { return R_FO.transpose() * w_F; }
  Eigen::Vector3d WrenchToRsr(const Eigen::Vector3d& w_O) const noexcept { return R_FO * w_O; }

  // Throws std::invalid_argument naming the transfer.yaml key when R_FO is not a proper rotation or a scale is not
  // a positive finite factor.
  void Validate() const;
};

}  // namespace robossis::transfer
