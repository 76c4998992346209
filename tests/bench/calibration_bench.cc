// Reading and evaluating an hour of OptiTrack data at 240 Hz (864,000 frames); target ≤ 5 s on
// one core. The take is a synthetic Motive 1.23 export (1 rigid body, 4 rigid-body markers, 4 markers, 20
// occlusions) of a 1-hour commanded motion, written once to a temporary file.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <benchmark/benchmark.h>

#include "calibration/mocap_track.h"
#include "calibration/synthetic_tracker.h"
#include "calibration/tracking_eval.h"
#include "src/core/pose.h"
#include "src/core/units.h"

namespace {

using namespace robossis;
using namespace robossis::calibration;

struct HourTake {
  std::filesystem::path path;
  PoseTrajectory commanded;
  std::uintmax_t bytes = 0;
};

const HourTake& Take() {
  static const HourTake take = [] {
    HourTake t;
    // A motion that never repeats: 24 sinusoids per axis with random frequencies (0.005–0.4 Hz) and phases.
    const double duration_s = 3600.0, rate_hz = 100.0;
    std::mt19937 gen{42};
    std::uniform_real_distribution<double> freq(0.005, 0.4), phase(0, 2 * kPi);
    double f[6][24], ph[6][24];
    for (int j = 0; j < 6; ++j) {
      for (int m = 0; m < 24; ++m) {
        f[j][m] = freq(gen);
        ph[j][m] = phase(gen);
      }
    }
    for (int k = 0; k <= static_cast<int>(duration_s * rate_hz); ++k) {
      const double s_t = k / rate_hz;
      double s[6];
      for (int j = 0; j < 6; ++j) {
        s[j] = 0;
        for (int m = 0; m < 24; ++m) s[j] += std::sin(2 * kPi * f[j][m] * s_t + ph[j][m]) / 6.0;
      }
      t.commanded.Add(s_t, Eigen::Vector3d(0.02 * s[0], 0.02 * s[1], 0.284 + 0.01 * s[2]),
                      Eigen::Quaterniond(RotationFromRpy(DegToRad(6.0) * Eigen::Vector3d(s[3], s[4], s[5]))));
    }
    SyntheticTrackerOptions o;
    o.rate_hz = 240.0;
    o.occlusion_gaps = 20;
    o.X_TF = PoseFromMmDeg((Vector6d() << 350, -420, 1650, 178, -3, 35).finished());
    o.X_MB = PoseFromMmDeg((Vector6d() << 12, -8, 30, 2, -1, 40).finished());
    o.clock_offset_s = 12.345;
    t.path = std::filesystem::temp_directory_path() / "robossis_bench_hour_240hz.csv";
    std::ofstream out(t.path, std::ios::binary);
    WriteSyntheticMotiveCsv(t.commanded, o, out);
    out.close();
    t.bytes = std::filesystem::file_size(t.path);
    return t;
  }();
  return take;
}

void BM_ReadMotiveHour240Hz(benchmark::State& state) {
  const HourTake& take = Take();
  for (auto _ : state) {
    const RigidBodyTrack track = ReadRigidBodyTrack(take.path, "MovingRing");
    benchmark::DoNotOptimize(track.p_TB.data());
    state.counters["frames"] = static_cast<double>(track.size());
  }
  state.counters["file_MB"] = static_cast<double>(take.bytes) / 1e6;
  state.SetBytesProcessed(static_cast<std::int64_t>(take.bytes) * state.iterations());
}
BENCHMARK(BM_ReadMotiveHour240Hz)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_EvaluateHour240Hz(benchmark::State& state) {
  const HourTake& take = Take();
  const RigidBodyTrack track = ReadRigidBodyTrack(take.path, "MovingRing");
  for (auto _ : state) {
    const TrackingEvalResult result = EvaluateTracking(track, take.commanded);
    benchmark::DoNotOptimize(result.translation.mean);
    state.counters["offset_err_ms"] = (result.clock.offset_s - 12.345) * 1e3;
    state.counters["mean_err_mm"] = result.translation.mean * 1e3;
  }
}
BENCHMARK(BM_EvaluateHour240Hz)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_ReadAndEvaluateHour240Hz(benchmark::State& state) {
  const HourTake& take = Take();
  for (auto _ : state) {
    const RigidBodyTrack track = ReadRigidBodyTrack(take.path, "MovingRing");
    const TrackingEvalResult result = EvaluateTracking(track, take.commanded);
    benchmark::DoNotOptimize(result.translation.mean);
  }
}
BENCHMARK(BM_ReadAndEvaluateHour240Hz)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace
