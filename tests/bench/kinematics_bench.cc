// Per-call cost of the RSR and sigma.7 kinematics. The haptic tick (1 ms at 1 kHz, 0.25 ms at 4 kHz) runs
// thousands of feasibility checks; see BENCHMARKS.md.

#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "robot/rsr_kinematics.h"
#include "robot/sigma7_model.h"

namespace {

using namespace robossis;
using namespace robossis::robot;

// 1024 poses around home, cycled through so the branch predictor cannot learn one.
std::vector<Eigen::Isometry3d> Poses(const RsrModel& model) {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> p(-0.1, 0.1), a(-0.3, 0.3);
  std::vector<Eigen::Isometry3d> poses;
  while (poses.size() < 1024) {
    Eigen::Isometry3d X = model.geometry().X_FM_home;
    X.translation() += Eigen::Vector3d(p(gen), p(gen), 0.5 * p(gen));
    X.linear() = RotationFromRpy(Eigen::Vector3d(a(gen), a(gen), a(gen)));
    if (CalcInverseKinematics(model, X).feasible) poses.push_back(X);
  }
  return poses;
}

void BM_RsrInverseKinematics(benchmark::State& state) {
  const RsrModel model = RsrModel::Default();
  const auto poses = Poses(model);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(CalcInverseKinematics(model, poses[i++ & 1023]));
}
BENCHMARK(BM_RsrInverseKinematics);

void BM_RsrIsPoseFeasible(benchmark::State& state) {
  const RsrModel model = RsrModel::Default();
  const auto poses = Poses(model);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(IsPoseFeasible(model, poses[i++ & 1023]));
}
BENCHMARK(BM_RsrIsPoseFeasible);

void BM_RsrJacobian(benchmark::State& state) {
  const RsrModel model = RsrModel::Default();
  const auto poses = Poses(model);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(CalcJacobian(model, poses[i++ & 1023]));
}
BENCHMARK(BM_RsrJacobian);

// FK from the home pose (a cold start), and warm-started from a pose 1 mm / 0.1 deg away (a loop's case).
void BM_RsrForwardKinematics(benchmark::State& state) {
  const RsrModel model = RsrModel::Default();
  const auto poses = Poses(model);
  const bool warm = state.range(0) != 0;
  std::vector<RsrJointVector> q;
  std::vector<Eigen::Isometry3d> guesses;
  for (const auto& X : poses) {
    q.push_back(CalcInverseKinematics(model, X).joints.actuated());
    Eigen::Isometry3d guess = X;
    guess.translation() += Eigen::Vector3d(1e-3, 0, 0);
    guess.linear() = RotationFromRpy(Eigen::Vector3d(0, 0.00175, 0)) * X.linear();
    guesses.push_back(warm ? guess : model.geometry().X_FM_home);
  }
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ & 1023;
    benchmark::DoNotOptimize(CalcForwardKinematics(model, q[k], guesses[k]));
  }
}
BENCHMARK(BM_RsrForwardKinematics)->Arg(0)->Arg(1)->ArgName("warm");

void BM_Sigma7DeltaIk(benchmark::State& state) {
  const Sigma7Model model = Sigma7Model::Default();
  const Eigen::Vector3d p = model.p_center_O() + Eigen::Vector3d(0.01, -0.02, 0.015);
  for (auto _ : state) benchmark::DoNotOptimize(CalcDeltaInverseKinematics(model, p));
}
BENCHMARK(BM_Sigma7DeltaIk);

void BM_Sigma7DeltaFk(benchmark::State& state) {
  const Sigma7Model model = Sigma7Model::Default();
  const Eigen::Vector3d theta1 = CalcDeltaInverseKinematics(model, model.p_center_O()).joints.theta1;
  for (auto _ : state) benchmark::DoNotOptimize(CalcDeltaForwardKinematics(model, theta1));
}
BENCHMARK(BM_Sigma7DeltaFk);

}  // namespace
