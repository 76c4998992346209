#include "calibration/clock_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>

#include <Eigen/Dense>

#include "calibration/reference_curve.h"
#include "src/core/pose.h"

namespace robossis::calibration {

namespace {

// Parameters: right perturbations of X_FT (rotation, translation), of X_MB (rotation, translation), the offset at
// mid-take and the drift.
constexpr int kParams = 14;
constexpr int kOffset = 12, kDrift = 13;
using Vector14 = Eigen::Matrix<double, kParams, 1>;
using Matrix14 = Eigen::Matrix<double, kParams, kParams>;
using Vector6 = Eigen::Matrix<double, 6, 1>;
using Jacobian = Eigen::Matrix<double, 6, kParams>;

// Margin kept between the aligned frames and the reference's ends, so the frame set stays fixed while the fit moves
// the clock (assumption: the coarse offset is within a few ms of the fit's; 0.1 s is far beyond).
constexpr double kEndMarginS = 0.1;

using Params = ClockFitParameters;

struct Frame {
  double t_s;
  Eigen::Isometry3d X_TB;
  int segment;  // frames of one segment are consecutive, with no occlusion or exclusion between them
};

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

Eigen::Isometry3d Retract(const Eigen::Isometry3d& X, const Eigen::Vector3d& w, const Eigen::Vector3d& t) {
  Eigen::Isometry3d D = Eigen::Isometry3d::Identity();
  D.linear() = RotationFromVector(w);
  D.translation() = t;
  return X * D;
}

// Residual of one frame, tracked ring pose − reference at the aligned time (position m, rotation vector rad), and
// its Jacobian (first order in the residual rotation, which is ~1e-4 rad). False outside the reference.
bool Linearize(const ReferenceCurve& reference, const Params& x, double t_mid, const Frame& f, Vector6& r,
               Jacobian* J, ReferenceState* state_out = nullptr) {
  ReferenceState s;
  if (!reference.Evaluate(f.t_s + x.offset_mid_s + x.drift * (f.t_s - t_mid), s)) return false;
  const Eigen::Matrix3d R_BM = x.X_MB.linear().transpose();
  const Eigen::Vector3d u = R_BM * x.X_MB.translation();
  const Eigen::Matrix3d& R_TB = f.X_TB.linear();
  const Eigen::Vector3d p_TM = f.X_TB.translation() - R_TB * u;  // ring origin in the tracker frame
  const Eigen::Matrix3d& R_FT = x.X_FT.linear();
  const Eigen::Matrix3d R_FB = R_FT * R_TB;
  r.head<3>() = R_FT * p_TM + x.X_FT.translation() - s.p_FM;
  r.tail<3>() = RotationVector(R_FB * R_BM * s.R_FM.transpose());
  if (J) {
    J->setZero();
    J->block<3, 3>(0, 0) = -R_FT * Skew(p_TM);
    J->block<3, 3>(0, 3) = R_FT;
    J->block<3, 3>(3, 0) = R_FT;
    J->block<3, 3>(0, 6) = -R_FB * Skew(u);
    J->block<3, 3>(0, 9) = -R_FB;
    J->block<3, 3>(3, 6) = -R_FB;
    J->block<3, 1>(0, kOffset) = -s.v_FM;
    J->block<3, 1>(3, kOffset) = -s.w_FM;
    J->col(kDrift) = J->col(kOffset) * (f.t_s - t_mid);
  }
  if (state_out) *state_out = s;
  return true;
}

Params Apply(const Params& x, const Vector14& d) {
  Params y = x;
  y.X_FT = Retract(x.X_FT, d.segment<3>(0), d.segment<3>(3));
  y.X_MB = Retract(x.X_MB, d.segment<3>(6), d.segment<3>(9));
  y.offset_mid_s += d[kOffset];
  y.drift += d[kDrift];
  return y;
}

struct Whitening {
  double position_m = 1e-4, rotation_rad = 1e-3;
  void Apply(Vector6& r) const {
    r.head<3>() /= position_m;
    r.tail<3>() /= rotation_rad;
  }
  void Apply(Jacobian& J) const {
    J.topRows<3>() /= position_m;
    J.bottomRows<3>() /= rotation_rad;
  }
};

// Whitened cost Σ |W r|², and the normal equations when asked.
double Accumulate(const ReferenceCurve& reference, const std::vector<Frame>& frames, const Params& x, double t_mid,
                  const Whitening& w, Matrix14* A, Vector14* g) {
  double cost = 0;
  if (A) A->setZero();
  if (g) g->setZero();
  Vector6 r;
  Jacobian J;
  for (const Frame& f : frames) {
    if (!Linearize(reference, x, t_mid, f, r, A ? &J : nullptr)) {
      cost += 1e12;  // cannot happen inside the margin; makes a step that leaves the reference fail
      continue;
    }
    w.Apply(r);
    cost += r.squaredNorm();
    if (A) {
      w.Apply(J);
      A->noalias() += J.transpose() * J;
      g->noalias() += J.transpose() * r;
    }
  }
  return cost;
}

// Pseudo-inverse of a symmetric positive semi-definite matrix, in the Jacobi-scaled basis (parameters in m, rad
// and s have different scales).
Eigen::MatrixXd PseudoInverse(const Eigen::MatrixXd& A) {
  const Eigen::VectorXd d = A.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd M = d.asDiagonal() * A * d.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(M);
  const double cut = 1e-12 * std::max(1e-300, es.eigenvalues().cwiseAbs().maxCoeff());
  Eigen::VectorXd inv = es.eigenvalues();
  for (Eigen::Index i = 0; i < inv.size(); ++i) inv[i] = inv[i] > cut ? 1.0 / inv[i] : 0.0;
  return d.asDiagonal() * (es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose()) * d.asDiagonal();
}

// The free parameters' indices (drift only in the drift model).
std::vector<int> FreeParams(bool drift) {
  std::vector<int> p;
  for (int i = 0; i < (drift ? kParams : kParams - 1); ++i) p.push_back(i);
  return p;
}

Eigen::MatrixXd Sub(const Matrix14& A, const std::vector<int>& p) {
  Eigen::MatrixXd S(p.size(), p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = 0; j < p.size(); ++j) S(i, j) = A(p[i], p[j]);
  }
  return S;
}

Vector14 Expand(const Eigen::VectorXd& v, const std::vector<int>& p) {
  Vector14 out = Vector14::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) out[p[i]] = v[i];
  return out;
}

