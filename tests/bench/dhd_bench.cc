// Read + write of one haptic tick through the Force Dimension SDK back end (haptics/device/dhd_device.h), against
// the fake SDK of tests/haptics/fake_dhd, as a share of a 4 kHz (250 µs) tick. The fake advances the simulated
// sigma.7 on every write, so its physics step alone is measured beside it: the back end's own cost is the
// difference (a real SDK's cost is the USB round trip instead, which only a real device can measure).
// Run: ROBOSSIS_DATA_DIR=data build/tests/bench/bench_dhd --benchmark_repetitions=3 --benchmark_report_aggregates_only=true

#include <algorithm>
#include <chrono>
#include <vector>

#include <benchmark/benchmark.h>

#include "haptics/device/device_sim.h"
#include "haptics/device/dhd_device.h"
#include "robot/sigma7_model.h"

namespace robossis::haptics {
namespace {

constexpr double kTick = 0.25e-3;  // 4 kHz

void SetShare(benchmark::State& state) {
  // Seconds per iteration over the tick: Google Benchmark divides the rate counter by the time per iteration.
  state.counters["share_of_4khz_tick"] =
      benchmark::Counter(kTick, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_DhdReadWrite(benchmark::State& state) {
  DhdOptions options;
  options.library_path = FAKE_DHD_LIBRARY;
  auto device = DhdDevice::Open(options);
  device->EnableForces(true);
  DeviceCommand command;
  command.f_O = {1.0, -0.5, 0.2};
  command.tau_O = {0, 0, 0.01};
  double now_s = 0;
  for (auto _ : state) {
    now_s += kTick;
    benchmark::DoNotOptimize(device->Read(now_s));
    benchmark::DoNotOptimize(device->Write(command));
  }
  SetShare(state);
}
BENCHMARK(BM_DhdReadWrite);

// The same tick timed one by one (steady_clock around each read + write, ~20 ns of its own): p50, p99 and the
// worst of 20 000 ticks, against the 250 µs budget. Wall time: a pre-empted tick counts, as it would in the loop.
void BM_DhdReadWritePerTick(benchmark::State& state) {
  DhdOptions options;
  options.library_path = FAKE_DHD_LIBRARY;
  auto device = DhdDevice::Open(options);
  device->EnableForces(true);
  DeviceCommand command;
  command.f_O = {1.0, -0.5, 0.2};
  constexpr int kTicks = 20000;
  std::vector<double> ns(kTicks);
  double now_s = 0;
  for (auto _ : state) {
    for (int k = 0; k < kTicks; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      now_s += kTick;
      benchmark::DoNotOptimize(device->Read(now_s));
      benchmark::DoNotOptimize(device->Write(command));
      ns[k] = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
    }
  }
  std::sort(ns.begin(), ns.end());
  state.counters["p50_ns"] = ns[kTicks / 2];
  state.counters["p99_ns"] = ns[kTicks * 99 / 100];
  state.counters["max_ns"] = ns.back();
  state.counters["p99_share_of_4khz_tick"] = ns[kTicks * 99 / 100] * 1e-9 / kTick;
}
BENCHMARK(BM_DhdReadWritePerTick)->Iterations(1);

// The fake's physics per write (the same SimulatedSigma7 step at the same tick), to subtract.
void BM_FakePhysicsStepAlone(benchmark::State& state) {
  const robot::Sigma7Model model = robot::Sigma7Model::Default();
  SimulatedSigma7 sim(model, DeviceSimParams{}, HandParams{});
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = model.p_center_O();
  sim.Reset(X);
  HandTarget target;
  target.X_OH = X;
  const Eigen::Vector3d f(1.0, -0.5, 0.2), tau(0, 0, 0.01);
  for (auto _ : state) benchmark::DoNotOptimize(sim.Step(kTick, f, tau, target));
  SetShare(state);
}
BENCHMARK(BM_FakePhysicsStepAlone);

}  // namespace
}  // namespace robossis::haptics
