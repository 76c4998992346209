// The true boundary's normal is unique only off its edges: where two joint limits are equally near and their normals
// differ, the boundary has a cone of normals and the metrics must not score a direction against one of them.

#include <random>

#include <gtest/gtest.h>

#include "haptics/rendering/boundary_probe.h"
#include "src/core/units.h"
#include "test_util.h"

namespace robossis::haptics {
namespace {

using testing::Home;
using testing::Rsr;
using testing::Translated;

constexpr int kChecks = 3 * robot::kNumArms;

// First-order distances s_i = margin_i / |grad margin_i| and unit normals, from the public gradient API.
struct Limits {
  double s[kChecks];
  MarginGradients unit;
  int Nearest(int skip = -1) const {
    int best = skip == 0 ? 1 : 0;
    for (int i = 0; i < kChecks; ++i) {
      if (i != skip && s[i] < s[best]) best = i;
    }
    return best;
  }
};

Limits LimitsAt(const Eigen::Isometry3d& X) {
  Limits l;
  const robot::RsrIkResult ik = robot::CalcInverseKinematics(Rsr(), X);
  AllMarginGradientsTranslation(Rsr(), X, l.unit);
  for (int i = 0; i < kChecks; ++i) {
    const double n = l.unit.col(i).norm();
    l.s[i] = n > 1e-12 ? ik.checks[i].margin / n : 1e300;
    if (n > 1e-12) l.unit.col(i) /= n;
  }
  return l;
}

TEST(BoundaryProbe, NormalIsUniqueOnAFaceAndNotWhereTwoLimitsMeet) {
  // Rays from home in seeded random directions: where the nearest limit changes from i to j at an angle between
  // their normals above the crease, the normal is not unique; where the second-nearest limit is well beyond the edge
  // margin, it is.
  const double margin_m = 1e-3, crease = DegToRad(30);
  std::mt19937 gen{42};
  std::normal_distribution<double> normal;
  int edges = 0, faces = 0;
  for (int ray = 0; ray < 30; ++ray) {
    const Eigen::Vector3d u = Eigen::Vector3d(normal(gen), normal(gen), normal(gen)).normalized();
    auto at = [&](double t) { return Translated(Home(), t * u); };
    Limits prev = LimitsAt(at(0));
    for (double t = 1e-3; t <= 0.12; t += 1e-3) {
      const Limits here = LimitsAt(at(t));
      const int i = prev.Nearest(), j = here.Nearest();
      if (i != j && prev.unit.col(i).dot(here.unit.col(j)) < std::cos(crease + DegToRad(10))) {
        double lo = t - 1e-3, hi = t;  // s_i - s_j changes sign between lo and hi
        for (int k = 0; k < 40; ++k) {
          const double mid = 0.5 * (lo + hi);
          const Limits m = LimitsAt(at(mid));
          (m.s[i] - m.s[j] < 0 ? lo : hi) = mid;
        }
        EXPECT_FALSE(IsNormalUniqueTranslation(Rsr(), at(lo), margin_m, crease)) << "ray " << ray << " t " << lo;
        ++edges;
      }
      const int nearest = here.Nearest();
      // On a face: every limit within twice the edge margin of the nearest has the same normal (the RSR's three
      // arms can share one).
      bool face = true;
      for (int k = 0; k < kChecks; ++k) {
        face = face && (here.s[k] - here.s[nearest] > 2 * margin_m ||
                        here.unit.col(k).dot(here.unit.col(nearest)) > std::cos(DegToRad(5)));
      }
      if (face) {
        EXPECT_TRUE(IsNormalUniqueTranslation(Rsr(), at(t), margin_m, crease)) << "ray " << ray << " t " << t;
        ++faces;
      }
      prev = here;
    }
  }
  EXPECT_GT(edges, 3);  // the cases are exercised
  EXPECT_GT(faces, 100);
}

}  // namespace
}  // namespace robossis::haptics
