#include "haptics/rendering/mesh_wall_renderer.h"

#include <cmath>
#include <stdexcept>

#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::haptics {

Eigen::Matrix3d RpyRateToAngularVelocity(const Eigen::Vector3d& rpy) noexcept {
  const double cp = std::cos(rpy.y()), sp = std::sin(rpy.y());
  const double cy = std::cos(rpy.z()), sy = std::sin(rpy.z());
  Eigen::Matrix3d E;
  // ω = ẏ·z + Rz(y)·(ṗ·y + Ry(p)·(ṙ·x))
  E << cy * cp, -sy, 0,
       sy * cp, cy, 0,
       -sp, 0, 1;
  return E;
}

MeshWallRenderer::MeshWallRenderer(const robot::RsrModel& model, const HcToRsrMap& map, const WrenchLimits& limits,
                                   double rate_hz, const WallLawParams& wall, int moving_average_window,
                                   std::shared_ptr<const geometry::BoundaryAtlas> atlas, const char* name)
    : HapticRenderer(model, map, limits, rate_hz),
      wall_(wall),
      atlas_(std::move(atlas)),
      name_(name),
      filter_(moving_average_window) {
  // The walls act only outside the region: deep inside, the query need not find the nearest point (signed
  // distance ≥ the cutoff is all the law uses). [assumed] 5 mm / 2 deg, well beyond any tick's motion.
  query_.SetInsideCutoff(0.005, DegToRad(2));
  live_query_.SetInsideCutoff(0.005, DegToRad(2));
}

void SliceSwitchBlend::Reset() noexcept {
  remaining_ = 0;
  source_ = nullptr;
  offset_.setZero();
  last_.setZero();
}

Eigen::Vector3d SliceSwitchBlend::Apply(const void* source, const Eigen::Vector3d& in) noexcept {
  if (source != source_ && source_ != nullptr && ticks_ > 0) {
    offset_ = last_ - in;  // what the switch would add this tick
    remaining_ = ticks_;
  }
  source_ = source;
  Eigen::Vector3d out = in;
  if (remaining_ > 0) {
    out += offset_ * (static_cast<double>(remaining_) / ticks_);
    --remaining_;
  }
  last_ = out;
  return out;
}

void MeshWallRenderer::UseLiveBoundary(std::shared_ptr<geometry::LiveBoundary> live, double simulated_latency_s,
                                       double switch_blend_s) {
  if (!live) throw std::invalid_argument("mesh walls: no live boundary");
  if (!(std::isfinite(switch_blend_s) && switch_blend_s >= 0)) {
    throw std::invalid_argument("mesh walls: switch_blend_s must be a number >= 0");
  }
  translation_blend_.Configure(static_cast<int>(std::lround(switch_blend_s / dt())));
  rotation_blend_.Configure(static_cast<int>(std::lround(switch_blend_s / dt())));
  live_ = std::move(live);
  refresher_ = simulated_latency_s >= 0 ? std::make_unique<geometry::SimulatedRefresher>(*live_, simulated_latency_s)
                                        : nullptr;
}

void MeshWallRenderer::StepSimulatedBackground(double now_s) {
  if (refresher_) refresher_->Step(now_s);
}

void MeshWallRenderer::ResetMethod(const Eigen::Isometry3d&) noexcept {
  filter_.Reset();
  translation_blend_.Reset();
  rotation_blend_.Reset();
}

HapticStatus MeshWallRenderer::Render(const RsrSideState& state, Eigen::Vector3d& f_F,
                                      Eigen::Vector3d& tau_F) noexcept {
  if (live_) {
    live_query_.Query(*live_, atlas_.get(), state.X_FM, 0.0, 0.0, &result_);
  } else if (atlas_) {
    query_.Query(*atlas_, state.X_FM, 0.0, 0.0, &result_);
  } else {
    result_ = geometry::PoseBoundaryResult{};  // no boundary at all: kNoField below
  }
  HapticStatus status = HapticStatus::kFree;
  Eigen::Vector3d d_in = Eigen::Vector3d::Zero();
  Eigen::Vector3d theta_in = Eigen::Vector3d::Zero();
  const geometry::SignedDistanceResult& t = result_.translation;
  const geometry::SignedDistanceResult& r = result_.rotation;
  if (t.status != geometry::QueryStatus::kOk || r.status != geometry::QueryStatus::kOk) {
    status = HapticStatus::kDeepPenetration;
  }
  if (t.status == geometry::QueryStatus::kOk && t.signed_distance < 0) {
    d_in = t.signed_distance * t.normal;  // |s| along the inward normal −n_out
    if (status == HapticStatus::kFree) status = HapticStatus::kContact;
  }
  if (r.status == geometry::QueryStatus::kOk && r.signed_distance < 0) {
    const Eigen::Vector3d rpy = RpyFromRotation(state.X_FM.linear());
    theta_in = RpyRateToAngularVelocity(rpy) * (r.signed_distance * r.normal);
    if (status == HapticStatus::kFree) status = HapticStatus::kContact;
  }
  if (live_) {
    // The slice that answered each family: a live one, or the atlas node's.
    const void* translation_source = result_.live_dexterous_slice
                                         ? static_cast<const void*>(result_.live_dexterous_slice)
                                         : static_cast<const void*>(result_.dexterous_slice);
    const void* rotation_source = result_.live_rotational_slice
                                      ? static_cast<const void*>(result_.live_rotational_slice)
                                      : static_cast<const void*>(result_.rotational_slice);
    d_in = translation_blend_.Apply(translation_source, d_in);
    theta_in = rotation_blend_.Apply(rotation_source, theta_in);
  }
  Vector6d wrench;
  wrench.head<3>() = WallForce(wall_, d_in, state.v_F);        // eq. 18
  wrench.tail<3>() = WallTorque(wall_, theta_in, state.w_F);  // eq. 19
  const Vector6d filtered = filter_.Filter(wrench);
  f_F = filtered.head<3>();
  tau_F = filtered.tail<3>();
  return status;
}

}  // namespace robossis::haptics
