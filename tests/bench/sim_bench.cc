// Real-time factor of the Bullet simulation at its 1 kHz physics step (target: >= 10x real time on one
// core). The budget of one step is 1 ms; counters report the real-time factor (simulated s per CPU s). See
// BENCHMARKS.md.

#include <memory>

#include <benchmark/benchmark.h>

#include "robot/rsr_kinematics.h"
#include "robot/sim/rsr_simulation.h"
#include "robot/sim/scenario.h"
#include "src/core/config.h"

namespace {

using namespace robossis;
using namespace robossis::sim;

struct Data {
  robot::RsrModel model = robot::RsrModel::Default();
  SimConfig config = LoadSimConfig(DefaultDataDir() / "config" / "sim.yaml", DefaultDataDir());
  BoneFragments fragments = BuildBoneFragments(config, model);
};
const Data& D() {
  static const Data data;
  return data;
}

Eigen::Isometry3d Pose(double dz_m) {
  Eigen::Isometry3d X = D().model.geometry().X_FM_home;
  X.translation().z() += dz_m;
  return X;
}

void SetRate(benchmark::State& state, double step_s) {
  state.counters["realtime_factor"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * step_s, benchmark::Counter::kIsRate);
}

// One physics step (Command + Step + State through the follower interface) holding a loaded pose.
// Args: solver (0 = dantzig, 1 = pgs), bone and traction (0/1).
void BM_SimStepHold(benchmark::State& state) {
  SimConfig config = D().config;
  config.physics.solver = state.range(0) == 0 ? ConstraintSolverKind::kDantzig : ConstraintSolverKind::kPgs;
  const bool bone = state.range(1) != 0;
  const Eigen::Isometry3d X = Pose(0.03);
  MuscleTraction traction(config.traction, Eigen::Vector3d::UnitZ(), D().fragments.fracture_site_F,
                          D().model.geometry().X_FM_home);
  traction.Calibrate(X, X.linear(), 517, 74);
  SimOptions options;
  options.with_bone = bone;
  options.with_traction = bone;
  RsrSimulation sim(D().model, config, &D().fragments, &traction, X, options);
  robot::Follower& follower = sim;
  robot::RsrJointCommand cmd;
  cmd.q = robot::CalcInverseKinematics(D().model, X).joints.actuated();
  for (auto _ : state) {
    cmd.time_s = sim.time_s() + sim.step_s();
    follower.Command(cmd);
    benchmark::DoNotOptimize(sim.Step());
    benchmark::DoNotOptimize(follower.State());
  }
  SetRate(state, sim.step_s());
}
BENCHMARK(BM_SimStepHold)->ArgNames({"pgs", "bone"})->Args({0, 0})->Args({0, 1})->Args({1, 1});

// The fragments pressed together (contact active every step): the worst case of the collision pipeline.
void BM_SimStepContact(benchmark::State& state) {
  const Eigen::Isometry3d start = Pose(0.0);  // cut faces touching
  RsrSimulation sim(D().model, D().config, &D().fragments, nullptr, start);
  robot::RsrJointCommand cmd;
  cmd.q = robot::CalcInverseKinematics(D().model, Pose(-0.001)).joints.actuated();  // 1 mm into the bone
  for (auto _ : state) {
    cmd.time_s = sim.time_s() + sim.step_s();
    sim.Command(cmd);
    benchmark::DoNotOptimize(sim.Step());
  }
  state.counters["contact_points"] = sim.diagnostics().contact_points;
  SetRate(state, sim.step_s());
}
BENCHMARK(BM_SimStepContact);

// A whole scenario as the CLI runs it (IK + velocity feed-forward + step + error and statics bookkeeping +
// recording), 2 s of the loaded Fig. 7 sinusoid per iteration.
void BM_ScenarioSinusoidLoaded(benchmark::State& state) {
  ScenarioParams p;
  p.kind = ScenarioKind::kSinusoid;
  p.load_n = 517;
  p.load_nm = 74;
  p.duration_s = 2;
  for (auto _ : state) {
    benchmark::DoNotOptimize(RunScenario(D().model, D().config, D().fragments, p));
  }
  state.counters["realtime_factor"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * p.duration_s, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ScenarioSinusoidLoaded)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