// Levenberg-Marquardt from x on the fixed frame set.
struct Fit {
  Params x;
  double cost = 0;
  int iterations = 0;
};

Fit Solve(const ReferenceCurve& reference, const std::vector<Frame>& frames, Params x, double t_mid,
          const Whitening& w, bool drift, int max_iterations) {
  const std::vector<int> p = FreeParams(drift);
  if (!drift) x.drift = 0;
  Matrix14 A;
  Vector14 g;
  double cost = Accumulate(reference, frames, x, t_mid, w, &A, &g);
  double lambda = 1e-4;
  Fit fit{x, cost, 0};
  for (int it = 0; it < max_iterations; ++it) {
    const Eigen::MatrixXd Ap = Sub(A, p);
    Eigen::VectorXd gp(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) gp[i] = g[p[i]];
    bool accepted = false;
    for (int tries = 0; tries < 12 && !accepted; ++tries) {
      Eigen::MatrixXd M = Ap;
      M.diagonal() += lambda * Ap.diagonal() + Eigen::VectorXd::Constant(Ap.rows(), 1e-12 * Ap.diagonal().maxCoeff());
      const Vector14 step = Expand(M.ldlt().solve(-gp), p);
      if (!step.allFinite()) break;
      const Params y = Apply(fit.x, step);
      const double c = Accumulate(reference, frames, y, t_mid, w, nullptr, nullptr);
      if (c <= fit.cost) {
        const double gain = fit.cost - c;
        fit.x = y;
        fit.cost = Accumulate(reference, frames, y, t_mid, w, &A, &g);
        lambda = std::max(1e-9, lambda / 10);
        accepted = true;
        fit.iterations = it + 1;
        // Converged when the cost no longer moves (relative 1e-10) or the offset step is below a nanosecond.
        if (gain <= 1e-10 * fit.cost || (std::abs(step[kOffset]) < 1e-9 && step.head<12>().norm() < 1e-10)) {
          return fit;
        }
      } else {
        lambda *= 10;
      }
    }
    if (!accepted) break;
  }
  return fit;
}

