#pragma once
// A small dense quadratic program solved in fixed-size storage, for real-time ticks: the point of a polyhedron
// nearest a target,
//
//     minimise 0.5 * |y - y_target|^2   subject to   A y >= b   (one row per inequality),
//
// by the primal active-set method (Nocedal & Wright, Numerical Optimization, 2nd ed., Algorithm 16.3) started from
// a feasible point. Every iterate is feasible, so stopping early (the iteration cap) still returns a feasible point.
//
// Why a hand-written solver: Debian packages no C++ QP library (apt-cache search finds only R's quadprog); OSQP,
// qpOASES and eiquadprog would have to be vendored, and the general ones allocate on setup. The follower's guard
// solves 6 variables and 15 inequalities per tick; the equality subproblem is at most 6x6 and fits an Eigen
// fixed-size LDLT, so nothing allocates.

#include <array>
#include <cstdint>

#include <Eigen/Core>

namespace robossis::robot {

inline constexpr int kQpVariables = 6;
inline constexpr int kQpMaxConstraints = 16;

using QpVector = Eigen::Matrix<double, kQpVariables, 1>;

struct ProjectionQp {
  int num_constraints = 0;
  Eigen::Matrix<double, kQpMaxConstraints, kQpVariables> A = decltype(A)::Zero();
  Eigen::Matrix<double, kQpMaxConstraints, 1> b = decltype(b)::Zero();
};

enum class QpStatus : std::uint8_t {
  kOptimal,        // the KKT conditions hold
  kIterationCap,   // stopped early; the point is feasible but maybe not the nearest
  kStartInfeasible // the start violates some inequality: nothing was done
};
const char* ToString(QpStatus status);

struct QpResult {
  QpStatus status = QpStatus::kOptimal;
  QpVector y = QpVector::Zero();
  int iterations = 0;
  int active = 0;  // inequalities in the final working set
  std::array<std::int8_t, kQpMaxConstraints> is_active{};
};

// Solves the projection from the feasible start y_start. Tolerance `feasibility_tol` is the slack allowed on
// A y >= b (absolute, in the units of b). Allocation-free, noexcept.
QpResult SolveProjectionQp(const ProjectionQp& qp, const QpVector& y_target, const QpVector& y_start,
                           int max_iterations = 64, double feasibility_tol = 1e-12) noexcept;

}  // namespace robossis::robot
