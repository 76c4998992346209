// Tick time of each haptic rendering method: point cloud versus point count, proxy, mesh walls.
// Run: build/tests/bench/bench_haptics --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// Ratios to the 1 ms (1 kHz) and 250 µs (4 kHz) budgets are recorded in BENCHMARKS.md.

#include <algorithm>
#include <ctime>
#include <filesystem>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>

#include "haptics/haptics_config.h"
#include "haptics/rendering/mesh_proxy_renderer.h"
#include "haptics/rendering/mesh_wall_renderer.h"
#include "haptics/rendering/point_cloud_renderer.h"
#include "haptics/rendering/proxy_renderer.h"
#include "haptics/scenarios/scenario.h"
#include "robot/rsr_kinematics.h"
#include "src/core/config.h"

namespace robossis::haptics {
namespace {

const robot::RsrModel& Rsr() {
  static const robot::RsrModel m = robot::RsrModel::Default();
  return m;
}
const HapticsConfig& Config() {
  static const HapticsConfig c = HapticsConfig::FromYaml(DefaultDataDir() / "config" / "haptics.yaml");
  return c;
}

// Poses on a small back-and-forth path across the +x edge (range 0: free space at home; 1: at the edge).
struct Path {
  explicit Path(bool at_edge) {
    const Eigen::Isometry3d home = Rsr().geometry().X_FM_home;
    const double reach = at_edge ? ReachAlongAxis(Rsr(), home, Eigen::Vector3d::UnitX(), false, 0.3) : 0.0;
    for (int k = 0; k < 64; ++k) {
      Eigen::Isometry3d X = home;
      X.translation().x() += reach + (at_edge ? 0.004 * std::sin(0.1 * k) : 0.0);
      X.translation().y() += 0.002 * std::cos(0.1 * k);
      poses[k] = X;
    }
  }
  Eigen::Isometry3d poses[64];
};

void RunTicks(benchmark::State& state, HapticRenderer& r, const Path& path) {
  HapticInput in;
  HapticOutput out;
  int k = 0;
  r.Reset(path.poses[0]);
  for (auto _ : state) {
    in.X_OH = path.poses[k++ & 63];
    benchmark::DoNotOptimize(r.Tick(in, out));
    benchmark::DoNotOptimize(out.f_O.data());
  }
}

void BM_IsPoseFeasible(benchmark::State& state) {
  const Path path(true);
  int k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(robot::IsPoseFeasible(Rsr(), path.poses[k++ & 63]));
}
BENCHMARK(BM_IsPoseFeasible);

// A 200-point translational cloud's feasibility around a pose at the edge: each pose tested whole (arg 0,
// IsPoseFeasible) or with the legs' fixed parts computed once (arg 1, PoseFeasibilityAround, what the renderer uses).
void BM_TranslationCloudFeasibility(benchmark::State& state) {
  const Path path(true);
  const std::vector<Eigen::Vector3d> units = FibonacciSphere(200);
  int k = 0, inside = 0;
  for (auto _ : state) {
    const Eigen::Isometry3d& X = path.poses[k++ & 63];
    if (state.range(0) == 0) {
      Eigen::Isometry3d Y = X;
      for (const Eigen::Vector3d& unit : units) {
        Y.translation() = X.translation() + 0.015 * unit;
        inside += robot::IsPoseFeasible(Rsr(), Y);
      }
    } else {
      const robot::PoseFeasibilityAround around(Rsr(), X);
      for (const Eigen::Vector3d& unit : units) inside += around.Translated(0.015 * unit);
    }
  }
  benchmark::DoNotOptimize(inside);
}
BENCHMARK(BM_TranslationCloudFeasibility)->Arg(0)->Arg(1)->ArgName("around")->Unit(benchmark::kMicrosecond);

// Arguments: points per cloud (each of the two clouds), at the edge (1) or in free space (0).
void BM_PointCloudTick(benchmark::State& state) {
  PointCloudParams cloud = Config().cloud;
  cloud.translation_points = cloud.rotation_points = static_cast<int>(state.range(0));
  PointCloudRenderer r(Rsr(), HcToRsrMap{}, Config().limits, 1000, Config().wall, cloud);
  RunTicks(state, r, Path(state.range(1) != 0));
  state.counters["points_per_tick"] = 2.0 * state.range(0);
}
BENCHMARK(BM_PointCloudTick)
    ->ArgsProduct({{50, 100, 200, 500, 1000, 2000}, {0, 1}})
    ->ArgNames({"points", "edge"})
    ->Unit(benchmark::kMicrosecond);

void BM_ProxyTick(benchmark::State& state) {
  ProxyRenderer r(Rsr(), HcToRsrMap{}, Config().limits, 1000, Config().wall, Config().proxy);
  RunTicks(state, r, Path(state.range(0) != 0));
}
BENCHMARK(BM_ProxyTick)->Arg(0)->Arg(1)->ArgName("edge")->Unit(benchmark::kMicrosecond);

void BM_ProxyTickPassivity(benchmark::State& state) {
  ProxyRenderer r(Rsr(), HcToRsrMap{}, Config().limits, 1000, Config().device_safe_wall, Config().proxy);
  PassivityParams pc = Config().passivity;
  pc.enabled = true;
  r.SetPassivity(pc);
  RunTicks(state, r, Path(true));
}
BENCHMARK(BM_ProxyTickPassivity)->Unit(benchmark::kMicrosecond);

std::shared_ptr<const geometry::BoundaryAtlas> Atlas() {
  static std::shared_ptr<const geometry::BoundaryAtlas> atlas;
  if (!atlas) {
    // $ROBOSSIS_BENCH_ATLAS: an atlas folder (robossis workspace atlas --out DIR); else a coarse one built here.
    const char* dir = std::getenv("ROBOSSIS_BENCH_ATLAS");
    if (dir != nullptr && *dir != '\0') {
      atlas = std::make_shared<const geometry::BoundaryAtlas>(geometry::BoundaryAtlas::Load(dir));
    } else {
      atlas = std::make_shared<const geometry::BoundaryAtlas>(geometry::BuildAtlas(
          Rsr(), robot::Sigma7Model::Default(), geometry::AtlasSpec::Coarse(Rsr()),
          std::filesystem::temp_directory_path() / "robossis_bench_atlas"));
    }
  }
  return atlas;
}

void BM_MeshTick(benchmark::State& state) {
  MeshWallRenderer r(Rsr(), HcToRsrMap{}, Config().limits, 1000, Config().wall, 5, Atlas());
  RunTicks(state, r, Path(state.range(0) != 0));
}
BENCHMARK(BM_MeshTick)->Arg(0)->Arg(1)->ArgName("edge")->Unit(benchmark::kMicrosecond);

// mesh-live: the live slices at the path's pose are generated before timing (as the background refresh would have
// them); the tick then queries them (tick cost only; the refresh runs off the real-time thread).
void BM_MeshLiveTick(benchmark::State& state) {
  MeshWallRenderer r(Rsr(), HcToRsrMap{}, Config().limits, 1000, Config().wall, 5, Atlas());
  r.UseLiveBoundary(std::make_shared<geometry::LiveBoundary>(Rsr(), robot::Sigma7Model::Default(), Config().live), 0,
                    Config().live_switch_blend_s);
  const Path path(state.range(0) != 0);
  HapticInput in;
  HapticOutput out;
  in.X_OH = path.poses[0];
  r.Reset(in.X_OH);
  r.Tick(in, out);                  // posts the pose
  r.StepSimulatedBackground(0.0);   // generates the live slices ...
  r.StepSimulatedBackground(0.0);   // ... and publishes them (latency 0)
  RunTicks(state, r, path);
}
BENCHMARK(BM_MeshLiveTick)->Arg(0)->Arg(1)->ArgName("edge")->Unit(benchmark::kMicrosecond);

// mesh-proxy: the god-object on live slices regenerated around the proxy (generated before timing, as the
// background refresh would have them; the refresh itself is BM_MeshProxyRefresh, off the real-time thread).
void BM_MeshProxyTick(benchmark::State& state) {
  auto live = std::make_shared<geometry::LiveBoundary>(Rsr(), robot::Sigma7Model::Default(), Config().live);
  MeshProxyRenderer r(Rsr(), HcToRsrMap{}, Config().limits, 1000, Config().wall, Config().mesh_proxy, Atlas(), live,
                      -1.0);
  const Path path(state.range(0) != 0);
  HapticInput in;
  HapticOutput out;
  in.X_OH = path.poses[0];
  r.Reset(in.X_OH);
  r.Tick(in, out);    // posts the proxy pose
  live->RefreshNow();  // generates and publishes the slices there
  RunTicks(state, r, path);
}
BENCHMARK(BM_MeshProxyTick)->Arg(0)->Arg(1)->ArgName("edge")->Unit(benchmark::kMicrosecond);

// The refresh that mesh-proxy runs off the real-time thread: both slices regenerated at a pose near the +x edge.
void BM_MeshProxyRefresh(benchmark::State& state) {
  geometry::LiveBoundary live(Rsr(), robot::Sigma7Model::Default(), Config().live);
  const Path path(true);
  int k = 0;
  for (auto _ : state) {
    Eigen::Isometry3d X = path.poses[k++ & 63];
    X.linear() = Eigen::AngleAxisd(0.001 * k, Eigen::Vector3d::UnitY()).toRotationMatrix();  // force a refresh
    live.PostPose(X);
    benchmark::DoNotOptimize(live.RefreshNow());
  }
}
BENCHMARK(BM_MeshProxyRefresh)->Unit(benchmark::kMillisecond)->Iterations(5);

// Tick-time distribution in deep, moving contact (translation and rotation at once: from the +x edge, 0-6 mm
// beyond while rolling 0-12 deg past the roll limit), per tick in thread CPU time (the wall clock of a shared
// machine measures the other jobs): counters p50_cpu_us / p99_cpu_us / max_cpu_us. Argument 0: proxy, 1: mesh-proxy.
void BM_TickDistributionDeepContact(benchmark::State& state) {
  const Eigen::Isometry3d home = Rsr().geometry().X_FM_home;
  const double reach_x = ReachAlongAxis(Rsr(), home, Eigen::Vector3d::UnitX(), false, 0.3);
  const double reach_roll = ReachAlongAxis(Rsr(), home, Eigen::Vector3d::UnitX(), true, 1.0);
  std::vector<Eigen::Isometry3d> poses(2000);
  for (int k = 0; k < 2000; ++k) {
    const double phase = 0.5 - 0.5 * std::cos(2 * 3.14159265358979 * k / 2000.0);
    Eigen::Isometry3d X = home;
    X.translation().x() += reach_x + 0.006 * phase;
    X.translation().y() += 0.004 * std::sin(6.283 * k / 500.0);
    X.linear() = Eigen::AngleAxisd(reach_roll + 0.21 * phase, Eigen::Vector3d::UnitX()).toRotationMatrix();
    poses[k] = X;
  }
  auto live = std::make_shared<geometry::LiveBoundary>(Rsr(), robot::Sigma7Model::Default(), Config().live);
  std::unique_ptr<HapticRenderer> r;
  if (state.range(0) == 0) {
    r = std::make_unique<ProxyRenderer>(Rsr(), HcToRsrMap{}, Config().limits, 1000, Config().wall, Config().proxy);
  } else {
    r = std::make_unique<MeshProxyRenderer>(Rsr(), HcToRsrMap{}, Config().limits, 1000, Config().wall,
                                            Config().mesh_proxy, Atlas(), live, -1.0);
  }
  HapticInput in;
  HapticOutput out;
  std::vector<double> cpu_us;
  cpu_us.reserve(1 << 20);
  auto thread_cpu_s = [] {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
  };
  int k = 0;
  r->Reset(poses[0]);
  for (auto _ : state) {
    if (k % 2000 == 0) {  // the background refresh, between ticks and outside the timing (it runs off the loop)
      state.PauseTiming();
      in.X_OH = poses[0];
      r->Reset(in.X_OH);
      r->Tick(in, out);
      live->RefreshNow();
      state.ResumeTiming();
    }
    in.X_OH = poses[k++ % 2000];
    const double t0 = thread_cpu_s();
    benchmark::DoNotOptimize(r->Tick(in, out));
    cpu_us.push_back(1e6 * (thread_cpu_s() - t0));
  }
  std::sort(cpu_us.begin(), cpu_us.end());
  auto at = [&](double q) { return cpu_us[static_cast<std::size_t>(q * (cpu_us.size() - 1))]; };
  state.counters["p50_cpu_us"] = at(0.5);
  state.counters["p99_cpu_us"] = at(0.99);
  state.counters["max_cpu_us"] = cpu_us.back();
}
BENCHMARK(BM_TickDistributionDeepContact)->Arg(0)->Arg(1)->ArgName("mesh_proxy")->Iterations(20000)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace robossis::haptics
