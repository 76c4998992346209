#pragma once
// Which nodes of one grid row of an RSR dexterous slice can be feasible: lets the grid sampling skip the nodes no
// arm can reach and test the others with the exact feasibility, so that the grid is the one testing every node gives.
//
// At the slice's orientation R_FM, arm i's leg is p − c_i with c_i = a_i − R_FM·b_i (eq. 5). A feasible leg is no
// longer than the stroke's maximum (a ball about c_i) and lies in the spherical joint's cone about the ring normal
// z_M (a cone with apex c_i). Along a grid row, p = (x, y, z) with y and z fixed, each is one interval of x (between
// the roots of a quadratic), and the row's feasible nodes lie in the intersection of the six intervals. The ball and
// the cone are taken slightly larger than the limits (kRowBoundSlack*), so that no rounding of the exact test can
// accept a node outside them, and the range of nodes is widened by one node at each end.

#include <array>

#include <Eigen/Core>

#include "robot/rsr_model.h"

namespace robossis::geometry {

// How much larger than the limits the bounds are: 1 µm of stroke and 1 µrad of cone, many orders of magnitude
// above the rounding of the exact test (about 1e-16 of the leg's 0.3 m) and far below a grid's spacing.
inline constexpr double kRowBoundSlackM = 1e-6;
inline constexpr double kRowBoundSlackRad = 1e-6;

class DexterousRowBounds {
 public:
  DexterousRowBounds(const robot::RsrModel& rsr, const Eigen::Matrix3d& R_FM);
  // For the row of nodes x0 + spacing·i (i in [0, n)) at (y, z): the index range [*first, *last] outside which no
  // node is feasible; false when no node of the row can be. Allocation-free.
  bool Candidates(double y, double z, double x0, double spacing, int n, int* first, int* last) const noexcept;

 private:
  std::array<Eigen::Vector3d, robot::kNumArms> c_F_{};  // apex of each arm's ball and cone
  Eigen::Vector3d z_M_ = Eigen::Vector3d::UnitZ();       // the moving ring's normal, in F
  double ball_sq_ = 0;                                   // (stroke_max + slack)²
  double cos_sq_ = 0;                                    // cos²(cone_max + slack)
};

}  // namespace robossis::geometry
