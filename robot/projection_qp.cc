#include "robot/projection_qp.h"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

namespace robossis::robot {

const char* ToString(QpStatus status) {
  switch (status) {
    case QpStatus::kOptimal: return "optimal";
    case QpStatus::kIterationCap: return "iteration_cap";
    case QpStatus::kStartInfeasible: return "start_infeasible";
  }
  return "unknown";
}

namespace {

using Gram = Eigen::Matrix<double, kQpVariables, kQpVariables>;

// The equality subproblem on the working set W (rows `working[0..n)`): the point nearest y_target on
// {A_W y = b_W} is y_target + A_W^T lambda with (A_W A_W^T) lambda = b_W - A_W y_target. Unused rows of the 6x6
// system are padded with the identity so that one fixed-size LDLT serves every working-set size.
bool SolveOnWorkingSet(const ProjectionQp& qp, const std::array<int, kQpVariables>& working, int n,
                       const QpVector& rhs_point, QpVector& lambda) noexcept {
  Gram G = Gram::Identity();
  QpVector r = QpVector::Zero();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) G(i, j) = qp.A.row(working[i]).dot(qp.A.row(working[j]));
    r[i] = qp.b[working[i]] - qp.A.row(working[i]).dot(rhs_point);
  }
  const Eigen::LDLT<Gram> ldlt(G);
  if (ldlt.info() != Eigen::Success) return false;
  lambda = ldlt.solve(r);
  return lambda.allFinite();
}

}  // namespace

QpResult SolveProjectionQp(const ProjectionQp& qp, const QpVector& y_target, const QpVector& y_start,
                           int max_iterations, double feasibility_tol) noexcept {
  QpResult out;
  out.y = y_start;
  const int m = qp.num_constraints;
  for (int k = 0; k < m; ++k) {
    if (!(qp.A.row(k).dot(y_start) >= qp.b[k] - feasibility_tol)) {
      out.status = QpStatus::kStartInfeasible;
      return out;
    }
  }
  std::array<int, kQpVariables> working{};
  int n = 0;
  std::array<std::int8_t, kQpMaxConstraints> in_set{};
  // Directions shorter than this (relative to the problem's scale) count as "no step".
  const double step_tol = 1e-14 * (1.0 + y_target.norm() + y_start.norm());

  for (out.iterations = 0; out.iterations < max_iterations; ++out.iterations) {
    QpVector lambda = QpVector::Zero();
    if (!SolveOnWorkingSet(qp, working, n, y_target, lambda)) break;
    QpVector y_eq = y_target;
    for (int i = 0; i < n; ++i) y_eq += lambda[i] * qp.A.row(working[i]).transpose();
    const QpVector p = y_eq - out.y;

    if (p.norm() <= step_tol) {
      // At the subproblem's minimum: optimal if every multiplier is >= 0, else drop the most negative one.
      int drop = -1;
      double most_negative = 0.0;
      for (int i = 0; i < n; ++i) {
        if (lambda[i] < most_negative) {
          most_negative = lambda[i];
          drop = i;
        }
      }
      if (drop < 0) {
        out.status = QpStatus::kOptimal;
        out.active = n;
        out.is_active = in_set;
        return out;
      }
      in_set[working[drop]] = 0;
      working[drop] = working[n - 1];
      --n;
      continue;
    }

    // Step towards y_eq until the first inequality outside W blocks it. A blocking row is never in the span of
    // W's rows (those have A_W p = 0), so the working set stays linearly independent.
    double alpha = 1.0;
    int blocking = -1;
    for (int k = 0; k < m; ++k) {
      if (in_set[k]) continue;
      const double ap = qp.A.row(k).dot(p);
      if (ap >= -1e-15 * qp.A.row(k).norm() * p.norm()) continue;
      const double slack = qp.A.row(k).dot(out.y) - qp.b[k];
      const double a = std::max(slack, 0.0) / -ap;
      if (a < alpha) {
        alpha = a;
        blocking = k;
      }
    }
    out.y += alpha * p;
    if (blocking >= 0 && n < kQpVariables) {
      working[n++] = blocking;
      in_set[blocking] = 1;
    }
  }
  out.status = QpStatus::kIterationCap;
  out.active = n;
  out.is_active = in_set;
  return out;
}

}  // namespace robossis::robot
