#include "calibration/registration.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>

#include "src/core/pose.h"

namespace robossis::calibration {

RigidFit FitRigidTransform(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to) {
  if (from.size() != to.size() || from.size() < 3) {
    throw std::invalid_argument("FitRigidTransform: need ≥ 3 matching points, got " + std::to_string(from.size()) +
                                " and " + std::to_string(to.size()));
  }
  Eigen::Matrix3Xd A(3, from.size()), B(3, to.size());
  for (std::size_t i = 0; i < from.size(); ++i) {
    A.col(static_cast<Eigen::Index>(i)) = from[i];
    B.col(static_cast<Eigen::Index>(i)) = to[i];
  }
  RigidFit fit;
  fit.X.matrix() = Eigen::umeyama(A, B, false);
  double sum = 0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    const double e = (fit.X * from[i] - to[i]).norm();
    sum += e * e;
    fit.max_m = std::max(fit.max_m, e);
  }
  fit.rms_m = std::sqrt(sum / static_cast<double>(from.size()));
  return fit;
}

namespace {

Eigen::Isometry3d Exp(const Eigen::Matrix<double, 6, 1>& d) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = RotationFromVector(d.head<3>());
  X.translation() = d.tail<3>();
  return X;
}

// Residual of one pair: predicted ring pose against the commanded one (position m, weighted rotation vector).
Eigen::Matrix<double, 6, 1> Residual(const Eigen::Isometry3d& X_FT, const Eigen::Isometry3d& X_MB_inv,
                                     const Eigen::Isometry3d& X_FM, const Eigen::Isometry3d& X_TB, double w) {
  const Eigen::Isometry3d pred = X_FT * X_TB * X_MB_inv;
  Eigen::Matrix<double, 6, 1> r;
  r.head<3>() = pred.translation() - X_FM.translation();
  r.tail<3>() = w * RotationVector(pred.linear() * X_FM.linear().transpose());
  return r;
}

// Second-largest principal spread of the orientations (rad): how well rotations about two axes are excited.
double RotationSpread(const std::vector<Eigen::Isometry3d>& X) {
  if (X.size() < 3) return 0;
  const Eigen::Matrix3d R0t = X.front().linear().transpose();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> w;
  for (const Eigen::Isometry3d& x : X) {
    w.push_back(RotationVector(R0t * x.linear()));
    mean += w.back();
  }
  mean /= static_cast<double>(w.size());
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& v : w) C += (v - mean) * (v - mean).transpose();
  C /= static_cast<double>(w.size());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
  return std::sqrt(std::max(0.0, es.eigenvalues()[1]));  // ascending: [1] is the middle one
}

}  // namespace

