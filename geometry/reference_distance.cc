// Reference signed distance by ray casting and local minimisation.

#include "geometry/reference_distance.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace robossis::geometry {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Distance along unit direction d from q to the first feasibility change (inf if none within max_distance).
double RayCrossing(const FeasibilityFn& feasible, const Eigen::Vector3d& q, bool inside, const Eigen::Vector3d& d,
                   const ReferenceDistanceOptions& o) {
  double t_prev = 0;
  for (double t = o.march_step;; t += o.march_step) {
    const double t_eval = std::min(t, o.max_distance);
    if (feasible(q + t_eval * d) != inside) {
      double lo = t_prev, hi = t_eval;  // feasible(q + lo d) == inside, the other side at hi
      while (hi - lo > o.tolerance) {
        const double mid = 0.5 * (lo + hi);
        (feasible(q + mid * d) == inside ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    }
    if (t_eval >= o.max_distance) return kInf;
    t_prev = t_eval;
  }
}

}  // namespace

ReferenceDistanceResult ComputeReferenceSignedDistance(const FeasibilityFn& feasible, const Eigen::Vector3d& q,
                                                       const ReferenceDistanceOptions& o) {
  ReferenceDistanceResult out;
  out.inside = feasible(q);
  const int n = std::max(o.directions, 8);
  double best = kInf;
  Eigen::Vector3d best_dir = Eigen::Vector3d::UnitX();
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n;
    const double r = std::sqrt(1.0 - z * z);
    const Eigen::Vector3d d(r * std::cos(golden * i), r * std::sin(golden * i), z);
    const double t = RayCrossing(feasible, q, out.inside, d, o);
    if (t < best) {
      best = t;
      best_dir = d;
    }
  }
  if (!std::isfinite(best)) return out;
  // Local minimisation over the direction: pattern search in the tangent plane of best_dir.
  double step = std::sqrt(4.0 * std::numbers::pi / n);
  while (step > o.tolerance / std::max(best, o.tolerance)) {
    bool improved = false;
    const Eigen::Vector3d u = best_dir.unitOrthogonal(), v = best_dir.cross(u);
    for (const Eigen::Vector3d& delta : {Eigen::Vector3d(step * u), Eigen::Vector3d(-step * u),
                                         Eigen::Vector3d(step * v), Eigen::Vector3d(-step * v)}) {
      const Eigen::Vector3d d = (best_dir + delta).normalized();
      const double t = RayCrossing(feasible, q, out.inside, d, o);
      if (t < best) {
        best = t;
        best_dir = d;
        improved = true;
        break;
      }
    }
    if (!improved) step *= 0.5;
  }
  out.found = true;
  out.nearest = q + best * best_dir;
  out.signed_distance = out.inside ? best : -best;
  return out;
}

}  // namespace robossis::geometry