// Whitened Jacobians and residuals at a solution, summed per block, for the curvature and the bootstrap.
struct Linearization {
  Matrix14 A = Matrix14::Zero();
  std::vector<Matrix14> A_block;
  std::vector<Vector14> g_block;
  double block_s = 0;
};

Linearization Linearize(const ReferenceCurve& reference, const std::vector<Frame>& frames, const Params& x,
                        double t_mid, const Whitening& w, const ClockFitOptions& options, double frame_dt_s) {
  const std::size_t n = frames.size();
  std::vector<Jacobian> J(n);
  std::vector<Vector6> r(n);
  std::vector<double> score(n);  // the frame's contribution to the offset's gradient
  for (std::size_t i = 0; i < n; ++i) {
    Linearize(reference, x, t_mid, frames[i], r[i], &J[i]);
    w.Apply(r[i]);
    w.Apply(J[i]);
    score[i] = J[i].col(kOffset).dot(r[i]);
  }
  // Block length (frames): n^(1/3), and at least twice the lag where the score's autocorrelation falls below the
  // threshold (lags doubled until it does); at most n/10 so there are at least 10 blocks.
  double mean = 0, var = 0;
  for (double s : score) mean += s / static_cast<double>(n);
  for (double s : score) var += (s - mean) * (s - mean);
  std::size_t lag = 1;
  for (; lag < n / 10; lag *= 2) {
    double c = 0;
    for (std::size_t i = 0; i + lag < n; ++i) c += (score[i] - mean) * (score[i + lag] - mean);
    if (!(var > 0) || c / var < options.decorrelated_below) break;
  }
  const std::size_t length = std::clamp<std::size_t>(
      std::max<std::size_t>(static_cast<std::size_t>(std::ceil(std::cbrt(static_cast<double>(n)))), 2 * lag), 1,
      std::max<std::size_t>(1, n / 10));
  Linearization L;
  L.block_s = static_cast<double>(length) * frame_dt_s;
  std::size_t in_block = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i == 0 || in_block == length || frames[i].segment != frames[i - 1].segment) {
      L.A_block.push_back(Matrix14::Zero());
      L.g_block.push_back(Vector14::Zero());
      in_block = 0;
    }
    L.A_block.back().noalias() += J[i].transpose() * J[i];
    L.g_block.back().noalias() += J[i].transpose() * r[i];
    ++in_block;
  }
  for (const Matrix14& a : L.A_block) L.A += a;
  return L;
}

// Standard deviation of parameter k from the curvature (1/Schur complement over the other free parameters) and the
// share of its information the others do not take.
void Curvature(const Matrix14& A, const std::vector<int>& p, int k, double* sigma, double* share) {
  std::vector<int> others;
  for (int i : p) {
    if (i != k) others.push_back(i);
  }
  Eigen::VectorXd b(others.size());
  for (std::size_t i = 0; i < others.size(); ++i) b[i] = A(k, others[i]);
  const double schur = A(k, k) - b.dot(PseudoInverse(Sub(A, others)) * b);
  *sigma = schur > 0 ? 1.0 / std::sqrt(schur) : std::numeric_limits<double>::infinity();
  *share = A(k, k) > 0 ? std::max(0.0, schur) / A(k, k) : 0.0;
}

