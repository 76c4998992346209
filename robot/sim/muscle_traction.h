#pragma once
// Muscle traction between the bone fragments: spring-damper lines (the thigh muscles, parallel to the femur,
// around it) from anchors on the proximal fragment (fixed in F) to anchors on the distal one (moving with M), and
// a torsional spring-damper about the femur axis (the soft-tissue envelope's resistance to derotation).
//
// Calibration: the rest lengths and the rest twist are set so that at a reference pose X_FM_ref the traction is
// `load_n` along the femur axis (pulling the distal fragment toward the proximal one) and `load_nm` about it
// (paper §I: up to 517 N and 74 N·m). Away from it, the stiffnesses of config.traction set how the loads change.
// Muscles pull only (a line's tension is clamped at zero when slack).
//
// Evaluate() is allocation-free and noexcept: it runs every physics step.

#include <vector>

#include <Eigen/Geometry>

#include "robot/sim/sim_config.h"
#include "src/core/pose.h"

namespace robossis::sim {

struct TractionSample {
  Vector6d wrench_P_F = Vector6d::Zero();  // [force; moment about P] on the distal fragment, in F
  double axial_force_n = 0;                // traction along -axis (positive = pulling the fragments together)
  double twist_torque_nm = 0;              // torque about the femur axis from the torsional element
  double twist_rad = 0;                    // twist of the distal fragment from the reference pose
};

class MuscleTraction {
 public:
  // axis_F: the femur axis (unit, from the proximal to the distal fragment); site_F: the fracture site on it;
  // X_FM_aligned: the ring pose at which the fragments are aligned (muscle lines parallel to the axis).
  MuscleTraction(const TractionConfig& config, const Eigen::Vector3d& axis_F, const Eigen::Vector3d& site_F,
                 const Eigen::Isometry3d& X_FM_aligned);

  // Sets the rest lengths so that the lines pull with load_n along the axis at X_FM_lines_ref, and the rest twist so
  // that the torsional element gives load_nm at orientation R_FM_twist_ref (twist is measured from there).
  // load_n, load_nm >= 0; zero disables that part of the load. twist_sign: the sense in which the muscles' rest
  // twist lies from the reference (the displaced rotation's sign). Throws std::invalid_argument on bad values.
  void Calibrate(const Eigen::Isometry3d& X_FM_lines_ref, const Eigen::Matrix3d& R_FM_twist_ref, double load_n,
                 double load_nm, double twist_sign = 1.0);

  TractionSample Evaluate(const Eigen::Isometry3d& X_FM, const Eigen::Vector3d& v_P_F,
                          const Eigen::Vector3d& w_F) const noexcept;

  int muscle_count() const { return static_cast<int>(anchors_proximal_F_.size()); }
  const Eigen::Vector3d& anchor_proximal_F(int k) const { return anchors_proximal_F_[k]; }
  Eigen::Vector3d anchor_distal_F(int k, const Eigen::Isometry3d& X_FM) const { return X_FM * anchors_distal_M_[k]; }

 private:
  TractionConfig config_;
  Eigen::Vector3d axis_F_;
  std::vector<Eigen::Vector3d> anchors_proximal_F_;
  std::vector<Eigen::Vector3d> anchors_distal_M_;
  std::vector<double> rest_length_m_;
  Eigen::Matrix3d R_ref_ = Eigen::Matrix3d::Identity();
  double rest_twist_rad_ = 0;
  double line_stiffness_ = 0;
  double line_damping_ = 0;
  bool enabled_lines_ = false;
  bool enabled_twist_ = false;
};

}  // namespace robossis::sim
