#include "src/teleop/follower_passivity.h"

#include <algorithm>
#include <cmath>

namespace robossis::teleop {

double FollowerPassivity::StepShare(const Vector6d& step, const Vector6d& wrench_F, double budget_j) const noexcept {
  const double given = -wrench_F.dot(step);  // what the whole step would give the environment
  const double allowed = std::max(0.0, budget_j - energies_.out_j);
  if (given <= allowed) return 1.0;
  return allowed / given;  // given > allowed >= 0
}

void FollowerPassivity::Book(const Vector6d& wrench_F, const Vector6d& step) noexcept {
  const double e = wrench_F.dot(step);
  (e > 0 ? energies_.in_j : energies_.out_j) += std::abs(e);
}

}  // namespace robossis::teleop
