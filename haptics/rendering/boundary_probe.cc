#include "haptics/rendering/boundary_probe.h"

#include <algorithm>
#include <cmath>

#include "src/core/pose.h"

namespace robossis::haptics {

namespace {

Eigen::Isometry3d Translated(const Eigen::Isometry3d& X, const Eigen::Vector3d& dp) noexcept {
  Eigen::Isometry3d Y = X;
  Y.translation() += dp;
  return Y;
}

Eigen::Isometry3d Rotated(const Eigen::Isometry3d& X, const Eigen::Vector3d& e) noexcept {
  Eigen::Isometry3d Y = X;
  Y.linear() = RotationFromVector(e) * X.linear();
  return Y;
}

// Unit directions for the fallback search: the 26 neighbours of a cube.
struct Directions {
  Eigen::Vector3d dir[26];
  Directions() {
    int n = 0;
    for (int x = -1; x <= 1; ++x)
      for (int y = -1; y <= 1; ++y)
        for (int z = -1; z <= 1; ++z)
          if (x || y || z) dir[n++] = Eigen::Vector3d(x, y, z).normalized();
  }
};
const Directions& CubeDirections() noexcept {
  static const Directions d;
  return d;
}

template <typename Move>
double DirectionalSearch(const robot::RsrModel& model, const Eigen::Isometry3d& X, double cap, Move move) noexcept {
  double best = cap;
  const int kMarchSteps = 20;
  for (const Eigen::Vector3d& u : CubeDirections().dir) {
    double feasible_at = -1;
    double prev = 0;
    for (int k = 1; k <= kMarchSteps; ++k) {
      const double s = cap * k / kMarchSteps;
      if (s >= best) break;
      if (robot::IsPoseFeasible(model, move(X, s * u))) {
        feasible_at = s;
        break;
      }
      prev = s;
    }
    if (feasible_at < 0) continue;
    double lo = prev, hi = feasible_at;  // infeasible at lo, feasible at hi
    for (int k = 0; k < 20; ++k) {
      const double mid = 0.5 * (lo + hi);
      (robot::IsPoseFeasible(model, move(X, mid * u)) ? hi : lo) = mid;
    }
    if (hi < best) best = hi;
  }
  return best;
}

template <typename Move, typename Gradient>
double ProjectToFeasible(const robot::RsrModel& model, const Eigen::Isometry3d& X, double cap, Move move,
                         Gradient gradient) noexcept {
  if (robot::IsPoseFeasible(model, X)) return 0.0;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  for (int iteration = 0; iteration < 12; ++iteration) {
    const Eigen::Isometry3d Y = move(X, offset);
    const LimitMargin tight = TightestLimit(model, Y);
    if (tight.margin >= 0 && robot::IsPoseFeasible(model, Y)) {
      const double newton = offset.norm();
      // The Newton path is one feasible point; a shorter escape may exist (several active limits): take the better.
      const double searched = DirectionalSearch(model, X, std::min(cap, newton * 1.0000001), move);
      return std::min(newton, searched);
    }
    const Eigen::Vector3d g = gradient(Y, tight.index);
    const double g2 = g.squaredNorm();
    if (!(g2 > 1e-18)) break;
    // Step to the zero of the violated limit, plus a sliver so the pose lands strictly inside.
    offset += (-tight.margin / g2) * g + 1e-9 * g / std::sqrt(g2);
    if (offset.norm() > cap) break;
  }
  return DirectionalSearch(model, X, cap, move);
}

}  // namespace

LimitMargin TightestLimit(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM) noexcept {
  const robot::RsrIkResult ik = robot::CalcInverseKinematics(model, X_FM);
  LimitMargin out{0, ik.checks[0].margin};
  for (int i = 1; i < static_cast<int>(ik.checks.size()); ++i) {
    if (ik.checks[i].margin < out.margin) out = {i, ik.checks[i].margin};
  }
  return out;
}

double LimitMarginAt(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, int index) noexcept {
  return robot::CalcInverseKinematics(model, X_FM).checks[index].margin;
}

Eigen::Vector3d MarginGradientTranslation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, int index,
                                          double step_m) noexcept {
  Eigen::Vector3d g;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d dp = step_m * Eigen::Vector3d::Unit(k);
    g[k] = (LimitMarginAt(model, Translated(X_FM, dp), index) - LimitMarginAt(model, Translated(X_FM, -dp), index)) /
           (2 * step_m);
  }
  return g;
}

