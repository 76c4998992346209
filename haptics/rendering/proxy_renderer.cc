#include "haptics/rendering/proxy_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "haptics/rendering/boundary_probe.h"
#include "robot/rsr_kinematics.h"
#include "src/core/pose.h"

namespace robossis::haptics {

ProxyRenderer::ProxyRenderer(const robot::RsrModel& model, const HcToRsrMap& map, const WrenchLimits& limits,
                             double rate_hz, const WallLawParams& wall, const ProxyParams& proxy, const char* name)
    : HapticRenderer(model, map, limits, rate_hz), wall_(wall), params_(proxy), name_(name) {
  if (proxy.bisection_steps < 1 || proxy.max_slides < 1) {
    throw std::invalid_argument("proxy: bisection_steps and max_slides must be >= 1");
  }
  X_FP_ = model.geometry().X_FM_home;
}

void ProxyRenderer::ResetMethod(const Eigen::Isometry3d& X_OH) noexcept {
  const Eigen::Isometry3d X_FM = map_.ToRsr(X_OH);
  // Start on the HC if it is inside; otherwise at home, from where the first tick walks to the boundary.
  X_FP_ = robot::IsPoseFeasible(model_, X_FM) ? X_FM : model_.geometry().X_FM_home;
}

namespace {

// The step closest to `wanted` that does not move outward through any of the active boundary planes (inward unit
// normals n_i: n_i·Δ >= 0). A tiny convex QP solved exactly by enumerating the active subsets (at most 3 planes:
// face, edge, corner), as in Zilles & Salisbury's god-object.
Eigen::Vector3d ConstrainedStep(const Eigen::Vector3d& wanted, const std::array<Eigen::Vector3d, 3>& normals,
                                int count) noexcept {
  Eigen::Vector3d best = Eigen::Vector3d::Zero();  // the empty step is always allowed
  double best_cost = wanted.squaredNorm();
  for (int mask = 0; mask < (1 << count); ++mask) {
    Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
    int cols = 0;
    for (int i = 0; i < count; ++i) {
      if (mask & (1 << i)) N.col(cols++) = normals[i];
    }
    Eigen::Vector3d step = wanted;
    if (cols == 1) {
      step = wanted - N.col(0).dot(wanted) * N.col(0);
    } else if (cols == 2) {
      const Eigen::Matrix<double, 3, 2> A = N.leftCols<2>();
      const Eigen::Matrix2d G = A.transpose() * A;
      if (std::abs(G.determinant()) < 1e-10) continue;
      step = wanted - A * (G.inverse() * (A.transpose() * wanted));
    } else if (cols == 3) {
      if (std::abs(N.determinant()) < 1e-6) continue;
      step.setZero();
    }
    bool allowed = true;
    for (int i = 0; i < count; ++i) allowed = allowed && normals[i].dot(step) >= -1e-12;
    const double cost = (step - wanted).squaredNorm();
    if (allowed && cost < best_cost) {
      best = step;
      best_cost = cost;
    }
  }
  return best;
}

// Adds the unit normals (at the contact) of the limits violated just beyond it; keeps the newest three.
void AddViolatedNormals(const robot::RsrIkResult& beyond, const MarginGradients& g, std::array<Eigen::Vector3d, 3>& normals,
                        std::array<int, 3>& indices, int& count) noexcept {
  for (int i = 0; i < static_cast<int>(beyond.checks.size()); ++i) {
    if (beyond.checks[i].margin >= 0) continue;
    const double n = g.col(i).norm();
    if (!(n > 1e-12)) continue;
    bool known = false;
    for (int j = 0; j < count; ++j) {
      if (indices[j] == i) {
        normals[j] = g.col(i) / n;  // refresh at the new contact
        known = true;
      }
    }
    if (known) continue;
    if (count == 3) {
      normals[0] = normals[1], normals[1] = normals[2];
      indices[0] = indices[1], indices[1] = indices[2];
      count = 2;
    }
    normals[count] = g.col(i) / n;
    indices[count] = i;
    ++count;
  }
}

}  // namespace

void ProxyRenderer::MoveTranslation(const Eigen::Vector3d& p_target) noexcept {
  const Eigen::Matrix3d R = X_FP_.linear();
  Eigen::Vector3d p = X_FP_.translation();
  std::array<Eigen::Vector3d, 3> normals;
  std::array<int, 3> indices{};
  int count = 0;
  MarginGradients g;
  for (int slide = 0; slide < params_.max_slides; ++slide) {
    const Eigen::Vector3d step = ConstrainedStep(p_target - p, normals, count);
    if (step.squaredNorm() < 1e-20) break;
    const double s = BisectTranslation(model_, R, p, p + step, params_.bisection_steps);
    if (s >= 1.0) {
      p += step;
      break;
    }
    Eigen::Isometry3d X = X_FP_;
    if (count > 0 && s < 0.5) {
      // Sliding on a curved boundary: the tangent step leaves the workspace at once. Pull the stepped point back
      // along the active normals to the boundary (bisection), which follows the curvature.
      Eigen::Vector3d n_sum = Eigen::Vector3d::Zero();
      for (int i = 0; i < count; ++i) n_sum += normals[i];
      if (n_sum.squaredNorm() > 1e-12) {
        const Eigen::Vector3d q = p + step;
        const Eigen::Vector3d q_in = q + step.norm() * n_sum.normalized();
        X.translation() = q_in;
        if (robot::IsPoseFeasible(model_, X)) {
          const double t = BisectTranslation(model_, R, q_in, q, params_.bisection_steps);
          X.translation() = q_in + std::min(1.0, t + std::ldexp(1.0, -params_.bisection_steps)) * (q - q_in);
          const robot::RsrIkResult beyond = robot::CalcInverseKinematics(model_, X);
          p = q_in + t * (q - q_in);
          X.translation() = p;
          AllMarginGradientsTranslation(model_, X, g);
          AddViolatedNormals(beyond, g, normals, indices, count);
          continue;
        }
      }
    }
    X.translation() = p + std::min(1.0, s + std::ldexp(1.0, -params_.bisection_steps)) * step;
    const robot::RsrIkResult beyond = robot::CalcInverseKinematics(model_, X);
    p += s * step;
    X.translation() = p;
    AllMarginGradientsTranslation(model_, X, g);
    AddViolatedNormals(beyond, g, normals, indices, count);
  }
  X_FP_.translation() = p;
}

void ProxyRenderer::MoveRotation(const Eigen::Matrix3d& R_target) noexcept {
  Eigen::Matrix3d R = X_FP_.linear();
  std::array<Eigen::Vector3d, 3> normals;
  std::array<int, 3> indices{};
  int count = 0;
  MarginGradients g;
  for (int slide = 0; slide < params_.max_slides; ++slide) {
    const Eigen::Vector3d step = ConstrainedStep(RotationVector(R_target * R.transpose()), normals, count);
    if (step.squaredNorm() < 1e-24) break;
    const double s = BisectRotation(model_, X_FP_.translation(), R, step, params_.bisection_steps);
    if (s >= 1.0) {
      R = RotationFromVector(step) * R;
      break;
    }
    Eigen::Isometry3d X = X_FP_;
    if (count > 0 && s < 0.5) {
      // Curved boundary: pull the stepped orientation back along the active normals (see MoveTranslation).
      Eigen::Vector3d n_sum = Eigen::Vector3d::Zero();
      for (int i = 0; i < count; ++i) n_sum += normals[i];
      if (n_sum.squaredNorm() > 1e-12) {
        const Eigen::Matrix3d Q = RotationFromVector(step) * R;
        const Eigen::Vector3d back = step.norm() * n_sum.normalized();
        const Eigen::Matrix3d Q_in = RotationFromVector(back) * Q;
        X.linear() = Q_in;
        if (robot::IsPoseFeasible(model_, X)) {
          // Bisect from Q_in (feasible) toward Q (outside) along the geodesic.
          const Eigen::Vector3d toward = RotationVector(Q * Q_in.transpose());
          const double t = BisectRotation(model_, X_FP_.translation(), Q_in, toward, params_.bisection_steps);
          X.linear() = RotationFromVector(std::min(1.0, t + std::ldexp(1.0, -params_.bisection_steps)) * toward) * Q_in;
          const robot::RsrIkResult beyond = robot::CalcInverseKinematics(model_, X);
          R = RotationFromVector(t * toward) * Q_in;
          X.linear() = R;
          AllMarginGradientsRotation(model_, X, g);
          AddViolatedNormals(beyond, g, normals, indices, count);
          continue;
        }
      }
    }
    X.linear() = RotationFromVector(std::min(1.0, s + std::ldexp(1.0, -params_.bisection_steps)) * step) * R;
    const robot::RsrIkResult beyond = robot::CalcInverseKinematics(model_, X);
    R = RotationFromVector(s * step) * R;
    X.linear() = R;
    AllMarginGradientsRotation(model_, X, g);
    AddViolatedNormals(beyond, g, normals, indices, count);
  }
  X_FP_.linear() = R;
}

HapticStatus ProxyRenderer::Render(const RsrSideState& state, Eigen::Vector3d& f_F, Eigen::Vector3d& tau_F) noexcept {
  if (!robot::IsPoseFeasible(model_, X_FP_)) X_FP_ = model_.geometry().X_FM_home;  // never expected; stay safe
  MoveTranslation(state.X_FM.translation());
  MoveRotation(state.X_FM.linear());
  const Eigen::Vector3d d_F = X_FP_.translation() - state.X_FM.translation();
  const Eigen::Vector3d theta_F = RotationVector(X_FP_.linear() * state.X_FM.linear().transpose());
  f_F = WallForce(wall_, d_F, state.v_F);        // eq. 18 with d = proxy − HC
  tau_F = WallTorque(wall_, theta_F, state.w_F);  // eq. 19 with θ = log(R_P R_HCᵀ)
  const bool contact = d_F.squaredNorm() > 1e-18 || theta_F.squaredNorm() > 1e-18;
  return contact ? HapticStatus::kContact : HapticStatus::kFree;
}

}  // namespace robossis::haptics
