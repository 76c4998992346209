#pragma once
// The real-time rendering interface: one tick takes the haptic controller (HC) pose and velocity and returns the
// force and torque to display plus a status. Every renderer derives from HapticRenderer; Tick() is noexcept and
// allocation-free (tests/haptics/rendering_rt_test.cc proves it with AllocationCounter).
//
// Frames: O is the HC base (sigma.7), H the HC handle; F is the RSR fixed ring, M its moving ring. The HC pose is
// mapped to a commanded RSR pose X_FM by HcToRsrMap (eq. 10 with the nominal scales, through the one HC → RSR frame
// map of transfer.yaml); the walls live in RSR space; forces are rotated back and returned in O.

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "haptics/transfer/hc_to_rsr_frame.h"
#include "robot/rsr_model.h"

namespace robossis::haptics {

enum class HapticStatus : std::uint8_t {
  kFree,             // no wall: only the free-space viscous force
  kContact,          // a wall is rendered
  kDeepPenetration,  // the pose is so far outside that the method's own depth estimate is lost (bounded fallback)
  kFault,            // non-finite input: zero force and torque
};
const char* ToString(HapticStatus status);

// One HC sample (SI, in the HC base frame O).
struct HapticInput {
  Eigen::Isometry3d X_OH = Eigen::Isometry3d::Identity();  // handle pose
  Eigen::Vector3d v_O = Eigen::Vector3d::Zero();           // handle linear velocity (m/s)
  Eigen::Vector3d w_O = Eigen::Vector3d::Zero();           // handle angular velocity (rad/s)
};

struct HapticOutput {
  Eigen::Vector3d f_O = Eigen::Vector3d::Zero();    // force on the hand (N)
  Eigen::Vector3d tau_O = Eigen::Vector3d::Zero();  // torque on the hand (N·m)
  HapticStatus status = HapticStatus::kFree;
  bool saturated = false;  // the force or torque cap was reached this tick
};

// HC → RSR pose: eq. 10 summed from the anchor poses (the clutch) with the nominal scales, through the one frame
// map (R_FO and the scales: transfer.yaml `mapping`, hc_to_rsr_frame.h). The dynamic scaling of eq. 11 is the
// incremental mapping's (transfer::IncrementalMapper); this is the map the walls place the hand with.
//   p_FM = p_FM_anchor + s_t · R_FO · (p_OH − p_OH_anchor),   R_FM = frame(R_OH · R_OH_anchorᵀ) · R_FM_anchor
// where frame(dR) = R_FO · dR · R_FOᵀ at s_r = 1 (the rotation increment of the handle, in O, seen in F).
struct HcToRsrMap {
  Eigen::Isometry3d X_FM_anchor = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d X_OH_anchor = Eigen::Isometry3d::Identity();
  transfer::HcToRsrFrame frame;

  Eigen::Isometry3d ToRsr(const Eigen::Isometry3d& X_OH) const noexcept;
  Eigen::Isometry3d ToHc(const Eigen::Isometry3d& X_FM) const noexcept;
};

// The HC state expressed in RSR space: what the walls see.
struct RsrSideState {
  Eigen::Isometry3d X_FM = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_F = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_F = Eigen::Vector3d::Zero();
};

// Caps on the rendered wrench (paper §VI: 15 N and 0.3 N·m).
struct WrenchLimits {
  double max_force_n = 15.0;
  double max_torque_nm = 0.3;
};

// Time-domain passivity observer and controller (Ryu & Hannaford) on the rendered force and torque, one port each.
// The observer sums the energy the hand put into the wall, E(k) = E(k−1) − F_k·v_k·Δt (F on the hand, v the
// measured HC velocity); when E < 0 the wall has produced energy, and the controller adds the variable damper
// −α·v with α = −E/(Δt·|v|²) (capped) that dissipates exactly that deficit. E is reset to 0 in free space, so
// the free-space viscous force does not bank a reserve that would hide later wall activity (our choice).
struct PassivityParams {
  bool enabled = false;
  double max_damping_ns_per_m = 200.0;      // [assumed] cap on α for the force port
  double max_damping_nms_per_rad = 0.5;     // [assumed] cap on α for the torque port
};

class HapticRenderer {
 public:
  HapticRenderer(const robot::RsrModel& model, const HcToRsrMap& map, const WrenchLimits& limits, double rate_hz);
  virtual ~HapticRenderer() = default;
  HapticRenderer(const HapticRenderer&) = delete;
  HapticRenderer& operator=(const HapticRenderer&) = delete;