// Block bootstrap of the linearized fit: blocks drawn with replacement, one Gauss-Newton step from the solution.
// Returns the standard deviations of the offset and the drift (drift 0 when not free).
void Bootstrap(const Linearization& L, const std::vector<int>& p, const ClockFitOptions& options, double* sd_offset,
               double* sd_drift) {
  std::mt19937 gen(options.seed);
  std::uniform_int_distribution<std::size_t> pick(0, L.A_block.size() - 1);
  double s1 = 0, s2 = 0, d1 = 0, d2 = 0;
  const int B = std::max(2, options.bootstrap_replicates);
  for (int b = 0; b < B; ++b) {
    Matrix14 A = Matrix14::Zero();
    Vector14 g = Vector14::Zero();
    for (std::size_t k = 0; k < L.A_block.size(); ++k) {
      const std::size_t j = pick(gen);
      A += L.A_block[j];
      g += L.g_block[j];
    }
    // Fixed parameters (the drift in the offset-only model) get a unit diagonal and no gradient; a tiny ridge in
    // the Jacobi-scaled basis keeps directions the take does not excite (the marker offset without rotation) at 0.
    if (p.size() < kParams) {
      A.row(kDrift).setZero();
      A.col(kDrift).setZero();
      A(kDrift, kDrift) = 1;
      g[kDrift] = 0;
    }
    const Vector14 d = A.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    Matrix14 M = d.asDiagonal() * A * d.asDiagonal();
    M.diagonal().array() += 1e-12;
    const Vector14 step = -(d.asDiagonal() * M.ldlt().solve(d.asDiagonal() * g)).eval();
    s1 += step[kOffset];
    s2 += step[kOffset] * step[kOffset];
    d1 += step[kDrift];
    d2 += step[kDrift] * step[kDrift];
  }
  *sd_offset = std::sqrt(std::max(0.0, (s2 - s1 * s1 / B) / (B - 1)));
  *sd_drift = std::sqrt(std::max(0.0, (d2 - d1 * d1 / B) / (B - 1)));
}

}  // namespace

ClockFitParameters PerturbClockFitParameters(const ClockFitParameters& x, const Eigen::Matrix<double, 14, 1>& d) {
  return Apply(x, d);
}

bool ClockFitResidual(const ReferenceCurve& reference, const ClockFitParameters& x, double t_mid_s, double t_s,
                      const Eigen::Isometry3d& X_TB, Eigen::Matrix<double, 6, 1>& r, Eigen::Matrix<double, 6, 14>* J) {
  return Linearize(reference, x, t_mid_s, Frame{t_s, X_TB, 0}, r, J);
}

