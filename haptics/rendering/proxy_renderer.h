#pragma once
// Our method: a 6-DOF god-object (proxy) kept on the TRUE workspace boundary, coupled to the HC by the same
// spring-damper law (virtual coupling).
//
// The proxy pose X_P is always feasible. Each tick it moves toward the HC pose: first in translation (at the
// proxy's orientation), then in orientation (at the new position). If the straight move leaves the workspace, a
// bisection on IsPoseFeasible finds the contact point, the inward normal n is the gradient of the violated joint
// limit's margin there (the exact local normal of the true boundary). The next step is the one closest to the rest
// of the motion that does not cross any boundary plane met so far (a 3-plane QP solved exactly, as in Zilles &
// Salisbury's god-object), so the proxy slides along faces, edges (the RSR's ±x, ±y edges meet three spherical-cone
// limits at once) and corners; up to `max_slides` bisections per tick. The wrench is
//   F = k_f · (p_P − p_HC) − c_f · v_HC,   τ = k_τ · log(R_P · R_HCᵀ) − c_τ · ω_HC      (eq. 18–19, d = proxy offset)
// so in free space (proxy = HC) only the viscous term of Algorithm 1 remains, and in contact the spring points
// along the true boundary normal, grows continuously from zero at the boundary and needs no moving average.

#include "haptics/rendering/haptic_types.h"
#include "haptics/rendering/wall_law.h"

namespace robossis::haptics {

struct ProxyParams {
  int bisection_steps = 14;  // [assumed] resolution: segment length / 2^14 per tick
  int max_slides = 4;        // [assumed] bisections per tick (face, edge, corner, and one more)
};

class ProxyRenderer final : public HapticRenderer {
 public:
  ProxyRenderer(const robot::RsrModel& model, const HcToRsrMap& map, const WrenchLimits& limits, double rate_hz,
                const WallLawParams& wall, const ProxyParams& proxy, const char* name = "proxy");

  const char* name() const noexcept override { return name_; }
  const Eigen::Isometry3d& proxy_pose() const { return X_FP_; }
  const Eigen::Isometry3d* constrained_pose() const noexcept override { return &X_FP_; }

 protected:
  HapticStatus Render(const RsrSideState& state, Eigen::Vector3d& f_F, Eigen::Vector3d& tau_F) noexcept override;
  void ResetMethod(const Eigen::Isometry3d& X_OH) noexcept override;

 private:
  void MoveTranslation(const Eigen::Vector3d& p_goal) noexcept;
  void MoveRotation(const Eigen::Matrix3d& R_goal) noexcept;

  WallLawParams wall_;
  ProxyParams params_;
  const char* name_;
  Eigen::Isometry3d X_FP_ = Eigen::Isometry3d::Identity();  // proxy pose, always feasible
};

}  // namespace robossis::haptics