  // One haptic tick. Maps the HC state to RSR space, renders, saturates (keeping the direction) and returns the
  // status. A non-finite input or result gives zero force and kFault. Allocation-free, lock-free, noexcept.
  HapticStatus Tick(const HapticInput& input, HapticOutput& output) noexcept;
  // One haptic tick at an RSR pose given directly (the teleoperation leader maps the hand once, with the motion
  // transfer of eq. 10–12, and renders the walls at the pose the follower will be sent). `input` is the HC sample
  // the pose came from: its velocities reach F through the map's frame, as in Tick(), and drive the passivity
  // observer. The wrench is returned in O, as by Tick(). Same checks, saturation and status. Allocation-free.
  HapticStatus TickRsr(const Eigen::Isometry3d& X_FM, const HapticInput& input, HapticOutput& output) noexcept;

  // Forget the history (filters, proxy, passivity observer) and start from the HC pose X_OH. Allocation-free.
  void Reset(const Eigen::Isometry3d& X_OH) noexcept;
  virtual const char* name() const noexcept = 0;
  // The god-object's pose (X_FM, always inside the true workspace) for methods that keep one (proxy, mesh-proxy):
  // where the robot is sent while the hand is beyond a wall. nullptr for methods without one.
  virtual const Eigen::Isometry3d* constrained_pose() const noexcept { return nullptr; }

  // Re-clutch: new anchors, or the frame map (outside the tick; call Reset afterwards). The frame must be valid
  // (transfer::HcToRsrFrame::Validate, as the constructor checks).
  void SetMap(const HcToRsrMap& map) noexcept { map_ = map; }
  void SetPassivity(const PassivityParams& params) noexcept { passivity_ = params; }
  const PassivityParams& passivity() const { return passivity_; }
  // Observed energy on each port (J, >= 0 while the wall is passive) after the controller acted.
  double observed_energy_force_j() const { return energy_force_j_; }
  double observed_energy_torque_j() const { return energy_torque_j_; }

  const robot::RsrModel& model() const { return model_; }
  const HcToRsrMap& map() const { return map_; }
  double dt() const { return dt_; }

  // Simulation only, between ticks, NOT real-time: the background work the method needs that is due at simulated
  // time now_s (mesh-live: regenerating the live boundary slices with a modelled latency). A real leader process
  // runs that work on its own thread instead (geometry::LiveBoundary::Start); calling it here keeps runs
  // deterministic. Methods without background work ignore it.
  virtual void StepSimulatedBackground(double now_s) { (void)now_s; }

 protected:
  // The method proper: the wrench in RSR space (F), before the common saturation.
  virtual HapticStatus Render(const RsrSideState& state, Eigen::Vector3d& f_F, Eigen::Vector3d& tau_F) noexcept = 0;
  virtual void ResetMethod(const Eigen::Isometry3d& X_OH) noexcept = 0;
  // Render, check, saturate, rotate into O and apply the passivity controller (the common part of Tick and TickRsr).
  HapticStatus RenderState(const Eigen::Isometry3d& X_FM, const HapticInput& input, HapticOutput& output) noexcept;

  const robot::RsrModel& model_;
  HcToRsrMap map_;
  WrenchLimits limits_;
  double dt_;
  PassivityParams passivity_;
  double energy_force_j_ = 0;
  double energy_torque_j_ = 0;
};

// Scales v down to norm max_norm if longer; returns true if it did.
bool SaturateNorm(Eigen::Vector3d& v, double max_norm) noexcept;

}  // namespace robossis::haptics