Eigen::Vector3d MarginGradientRotation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, int index,
                                       double step_rad) noexcept {
  Eigen::Vector3d g;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d de = step_rad * Eigen::Vector3d::Unit(k);
    g[k] = (LimitMarginAt(model, Rotated(X_FM, de), index) - LimitMarginAt(model, Rotated(X_FM, -de), index)) /
           (2 * step_rad);
  }
  return g;
}

namespace {
template <typename Move>
void AllGradients(const robot::RsrModel& model, const Eigen::Isometry3d& X, double step, MarginGradients& g,
                  Move move) noexcept {
  for (int k = 0; k < 3; ++k) {
    const robot::RsrIkResult plus = robot::CalcInverseKinematics(model, move(X, step * Eigen::Vector3d::Unit(k)));
    const robot::RsrIkResult minus = robot::CalcInverseKinematics(model, move(X, -step * Eigen::Vector3d::Unit(k)));
    for (int i = 0; i < g.cols(); ++i) g(k, i) = (plus.checks[i].margin - minus.checks[i].margin) / (2 * step);
  }
}

// Each limit's first-order signed distance s_i = margin_i / |grad margin_i| and unit inward normal; s_i = 1e300 for a
// limit with no gradient here. Returns the index of the tightest.
constexpr int kChecks = 3 * robot::kNumArms;
template <typename Move>
int LimitDistances(const robot::RsrModel& model, const Eigen::Isometry3d& X, double step, Move move,
                   double (&s)[kChecks], MarginGradients& unit) noexcept {
  const robot::RsrIkResult center = robot::CalcInverseKinematics(model, X);
  AllGradients(model, X, step, unit, move);
  int tightest = 0;
  for (int i = 0; i < kChecks; ++i) {
    const double n = unit.col(i).norm();
    s[i] = n > 1e-12 ? center.checks[i].margin / n : 1e300;
    if (n > 1e-12) unit.col(i) /= n;
    if (s[i] < s[tightest]) tightest = i;
  }
  return tightest;
}

template <typename Move>
Eigen::Vector3d SoftMinNormal(const robot::RsrModel& model, const Eigen::Isometry3d& X, double step, double blend,
                              Move move) noexcept {
  double s[kChecks];
  MarginGradients unit;
  const double s_min = s[LimitDistances(model, X, step, move, s, unit)];
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (int i = 0; i < kChecks; ++i) {
    if (s[i] >= 1e299) continue;
    normal += std::exp(-(s[i] - s_min) / blend) * unit.col(i);
  }
  const double n = normal.norm();
  return n > 1e-12 ? Eigen::Vector3d(normal / n) : Eigen::Vector3d::Zero();
}

template <typename Move>
bool IsNormalUnique(const robot::RsrModel& model, const Eigen::Isometry3d& X, double step, double edge_margin,
                    double crease_rad, Move move) noexcept {
  double s[kChecks];
  MarginGradients unit;
  const int tightest = LimitDistances(model, X, step, move, s, unit);
  if (s[tightest] >= 1e299) return false;
  const double cos_crease = std::cos(crease_rad);
  for (int i = 0; i < kChecks; ++i) {
    if (i == tightest || s[i] >= 1e299 || s[i] - s[tightest] >= edge_margin) continue;
    if (unit.col(i).dot(unit.col(tightest)) < cos_crease) return false;
  }
  return true;
}
}  // namespace

