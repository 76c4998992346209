#include "haptics/rendering/mesh_proxy_renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "haptics/rendering/boundary_probe.h"
#include "haptics/rendering/mesh_wall_renderer.h"
#include "robot/rsr_kinematics.h"
#include "src/core/pose.h"

namespace robossis::haptics {

MeshProxyRenderer::MeshProxyRenderer(const robot::RsrModel& model, const HcToRsrMap& map, const WrenchLimits& limits,
                                     double rate_hz, const WallLawParams& wall, const MeshProxyParams& params,
                                     std::shared_ptr<const geometry::BoundaryAtlas> atlas,
                                     std::shared_ptr<geometry::LiveBoundary> live, double simulated_latency_s,
                                     const char* name)
    : HapticRenderer(model, map, limits, rate_hz),
      wall_(wall),
      params_(params),
      atlas_(std::move(atlas)),
      live_(std::move(live)),
      name_(name),
      shaper_(wall.k_f_n_per_m, limits.max_force_n, 1.0 / rate_hz, params.force_rate) {
  if (!atlas_ && !live_) throw std::invalid_argument("mesh-proxy: needs a boundary atlas or a live boundary");
  if (params.bisection_steps < 1 || params.search_expansions < 1 || !(params.search_step_m > 0) ||
      !(params.search_step_rad > 0) || !(params.max_extra_step_m >= 0) || !(params.max_extra_step_rad >= 0) ||
      !(params.damping_fade_m >= 0) || !(params.damping_fade_rad >= 0) || !(params.max_direction_step_rad >= 0)) {
    throw std::invalid_argument(
        "mesh-proxy: bisection_steps and search_expansions must be >= 1, search steps > 0, extra steps and damping "
        "fades >= 0");
  }
  if (live_ && simulated_latency_s >= 0) {
    refresher_ = std::make_unique<geometry::SimulatedRefresher>(*live_, simulated_latency_s);
  }
  X_FP_ = model.geometry().X_FM_home;
}

void MeshProxyRenderer::StepSimulatedBackground(double now_s) {
  if (refresher_) refresher_->Step(now_s);
}

void MeshProxyRenderer::ResetMethod(const Eigen::Isometry3d& X_OH) noexcept {
  const Eigen::Isometry3d X_FM = map_.ToRsr(X_OH);
  X_FP_ = robot::IsPoseFeasible(model_, X_FM) ? X_FM : model_.geometry().X_FM_home;
  X_FM_previous_ = X_FM;
  translation_from_mesh_ = rotation_from_mesh_ = false;
  u_previous_.setZero();
  shaper_.Reset();
  have_margins_ = false;
  force_damping_weight_ = ContactDampingWeight(0.0, params_.damping_fade_m);
  torque_damping_weight_ = ContactDampingWeight(0.0, params_.damping_fade_rad);
}

void MeshProxyRenderer::SelectFields(const geometry::BoundaryDistanceField** dexterous,
                                     const geometry::BoundaryDistanceField** rotational) noexcept {
  const Eigen::Vector3d p = X_FP_.translation();
  const Eigen::Vector3d rpy = RpyFromRotation(X_FP_.linear());
  const geometry::LiveSlice* live_d = nullptr;
  const geometry::LiveSlice* live_r = nullptr;
  if (live_) {
    live_->PostPose(p, rpy);  // the refresher regenerates the slices around the proxy, not the HC
    live_d = live_->AcquireDexterous();
    live_r = live_->AcquireRotational();
  }
  const geometry::AtlasSlice* atlas_d = atlas_ ? atlas_->FindDexterous(rpy) : nullptr;
  const geometry::AtlasSlice* atlas_r = atlas_ ? atlas_->FindRotational(p) : nullptr;
  // For each family the slice made at the pose nearer to the proxy's.
  const bool use_live_d = live_d && (!atlas_d || (rpy - live_d->fixed).norm() <= (rpy - atlas_d->fixed).norm());
  const bool use_live_r = live_r && (!atlas_r || (p - live_r->fixed).norm() <= (p - atlas_r->fixed).norm());
  *dexterous = use_live_d ? live_d->field.get() : (atlas_d ? atlas_d->field.get() : nullptr);
  *rotational = use_live_r ? live_r->field.get() : (atlas_r ? atlas_r->field.get() : nullptr);
}

bool MeshProxyRenderer::MoveTranslation(const Eigen::Vector3d& p_HC,
                                        const geometry::BoundaryDistanceField* field) noexcept {
  const Eigen::Matrix3d R = X_FP_.linear();
  Eigen::Isometry3d X = X_FP_;
  X.translation() = p_HC;
  const Eigen::Vector3d u_previous = u_previous_;
  u_previous_.setZero();
  if (robot::IsPoseFeasible(model_, X)) {  // exact IK: free space, whatever the mesh says
    X_FP_.translation() = p_HC;
    return false;
  }
  if (field) {
    query_.QueryFields(field, nullptr, p_HC, Eigen::Vector3d::Zero(), 0.0, 0.0, &result_);
    const geometry::SignedDistanceResult& t = result_.translation;
    if (t.status == geometry::QueryStatus::kOk && t.normal.squaredNorm() > 0.5) {
      // Inward along the mesh's nearest-point direction; the mesh's depth is the first guess of the true one
      // (0 when the HC is inside the mesh but outside the true region: the face bulges out there).
      Eigen::Vector3d u = -t.normal;
      if (params_.max_direction_step_rad > 0 && u_previous.squaredNorm() > 0.5) {
        // Memory: turn from the last direction toward the mesh's by at most max_direction_step_rad.
        const double angle = std::acos(std::clamp(u_previous.dot(u), -1.0, 1.0));
        if (angle > params_.max_direction_step_rad) {
          const Eigen::Vector3d axis = u_previous.cross(u);
          if (axis.squaredNorm() > 1e-24) {
            u = Eigen::AngleAxisd(params_.max_direction_step_rad, axis.normalized()) * u_previous;
          }
        }
      }
      double reach = t.signed_distance < 0 ? -t.signed_distance : 0.0;
      const double mesh_depth = reach;
      double step = params_.search_step_m;
      for (int k = 0; k <= params_.search_expansions; ++k) {
        X.translation() = p_HC + reach * u;
        if (reach > 0 && robot::IsPoseFeasible(model_, X)) {
          const Eigen::Vector3d inside = X.translation();
          const double s = BisectTranslation(model_, R, inside, p_HC, params_.bisection_steps);
          const Eigen::Vector3d contact = inside + s * (p_HC - inside);  // on the TRUE boundary, along the mesh normal
          const Eigen::Vector3d p = X_FP_.translation();
          const double limit = (p_HC - X_FM_previous_.translation()).norm() + params_.max_extra_step_m;
          const double jump = (contact - p).norm();
          if (params_.max_extra_step_m > 0 && jump > limit) {
            // Toward the new contact by at most `limit`, staying feasible (p is).
            const Eigen::Vector3d p_try = p + (limit / jump) * (contact - p);
            X_FP_.translation() = p + BisectTranslation(model_, R, p, p_try, params_.bisection_steps) * (p_try - p);
          } else {
            X_FP_.translation() = contact;
          }
          u_previous_ = u;
          return true;
        }
        reach = mesh_depth + step;
        step *= 2;
      }
    }
  }
  // No usable slice: stop at the contact on the way from the proxy to the HC.
  const Eigen::Vector3d p = X_FP_.translation();
  const double s = BisectTranslation(model_, R, p, p_HC, params_.bisection_steps);
  X_FP_.translation() = p + s * (p_HC - p);
  return false;
}

bool MeshProxyRenderer::MoveRotation(const Eigen::Matrix3d& R_HC,
                                     const geometry::BoundaryDistanceField* field) noexcept {
  const Eigen::Vector3d p = X_FP_.translation();
  Eigen::Isometry3d X = X_FP_;
  X.linear() = R_HC;
  if (robot::IsPoseFeasible(model_, X)) {
    X_FP_.linear() = R_HC;
    return false;
  }
  if (field) {
    const Eigen::Vector3d rpy = RpyFromRotation(R_HC);
    query_.QueryFields(nullptr, field, p, rpy, 0.0, 0.0, &result_);
    const geometry::SignedDistanceResult& r = result_.rotation;
    const Eigen::Matrix3d E = RpyRateToAngularVelocity(rpy);  // ω = E · d(rpy)/dt
    if (r.status == geometry::QueryStatus::kOk && r.normal.squaredNorm() > 0.5 && std::abs(E.determinant()) > 1e-3) {
      // The RPY-space normal is a covector: in world rotation vectors the signed distance grows along −E⁻ᵀ·n at
      // the rate |E⁻ᵀ·n| per rad.
      const Eigen::Vector3d g = E.transpose().inverse() * r.normal;
      const double rate = g.norm();
      const Eigen::Vector3d u = -g / rate;
      double reach = r.signed_distance < 0 ? -r.signed_distance / rate : 0.0;
      const double mesh_depth = reach;
      double step = params_.search_step_rad;
      for (int k = 0; k <= params_.search_expansions; ++k) {
        const Eigen::Matrix3d R_in = RotationFromVector(reach * u) * R_HC;
        X.linear() = R_in;
        if (reach > 0 && robot::IsPoseFeasible(model_, X)) {
          const double s = BisectRotation(model_, p, R_in, -reach * u, params_.bisection_steps);
          const Eigen::Matrix3d contact = RotationFromVector(-s * reach * u) * R_in;  // on the TRUE boundary
          const Eigen::Matrix3d R = X_FP_.linear();
          const Eigen::Vector3d jump = RotationVector(contact * R.transpose());
          const double limit =
              RotationVector(R_HC * X_FM_previous_.linear().transpose()).norm() + params_.max_extra_step_rad;
          if (params_.max_extra_step_rad > 0 && jump.norm() > limit) {
            const Eigen::Vector3d toward = (limit / jump.norm()) * jump;
            const double t = BisectRotation(model_, p, R, toward, params_.bisection_steps);
            X_FP_.linear() = RotationFromVector(t * toward) * R;
          } else {
            X_FP_.linear() = contact;
          }
          return true;
        }
        reach = mesh_depth + step;
        step *= 2;
      }
    }
  }
  const Eigen::Matrix3d R = X_FP_.linear();
  const Eigen::Vector3d toward = RotationVector(R_HC * R.transpose());
  const double s = BisectRotation(model_, p, R, toward, params_.bisection_steps);
  X_FP_.linear() = RotationFromVector(s * toward) * R;
  return false;
}

double MeshProxyRenderer::EntryTime(const robot::RsrIkResult& ik) noexcept {
  // The pose is inside when every joint-limit margin is >= 0 (the coupled workspace as it is: position and
  // orientation together). Each violated margin closes at its rate since the last tick; the pose is inside when
  // the last of them has closed, or never if one of them is not closing.
  double entry_s = 0;
  for (std::size_t i = 0; i < ik.checks.size(); ++i) {
    const double margin = ik.checks[i].margin;
    if (margin < 0) {
      const double rate = have_margins_ ? (margin - margins_previous_[i]) / dt_ : 0.0;
      entry_s = rate > 0 ? std::max(entry_s, -margin / rate) : ForceRateShaper::kNever;
      if (!(rate > 0)) break;
    }
  }
  for (std::size_t i = 0; i < ik.checks.size(); ++i) margins_previous_[i] = ik.checks[i].margin;
  have_margins_ = true;
  return entry_s;
}

HapticStatus MeshProxyRenderer::Render(const RsrSideState& state, Eigen::Vector3d& f_F,
                                       Eigen::Vector3d& tau_F) noexcept {
  if (!robot::IsPoseFeasible(model_, X_FP_)) X_FP_ = model_.geometry().X_FM_home;  // never expected; stay safe
  const geometry::BoundaryDistanceField* dexterous = nullptr;
  const geometry::BoundaryDistanceField* rotational = nullptr;
  SelectFields(&dexterous, &rotational);
  const Eigen::Isometry3d X_before = X_FP_;
  translation_from_mesh_ = MoveTranslation(state.X_FM.translation(), dexterous);
  rotation_from_mesh_ = MoveRotation(state.X_FM.linear(), rotational);
  X_FM_previous_ = state.X_FM;
  // The exact IK is the final check: the proxy (the follower's set-point) never leaves the true region.
  if (!robot::IsPoseFeasible(model_, X_FP_)) X_FP_ = X_before;
  const Eigen::Vector3d d_F = X_FP_.translation() - state.X_FM.translation();
  const Eigen::Vector3d theta_F = RotationVector(X_FP_.linear() * state.X_FM.linear().transpose());
  // The damper in contact only, faded in with the depth (MeshProxyParams::damping_fade_m/rad).
  force_damping_weight_ = ContactDampingWeight(d_F.norm(), params_.damping_fade_m);
  torque_damping_weight_ = ContactDampingWeight(theta_F.norm(), params_.damping_fade_rad);
  WallLawParams law = wall_;
  law.c_f_ns_per_m *= force_damping_weight_;
  law.c_tau_nms_per_rad *= torque_damping_weight_;
  // eq. 18 with d = proxy − HC, through the force-rate shaper (eq. 18 itself when it is off).
  bool inside = false;
  double entry_s = ForceRateShaper::kNever;
  if (shaper_.enabled()) {
    const robot::RsrIkResult ik = robot::CalcInverseKinematics(model_, state.X_FM);
    inside = ik.feasible;
    entry_s = EntryTime(ik);
  }
  f_F = shaper_.Shape(state.X_FM.translation(), state.v_F, X_FP_.translation(), law.c_f_ns_per_m, inside, entry_s);
  if (wall_.c_f_ns_per_m > 0) force_damping_weight_ = shaper_.applied_damping_ns_per_m() / wall_.c_f_ns_per_m;
  tau_F = WallTorque(law, theta_F, state.w_F);  // eq. 19 with θ = log(R_P R_HCᵀ)
  const bool contact = d_F.squaredNorm() > 1e-18 || theta_F.squaredNorm() > 1e-18;
  return contact ? HapticStatus::kContact : HapticStatus::kFree;
}

}  // namespace robossis::haptics