HandEyeResult CalibrateTrackerToBase(const std::vector<Eigen::Isometry3d>& X_FM_all,
                                     const std::vector<Eigen::Isometry3d>& X_TB_all, const HandEyeOptions& options) {
  if (X_FM_all.size() != X_TB_all.size() || X_FM_all.size() < 3) {
    throw std::invalid_argument("tracker-to-robot registration: need ≥ 3 paired poses, got " +
                                std::to_string(std::min(X_FM_all.size(), X_TB_all.size())));
  }
  std::vector<Eigen::Isometry3d> X_FM, X_TB;
  const std::size_t n_all = X_FM_all.size();
  const std::size_t n = std::min<std::size_t>(n_all, static_cast<std::size_t>(std::max(3, options.max_pairs)));
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = n == n_all ? k : k * (n_all - 1) / (n - 1);
    X_FM.push_back(X_FM_all[i]);
    X_TB.push_back(X_TB_all[i]);
  }
  HandEyeResult result;
  result.pairs = static_cast<int>(n_all);
  result.rotation_spread_rad = std::min(RotationSpread(X_FM), RotationSpread(X_TB));
  const double w = options.rotation_weight_m_per_rad;
  const bool rotation_excited = result.rotation_spread_rad >= options.min_rotation_spread_rad;
  if (rotation_excited) {
    // Closed-form start: OpenCV solves A_i X = Z B_i with A = cTw ("world2cam"), X = wTb, Z = cTg, B = gTb.
    // Here A_i = X_FM_i, X = X_MB, Z = X_FT, B_i = X_TB_i.
    std::vector<cv::Mat> R_A, t_A, R_B, t_B;
    const std::size_t m = std::min<std::size_t>(n, 400);
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t i = m == n ? k : k * (n - 1) / (m - 1);
      cv::Mat ra, ta, rb, tb;
      cv::eigen2cv(Eigen::Matrix3d(X_FM[i].linear()), ra);
      cv::eigen2cv(Eigen::Vector3d(X_FM[i].translation()), ta);
      cv::eigen2cv(Eigen::Matrix3d(X_TB[i].linear()), rb);
      cv::eigen2cv(Eigen::Vector3d(X_TB[i].translation()), tb);
      R_A.push_back(ra);
      t_A.push_back(ta);
      R_B.push_back(rb);
      t_B.push_back(tb);
    }
    cv::Mat R_X, t_X, R_Z, t_Z;
    cv::calibrateRobotWorldHandEye(R_A, t_A, R_B, t_B, R_X, t_X, R_Z, t_Z, cv::CALIB_ROBOT_WORLD_HAND_EYE_SHAH);
    Eigen::Matrix3d rx, rz;
    Eigen::Vector3d tx, tz;
    cv::cv2eigen(R_X, rx);
    cv::cv2eigen(t_X, tx);
    cv::cv2eigen(R_Z, rz);
    cv::cv2eigen(t_Z, tz);
    result.X_MB.linear() = Eigen::Quaterniond(rx).normalized().toRotationMatrix();
    result.X_MB.translation() = tx;
    result.X_FT.linear() = Eigen::Quaterniond(rz).normalized().toRotationMatrix();
    result.X_FT.translation() = tz;
    result.method = "robot-world-hand-eye (OpenCV, Shah) + Gauss-Newton";
  } else {
    // Too little rotation to separate the marker offset: fit positions only and attribute the offset's rotation
    // to X_MB (its translation is absorbed by X_FT while the orientation is constant).
    std::vector<Eigen::Vector3d> from, to;
    for (std::size_t i = 0; i < n; ++i) {
      from.push_back(X_TB[i].translation());
      to.push_back(X_FM[i].translation());
    }
    const RigidFit fit = FitRigidTransform(from, to);
    result.X_FT = fit.X;
    // X_MB = X_FM^-1 X_FT X_TB averaged over the rotation (first pair; rotation is nearly constant anyway).
    result.X_MB.linear() = (X_FM[0].linear().transpose() * fit.X.linear() * X_TB[0].linear());
    result.X_MB.linear() = Eigen::Quaterniond(result.X_MB.linear()).normalized().toRotationMatrix();
    result.X_MB.translation().setZero();
    result.method = "rigid fit of positions (rotation motion too small to separate the marker offset)";
  }

  // Gauss-Newton on all (sub-sampled) pairs; perturbations on the right: X ← X · exp(δ).
  const int nparams = rotation_excited ? 12 : 6;
  for (int iter = 0; iter < options.iterations; ++iter) {
    Eigen::MatrixXd JtJ = Eigen::MatrixXd::Zero(nparams, nparams);
    Eigen::VectorXd Jtr = Eigen::VectorXd::Zero(nparams);
    const Eigen::Isometry3d X_MB_inv = result.X_MB.inverse();
    const double h = 1e-7;
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Matrix<double, 6, 1> r0 = Residual(result.X_FT, X_MB_inv, X_FM[i], X_TB[i], w);
      Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, nparams);
      for (int k = 0; k < nparams; ++k) {
        Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
        d[k % 6] = h;
        const Eigen::Matrix<double, 6, 1> r1 =
            k < 6 ? Residual(result.X_FT * Exp(d), X_MB_inv, X_FM[i], X_TB[i], w)
                  : Residual(result.X_FT, (result.X_MB * Exp(d)).inverse(), X_FM[i], X_TB[i], w);
        J.col(k) = (r1 - r0) / h;
      }
      JtJ.noalias() += J.transpose() * J;
      Jtr.noalias() += J.transpose() * r0;
    }
    const Eigen::VectorXd step = JtJ.ldlt().solve(-Jtr);
    if (!step.allFinite()) break;
    result.X_FT = result.X_FT * Exp(step.head<6>());
    if (nparams == 12) result.X_MB = result.X_MB * Exp(step.tail<6>());
    if (step.norm() < 1e-12) break;
  }
  ComputeRegistrationResiduals(X_FM_all, X_TB_all, result);
  return result;
}

void ComputeRegistrationResiduals(const std::vector<Eigen::Isometry3d>& X_FM,
                                  const std::vector<Eigen::Isometry3d>& X_TB, HandEyeResult& result) {
  const Eigen::Isometry3d X_MB_inv = result.X_MB.inverse();
  double sp = 0, sr = 0;
  result.max_position_m = result.max_rotation_rad = 0;
  for (std::size_t i = 0; i < X_FM.size(); ++i) {
    const Eigen::Matrix<double, 6, 1> r = Residual(result.X_FT, X_MB_inv, X_FM[i], X_TB[i], 1.0);
    const double ep = r.head<3>().norm(), er = r.tail<3>().norm();
    sp += ep * ep;
    sr += er * er;
    result.max_position_m = std::max(result.max_position_m, ep);
    result.max_rotation_rad = std::max(result.max_rotation_rad, er);
  }
  const double n = static_cast<double>(std::max<std::size_t>(1, X_FM.size()));
  result.rms_position_m = std::sqrt(sp / n);
  result.rms_rotation_rad = std::sqrt(sr / n);
  result.pairs = static_cast<int>(X_FM.size());
}

}  // namespace robossis::calibration