void AllMarginGradientsTranslation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, MarginGradients& g,
                                   double step_m) noexcept {
  AllGradients(model, X_FM, step_m, g,
               [](const Eigen::Isometry3d& X, const Eigen::Vector3d& d) { return Translated(X, d); });
}

void AllMarginGradientsRotation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, MarginGradients& g,
                                double step_rad) noexcept {
  AllGradients(model, X_FM, step_rad, g,
               [](const Eigen::Isometry3d& X, const Eigen::Vector3d& e) { return Rotated(X, e); });
}

Eigen::Vector3d InwardNormalTranslation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                                        double blend_m) noexcept {
  return SoftMinNormal(model, X_FM, 1e-6, blend_m,
                       [](const Eigen::Isometry3d& X, const Eigen::Vector3d& d) { return Translated(X, d); });
}

Eigen::Vector3d InwardNormalRotation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                                     double blend_rad) noexcept {
  return SoftMinNormal(model, X_FM, 1e-6, blend_rad,
                       [](const Eigen::Isometry3d& X, const Eigen::Vector3d& e) { return Rotated(X, e); });
}

bool IsNormalUniqueTranslation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, double edge_margin_m,
                               double crease_rad) noexcept {
  return IsNormalUnique(model, X_FM, 1e-6, edge_margin_m, crease_rad,
                        [](const Eigen::Isometry3d& X, const Eigen::Vector3d& d) { return Translated(X, d); });
}

bool IsNormalUniqueRotation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, double edge_margin_rad,
                            double crease_rad) noexcept {
  return IsNormalUnique(model, X_FM, 1e-6, edge_margin_rad, crease_rad,
                        [](const Eigen::Isometry3d& X, const Eigen::Vector3d& e) { return Rotated(X, e); });
}

double BisectTranslation(const robot::RsrModel& model, const Eigen::Matrix3d& R, const Eigen::Vector3d& p_from,
                         const Eigen::Vector3d& p_to, int steps) noexcept {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R;
  X.translation() = p_to;
  if (robot::IsPoseFeasible(model, X)) return 1.0;
  double lo = 0.0, hi = 1.0;
  for (int k = 0; k < steps; ++k) {
    const double mid = 0.5 * (lo + hi);
    X.translation() = p_from + mid * (p_to - p_from);
    (robot::IsPoseFeasible(model, X) ? lo : hi) = mid;
  }
  return lo;
}

double BisectRotation(const robot::RsrModel& model, const Eigen::Vector3d& p, const Eigen::Matrix3d& R_from,
                      const Eigen::Vector3d& rotvec, int steps) noexcept {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = p;
  X.linear() = RotationFromVector(rotvec) * R_from;
  if (robot::IsPoseFeasible(model, X)) return 1.0;
  double lo = 0.0, hi = 1.0;
  for (int k = 0; k < steps; ++k) {
    const double mid = 0.5 * (lo + hi);
    X.linear() = RotationFromVector(mid * rotvec) * R_from;
    (robot::IsPoseFeasible(model, X) ? lo : hi) = mid;
  }
  return lo;
}

double TranslationalPenetration(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, double cap_m) noexcept {
  return ProjectToFeasible(
      model, X_FM, cap_m, [](const Eigen::Isometry3d& X, const Eigen::Vector3d& d) { return Translated(X, d); },
      [&model](const Eigen::Isometry3d& Y, int index) { return MarginGradientTranslation(model, Y, index); });
}

double RotationalPenetration(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, double cap_rad) noexcept {
  return ProjectToFeasible(
      model, X_FM, cap_rad, [](const Eigen::Isometry3d& X, const Eigen::Vector3d& e) { return Rotated(X, e); },
      [&model](const Eigen::Isometry3d& Y, int index) { return MarginGradientRotation(model, Y, index); });
}

}  // namespace robossis::haptics
