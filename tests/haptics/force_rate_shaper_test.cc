// The force-rate shaper: the displayed force changes by at most the rate, the attachment never puts energy into the
// hand that the coupling has not dissipated, and a leaving hand finds no force inside the region.

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "haptics/rendering/force_rate_shaper.h"
#include "tests/support/alloc_counter.h"

namespace robossis::haptics {
namespace {

constexpr double kStiffness = 2000;  // N/m, the paper's k_f
constexpr double kCap = 15;          // N
constexpr double kDt = 1e-3;         // 1 kHz

ForceRateShaperParams On() {
  ForceRateShaperParams p;
  p.max_rate_n_per_s = 500;  // 0.5 N per tick
  p.free_space_force_n = 0.5;
  p.exit_speed_margin = 2;
  return p;
}

// The wall x <= 0: the target attachment is the hand's projection on it (the proxy), inside when x <= 0.
Eigen::Vector3d Proxy(const Eigen::Vector3d& p) { return Eigen::Vector3d(std::min(p.x(), 0.0), p.y(), p.z()); }

// The saturated spring's stored energy, written out independently of the shaper.
double Potential(double offset_m) {
  const double r_s = kCap / kStiffness;
  return offset_m <= r_s ? 0.5 * kStiffness * offset_m * offset_m
                         : kCap * (offset_m - r_s) + 0.5 * kStiffness * r_s * r_s;
}

// When the hand is back inside the wall x <= 0 at its velocity (first order).
double EntryTime(const Eigen::Vector3d& p, const Eigen::Vector3d& v) {
  if (p.x() <= 0) return 0;
  return v.x() < 0 ? p.x() / -v.x() : ForceRateShaper::kNever;
}

// Drives the shaper along `path` (hand positions, one per tick) against the wall above. Returns the displayed forces
// and checks on every tick that moving the attachment put in no energy beyond what the coupling had dissipated
// before in the same contact (the slider's and the damper's running balance).
std::vector<Eigen::Vector3d> Drive(ForceRateShaper& shaper, const std::vector<Eigen::Vector3d>& path) {
  std::vector<Eigen::Vector3d> forces;
  double injected_j = 0;  // Σ energy added by moving the attachment at a fixed hand position
  Eigen::Vector3d q_before = Eigen::Vector3d::Zero();
  bool first = true;
  for (std::size_t k = 0; k < path.size(); ++k) {
    const Eigen::Vector3d& p = path[k];
    const Eigen::Vector3d v = k == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d((p - path[k - 1]) / kDt);
    const Eigen::Vector3d f = shaper.Shape(p, v, Proxy(p), 0.0, p.x() <= 0, EntryTime(p, v));
    if (!first) {
      injected_j += Potential((shaper.attachment() - p).norm()) - Potential((q_before - p).norm());
      EXPECT_LE(injected_j, 1e-12) << "tick " << forces.size();
    }
    // What the damper (the shaper's stronger one included) dissipates over the tick may pay later.
    injected_j -= shaper.applied_damping_ns_per_m() * v.squaredNorm() * kDt;
    if (p.x() <= 0 && f.norm() == 0) injected_j = 0;  // a contact ends
    first = false;
    q_before = shaper.attachment();
    forces.push_back(f);
  }
  return forces;
}

double LargestStep(const std::vector<Eigen::Vector3d>& forces) {
  double worst = 0;
  for (std::size_t k = 1; k < forces.size(); ++k) worst = std::max(worst, (forces[k] - forces[k - 1]).norm());
  return worst;
}

// Along x from x0 at speed v (m/s) for n ticks.
void Line(std::vector<Eigen::Vector3d>& path, double v, int n) {
  for (int k = 0; k < n; ++k) path.push_back(path.back() + Eigen::Vector3d(v * kDt, 0, 0));
}

TEST(ForceRateShaper, OffItIsTheCouplingSpringItself) {
  ForceRateShaper shaper(kStiffness, kCap, kDt, ForceRateShaperParams{});
  EXPECT_FALSE(shaper.enabled());
  const Eigen::Vector3d p(0.02, 0, 0);
  const Eigen::Vector3d f =
      shaper.Shape(p, Eigen::Vector3d(0.1, 0.2, 0), Proxy(p), 10, false, ForceRateShaper::kNever);
  // eq. 18, unsaturated (the renderer saturates the whole wrench)
  EXPECT_TRUE(f.isApprox(Eigen::Vector3d(-41, -2, 0))) << f.transpose();
}

TEST(ForceRateShaper, AFastHandEntersAndStaysWithoutAStepAboveTheRate) {
  // 830 mm/s into the wall (1.66 N per tick for the bare spring), 25 mm deep, held there, then out at 300 mm/s.
  std::vector<Eigen::Vector3d> path = {Eigen::Vector3d(-0.01, 0, 0)};
  Line(path, 0.83, 42);
  Line(path, 0, 500);
  Line(path, -0.3, 200);
  ForceRateShaper shaper(kStiffness, kCap, kDt, On());
  const std::vector<Eigen::Vector3d> forces = Drive(shaper, path);
  EXPECT_LE(LargestStep(forces), 0.5 + 1e-9);
  // The wall is felt: the force points back inside and reaches the cap while held.
  EXPECT_NEAR(forces[42 + 400].x(), -kCap, 1e-6);
  for (std::size_t k = 0; k < path.size(); ++k) {
    EXPECT_LE(forces[k].x(), 1e-12) << k;  // never pulls the hand out of the region
    if (path[k].x() <= 0) {
      EXPECT_LE(forces[k].norm(), 0.5 + 1e-9) << k;  // no phantom wall inside
    }
  }
}

TEST(ForceRateShaper, ASlowPushIsThePlainSpring) {
  // 10 mm/s: the spring changes by 0.02 N per tick, far below the rate: the shaper displays the target.
  std::vector<Eigen::Vector3d> path = {Eigen::Vector3d(-0.002, 0, 0)};
  Line(path, 0.01, 1000);
  ForceRateShaper shaper(kStiffness, kCap, kDt, On());
  const std::vector<Eigen::Vector3d> forces = Drive(shaper, path);
  for (std::size_t k = 0; k < path.size(); ++k) {
    Eigen::Vector3d spring = kStiffness * (Proxy(path[k]) - path[k]);
    if (spring.norm() > kCap) spring *= kCap / spring.norm();
    EXPECT_NEAR((forces[k] - spring).norm(), 0, 1e-9) << k;
  }
}

TEST(ForceRateShaper, AHandLeavingFastFindsTheForceUnloadedAtTheBoundary) {
  // Pushed in slowly to 40 mm (the force at the cap, no energy dissipated), then out at 400 mm/s: the force must
  // be gone where the hand crosses back, and it unloads within the rate on the way (depth / speed leaves time).
  std::vector<Eigen::Vector3d> path = {Eigen::Vector3d(-0.001, 0, 0)};
  Line(path, 0.01, 4100);
  Line(path, -0.4, 150);
  ForceRateShaper shaper(kStiffness, kCap, kDt, On());
  const std::vector<Eigen::Vector3d> forces = Drive(shaper, path);
  EXPECT_NEAR(forces[4100].x(), -kCap, 1e-6);
  EXPECT_LE(LargestStep(forces), 0.5 + 1e-9);
  for (std::size_t k = 0; k < path.size(); ++k) {
    if (path[k].x() <= 0) {
      EXPECT_LE(forces[k].norm(), 0.5 + 1e-9) << k;
    }
  }
}

TEST(ForceRateShaper, AReleasedTargetUnloadsWithinTheRate) {
  // The hand held 10 mm beyond; the target attachment jumps to the hand (a proxy released by the other family):
  // the force goes from 15 N to 0 in 0.5 N steps, never pushing the attachment out.
  ForceRateShaper shaper(kStiffness, kCap, kDt, On());
  const Eigen::Vector3d p(0.01, 0, 0);
  const Eigen::Vector3d still = Eigen::Vector3d::Zero();
  const double never = ForceRateShaper::kNever;
  Eigen::Vector3d previous = shaper.Shape(p, still, Proxy(p), 0.0, false, never);
  for (int k = 0; k < 5; ++k) previous = shaper.Shape(p, still, Proxy(p), 0.0, false, never);
  ASSERT_NEAR(previous.norm(), kCap, 1e-9);
  int ticks = 0;
  while (previous.norm() > 0 && ticks < 100) {
    const Eigen::Vector3d f = shaper.Shape(p, still, p, 0.0, false, never);
    EXPECT_LE((f - previous).norm(), 0.5 + 1e-9);
    previous = f;
    ++ticks;
  }
  EXPECT_EQ(ticks, 30);
}

TEST(ForceRateShaper, AHandStoppingShortKeepsItsDamperForceWithinTheRate) {
  // A hand pressing in at 210 mm/s against the spring and a damper of 15 N·s/m, then slowed to 30 mm/s in one tick
  // (the handle meeting the sigma.7's own stop): the damper's 3.15 N would drop to 0.45 N at once. The spring and
  // a stronger damper take up the step; the force then returns to the wall's own within the rate.
  ForceRateShaper shaper(kStiffness, kCap, kDt, On());
  std::vector<Eigen::Vector3d> path = {Eigen::Vector3d(0, 0, 0)}, velocity = {Eigen::Vector3d::Zero()};
  auto move = [&](double v, int n) {
    for (int k = 0; k < n; ++k) {
      velocity.push_back(Eigen::Vector3d(v, 0, 0));
      path.push_back(path.back() + kDt * velocity.back());
    }
  };
  for (int k = 1; k <= 30; ++k) move(0.21 * k / 30.0, 1);  // speeding up smoothly: the damper grows within the rate
  move(0.21, 5);
  move(0.03, 60);
  std::vector<Eigen::Vector3d> totals;
  for (std::size_t k = 0; k < path.size(); ++k) {
    totals.push_back(
        shaper.Shape(path[k], velocity[k], Proxy(path[k]), 15.0, false, EntryTime(path[k], velocity[k])));
  }
  EXPECT_LE(LargestStep(totals), 0.5 + 1e-9);
  const Eigen::Vector3d wall = -kStiffness * path.back() - 15.0 * velocity.back();
  EXPECT_NEAR((totals.back() - wall).norm(), 0, 1e-6) << totals.back().transpose() << " vs " << wall.transpose();
}

TEST(ForceRateShaper, RandomMotionNeverInjectsEnergy) {
  // A hand wandering in and out of the wall at up to 1 m/s: the attachment's balance is checked every tick
  // (Drive), and every force stays within the cap.
  std::vector<Eigen::Vector3d> path = {Eigen::Vector3d(-0.01, 0, 0)};
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  unsigned state = 12345;
  auto uniform = [&state] {
    state = state * 1664525u + 1013904223u;
    return (state >> 8) / 16777216.0 - 0.5;
  };
  for (int k = 0; k < 20000; ++k) {
    v += Eigen::Vector3d(uniform(), uniform(), uniform()) * 0.2 - 2.0 * kDt * path.back() / 0.0004;
    v = v.norm() > 1.0 ? v.normalized() : v;
    path.push_back(path.back() + v * kDt);
  }
  ForceRateShaper shaper(kStiffness, kCap, kDt, On());
  const std::vector<Eigen::Vector3d> forces = Drive(shaper, path);
  for (const Eigen::Vector3d& f : forces) EXPECT_LE(f.norm(), kCap + 1e-9);
  EXPECT_GE(shaper.tank_j(), 0);
}

TEST(ForceRateShaper, ShapeAllocatesNothing) {
  ForceRateShaper shaper(kStiffness, kCap, kDt, On());
  robossis::testing::AllocationCounter counter;
  Eigen::Vector3d p(-0.01, 0, 0);
  for (int k = 0; k < 1000; ++k) {
    p.x() += 0.0005 * std::sin(0.01 * k);
    shaper.Shape(p, Eigen::Vector3d::Zero(), Proxy(p), 0.0, p.x() <= 0, ForceRateShaper::kNever);
  }
  EXPECT_EQ(counter.count(), 0u);
}

TEST(ForceRateShaper, RefusesNonsensicalParameters) {
  ForceRateShaperParams bad = On();
  bad.exit_speed_margin = 0.5;
  EXPECT_THROW(ForceRateShaper(kStiffness, kCap, kDt, bad), std::invalid_argument);
  EXPECT_THROW(ForceRateShaper(0, kCap, kDt, On()), std::invalid_argument);
  bad = On();
  bad.max_rate_n_per_s = -1;
  EXPECT_THROW(ForceRateShaper(kStiffness, kCap, kDt, bad), std::invalid_argument);
}

}  // namespace
}  // namespace robossis::haptics