ClockFitResult FitClockAndRegistration(const RigidBodyTrack& track, const std::vector<std::uint8_t>& excluded,
                                       const PoseTrajectory& reference_trajectory, const HandEyeResult& start,
                                       const ClockModel& start_clock, const ClockFitOptions& options) {
  const ReferenceCurve reference(reference_trajectory);
  // The frames: present, not excluded, inside the reference (with a margin) at the starting clock.
  std::vector<std::size_t> usable;
  for (std::size_t i = 0; i < track.size(); ++i) {
    if (!track.present[i] || (!excluded.empty() && excluded[i])) continue;
    const double t = start_clock.ToReference(track.t_s[i]);
    if (t >= reference.t_front() + kEndMarginS && t <= reference.t_back() - kEndMarginS) usable.push_back(i);
  }
  if (usable.size() < 20) {
    throw std::runtime_error("clock fit: only " + std::to_string(usable.size()) +
                             " tracked frames fall inside the command log; at least 20 are needed");
  }
  const std::size_t stride = (usable.size() + options.max_frames - 1) / options.max_frames;
  std::vector<Frame> frames;
  int segment = 0;
  for (std::size_t k = 0; k < usable.size(); k += stride) {
    const std::size_t i = usable[k];
    // A new segment after an occlusion, an excluded frame or a frame-number jump.
    if (!frames.empty() && (usable[k] - usable[k - stride] != stride ||
                            track.frame[i] - track.frame[usable[k - stride]] != static_cast<std::int64_t>(stride))) {
      ++segment;
    }
    Eigen::Isometry3d X_TB = Eigen::Isometry3d::Identity();
    X_TB.linear() = track.q_TB[i].toRotationMatrix();
    X_TB.translation() = track.p_TB[i];
    frames.push_back({track.t_s[i], X_TB, segment});
  }
  const double frame_dt_s = static_cast<double>(stride) / track.rate_hz;
  ClockFitResult result;
  result.frames = frames.size();
  const double t_mid = 0.5 * (frames.front().t_s + frames.back().t_s);
  result.t_mid_s = t_mid;
  Params x0{start.X_FT, start.X_MB, start_clock.offset_s + start_clock.drift * t_mid, 0.0};

  // Whitening scales from the registration's residuals, then from the fit's own (per component RMS).
  Whitening w;
  w.position_m = std::max(start.rms_position_m / std::sqrt(3.0), 1e-7);
  w.rotation_rad = std::max(start.rms_rotation_rad / std::sqrt(3.0), 1e-7);
  Fit no_drift = Solve(reference, frames, x0, t_mid, w, false, options.max_iterations);
  {
    double sp = 0, sr = 0;
    Vector6 r;
    for (const Frame& f : frames) {
      if (!Linearize(reference, no_drift.x, t_mid, f, r, nullptr)) continue;
      sp += r.head<3>().squaredNorm();
      sr += r.tail<3>().squaredNorm();
    }
    const double n3 = 3.0 * static_cast<double>(frames.size());
    w.position_m = std::max(std::sqrt(sp / n3), 1e-9);
    w.rotation_rad = std::max(std::sqrt(sr / n3), 1e-9);
  }
  no_drift = Solve(reference, frames, no_drift.x, t_mid, w, false, options.max_iterations);
  result.sigma_position_m = w.position_m;
  result.sigma_rotation_rad = w.rotation_rad;
  result.iterations = no_drift.iterations;

  // The drift model, its interval, and BIC on the whitened residuals. The χ² difference is divided by the variance
  // inflation the block bootstrap finds for the drift (κ ≥ 1: correlated residuals carry less information than their
  // count), and the number of residuals by the same κ.
  const std::vector<int> p0 = FreeParams(false), p1 = FreeParams(true);
  Fit chosen = no_drift;
  Linearization L = Linearize(reference, frames, no_drift.x, t_mid, w, options, frame_dt_s);
  result.drift_considered = options.allow_drift;
  if (options.allow_drift) {
    const Fit with_drift = Solve(reference, frames, no_drift.x, t_mid, w, true, options.max_iterations);
    const Linearization L1 = Linearize(reference, frames, with_drift.x, t_mid, w, options, frame_dt_s);
    double sd_curv = 0, share = 0, sd_boot_offset = 0, sd_boot = 0;
    Curvature(L1.A, p1, kDrift, &sd_curv, &share);
    Bootstrap(L1, p1, options, &sd_boot_offset, &sd_boot);
    const double kappa = std::isfinite(sd_curv) && sd_curv > 0 ? std::max(1.0, std::pow(sd_boot / sd_curv, 2)) : 1.0;
    const double n_residuals = 6.0 * static_cast<double>(frames.size());
    result.delta_bic = (no_drift.cost - with_drift.cost) / kappa - std::log(n_residuals / kappa);
    const double u = std::max(sd_curv, sd_boot);
    result.drift = with_drift.x.drift;
    result.drift_ci[0] = result.drift - options.coverage_factor * u;
    result.drift_ci[1] = result.drift + options.coverage_factor * u;
    result.drift_bound = std::abs(result.drift) + options.coverage_factor * u;
    result.drift_selected = result.delta_bic > 0 && std::isfinite(u);
    if (result.drift_selected) {
      chosen = with_drift;
      L = L1;
      result.iterations += with_drift.iterations;
    }
  }
  const std::vector<int>& p = result.drift_selected ? p1 : p0;
  result.offset_mid_s = chosen.x.offset_mid_s;
  result.X_FT = chosen.x.X_FT;
  result.X_MB = chosen.x.X_MB;
  result.clock.drift = result.drift_selected ? chosen.x.drift : 0.0;
  result.clock.offset_s = chosen.x.offset_mid_s - result.clock.drift * t_mid;
  result.blocks = L.A_block.size();
  result.block_s = L.block_s;

  // The offset: curvature, bootstrap, bound, identifiability.
  double sd_drift_unused = 0;
  Curvature(L.A, p, kOffset, &result.offset_sigma_curvature_s, &result.offset_information_share);
  Bootstrap(L, p, options, &result.offset_sigma_bootstrap_s, &sd_drift_unused);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  result.crb_s = L.A(kOffset, kOffset) > 0 ? 1.0 / std::sqrt(L.A(kOffset, kOffset)) : kInf;
  // The interpolation: how far the offset would move if the reference were interpolated linearly instead (the
  // position residuals' change projected on the offset's direction).
  double sum_v2 = 0, shift_num = 0;
  {
    Vector6 r;
    ReferenceState s;
    for (const Frame& f : frames) {
      if (!Linearize(reference, chosen.x, t_mid, f, r, nullptr, &s)) continue;
      Eigen::Vector3d p_lin;
      reference.LinearPosition(f.t_s + chosen.x.offset_mid_s + chosen.x.drift * (f.t_s - t_mid), p_lin);
      sum_v2 += s.v_FM.squaredNorm();
      shift_num += s.v_FM.dot(p_lin - s.p_FM);
    }
  }
  result.crb_position_only_s = sum_v2 > 0 ? w.position_m / std::sqrt(sum_v2) : kInf;
  const double interpolation_shift = sum_v2 > 0 ? std::abs(shift_num) / sum_v2 : 0.0;
  const double u_a = std::max(result.offset_sigma_curvature_s, result.offset_sigma_bootstrap_s);
  const double u_interp = interpolation_shift / std::sqrt(3.0);
  result.budget = {
      {"tracker noise and residual motion error", "A", u_a,
       "the larger of the block bootstrap and the fit's curvature"},
      {"interpolation of the command log", "B", u_interp,
       "rectangular, half-width the shift to linear interpolation"},
      {"clock drift", "B", 0.0, "none at mid-take: the offset is referenced there, so the drift does not move it"},
      {"lag of the ring behind the command log", "B", 0.0,
       "part of the measurand: a commanded reference cannot separate it"},
  };
  const double u_c = std::sqrt(u_a * u_a + u_interp * u_interp);
  result.coverage_factor = options.coverage_factor;
  result.expanded_uncertainty_s = options.coverage_factor * u_c;
  result.identifiable = result.offset_information_share >= options.min_offset_information_share &&
                        std::isfinite(result.expanded_uncertainty_s);
  double half = result.expanded_uncertainty_s;
  if (!result.identifiable) {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "the motion does not fix the clock offset: only %.2g %% of its information is not shared with the "
                  "transforms (constant speed about one axis, or a ring standing still); the interval is the "
                  "search window",
                  100.0 * result.offset_information_share);
    result.warning = buf;
    half = std::max(std::isfinite(half) ? half : 0.0, options.unidentified_half_width_s);
  }
  result.offset_ci_s[0] = result.offset_mid_s - half;
  result.offset_ci_s[1] = result.offset_mid_s + half;
  return result;
}

}  // namespace robossis::calibration
