// Workspace slice generation versus resolution, and the signed penetration query (p50/p99) at ~2k and ~20k
// triangles. Run: ./build/tests/bench/bench_geometry --benchmark_counters_tabular=true

#include <algorithm>
#include <cmath>
#include <chrono>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "geometry/boundary_atlas.h"
#include "geometry/live_boundary.h"
#include "geometry/signed_distance.h"
#include "geometry/workspace_slice.h"
#include "src/core/pose.h"
#include "src/core/units.h"

namespace {

using namespace robossis;
using namespace robossis::geometry;

const robot::RsrModel& Rsr() {
  static const robot::RsrModel model = robot::RsrModel::Default();
  return model;
}
const robot::Sigma7Model& Hc() {
  static const robot::Sigma7Model model = robot::Sigma7Model::Default();
  return model;
}

void SliceCounters(benchmark::State& state, const WorkspaceSlice& s) {
  state.counters["triangles"] = static_cast<double>(s.stats.triangles);
  state.counters["grid_s"] = s.seconds_grid;
  state.counters["mesh_refine_s"] = s.seconds_mesh;
}

// Argument: resolution in tenths of a mm.
void BM_DexterousSlice(benchmark::State& state) {
  const SliceSpec spec{SliceKind::kRsrDexterous, {0, DegToRad(5), DegToRad(10)}, state.range(0) * 1e-4};
  WorkspaceSlice s;
  for (auto _ : state) {
    s = GenerateSlice(Rsr(), Hc(), spec);
    benchmark::DoNotOptimize(s.stats.volume);
  }
  SliceCounters(state, s);
}
BENCHMARK(BM_DexterousSlice)->Arg(80)->Arg(40)->Arg(20)->Unit(benchmark::kMillisecond)->Iterations(2);

// Argument: resolution in tenths of a degree.
void BM_RotationalSlice(benchmark::State& state) {
  const SliceSpec spec{SliceKind::kRsrRotational, {0.03, 0.0, 0.29}, DegToRad(state.range(0) * 0.1)};
  WorkspaceSlice s;
  for (auto _ : state) {
    s = GenerateSlice(Rsr(), Hc(), spec);
    benchmark::DoNotOptimize(s.stats.volume);
  }
  SliceCounters(state, s);
}
BENCHMARK(BM_RotationalSlice)->Arg(40)->Arg(20)->Arg(10)->Unit(benchmark::kMillisecond)->Iterations(2);

// Wall-clock latency of each call, for the p50/p99/max counters (Google Benchmark reports only means).
class Latencies {
 public:
  Latencies() { ns_.reserve(1 << 20); }
  template <typename F>
  void Time(F&& call) {
    const auto t0 = std::chrono::steady_clock::now();
    call();
    const auto t1 = std::chrono::steady_clock::now();
    if (ns_.size() < ns_.capacity()) ns_.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
  }
  void Report(benchmark::State& state) {
    std::sort(ns_.begin(), ns_.end());
    state.counters["p50_us"] = ns_[ns_.size() / 2] * 1e-3;
    state.counters["p99_us"] = ns_[ns_.size() * 99 / 100] * 1e-3;
    state.counters["max_us"] = ns_.back() * 1e-3;
  }

 private:
  std::vector<double> ns_;
};

// Query latency percentiles over fixed random points near the boundary (vertex + uniform +/-15 mm) of a dexterous
// slice whose resolution (tenths of a mm) sets the triangle count.
void BM_SignedDistanceQuery(benchmark::State& state) {
  const WorkspaceSlice slice =
      GenerateSlice(Rsr(), Hc(), {SliceKind::kRsrDexterous, {0, DegToRad(5), DegToRad(10)}, state.range(0) * 1e-4});
  const BoundaryDistanceField field(slice.mesh);
  SignedDistanceQuery query;
  std::mt19937 gen{42};
  std::uniform_int_distribution<std::size_t> pick(0, slice.mesh.vertices.size() - 1);
  std::uniform_real_distribution<double> u(-0.015, 0.015);
  std::vector<Eigen::Vector3d> points(4096);
  for (auto& p : points) p = slice.mesh.vertices[pick(gen)] + Eigen::Vector3d(u(gen), u(gen), u(gen));
  Latencies latencies;
  std::size_t i = 0;
  SignedDistanceResult r;
  for (auto _ : state) {
    latencies.Time([&] { query.Query(&field, points[i++ & 4095], 0.0, &r); });
    benchmark::DoNotOptimize(r.signed_distance);
  }
  state.counters["triangles"] = static_cast<double>(slice.stats.triangles);
  latencies.Report(state);
}
BENCHMARK(BM_SignedDistanceQuery)->Arg(130)->Arg(42)->Unit(benchmark::kMicrosecond);

// The same meshes, but the point follows a haptic-like path: a circle of 20 mm radius through the boundary region
// at 50 mm/s sampled at 1 kHz (50 um per query), so each query is warm-started by the previous one.
void BM_SignedDistanceQueryCoherent(benchmark::State& state) {
  const WorkspaceSlice slice =
      GenerateSlice(Rsr(), Hc(), {SliceKind::kRsrDexterous, {0, DegToRad(5), DegToRad(10)}, state.range(0) * 1e-4});
  const BoundaryDistanceField field(slice.mesh);
  SignedDistanceQuery query;
  // Centre the circle on a boundary vertex so the path crosses the wall.
  const Eigen::Vector3d centre = slice.mesh.vertices[slice.mesh.vertices.size() / 2];
  std::vector<Eigen::Vector3d> points(2513);  // 2*pi*20 mm / 50 um
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double a = 2 * kPi * k / points.size();
    points[k] = centre + 0.02 * Eigen::Vector3d(std::cos(a), std::sin(a), 0.3 * std::sin(2 * a));
  }
  Latencies latencies;
  std::size_t i = 0;
  SignedDistanceResult r;
  for (auto _ : state) {
    latencies.Time([&] { query.Query(&field, points[i++ % points.size()], 0.0, &r); });
    benchmark::DoNotOptimize(r.signed_distance);
  }
  state.counters["triangles"] = static_cast<double>(slice.stats.triangles);
  latencies.Report(state);
}
BENCHMARK(BM_SignedDistanceQueryCoherent)->Arg(130)->Arg(42)->Unit(benchmark::kMicrosecond);

// The pose query the haptic tick calls: nearest-node lookup + translation and rotation queries.
void BM_AtlasPoseQuery(benchmark::State& state) {
  static const BoundaryAtlas* atlas = [] {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "robossis_bench_atlas";
    return new BoundaryAtlas(BuildAtlas(Rsr(), Hc(), AtlasSpec::Coarse(Rsr()), dir));
  }();
  AtlasPoseQuery query;
  PoseBoundaryResult r;
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Isometry3d> poses(1024);
  for (auto& X : poses) {
    X = PoseFromPositionRpy(Eigen::Vector3d(0.1 * u(gen), 0.1 * u(gen), 0.284 + 0.06 * u(gen)),
                            Eigen::Vector3d(DegToRad(15) * u(gen), DegToRad(15) * u(gen), DegToRad(30) * u(gen)));
  }
  std::size_t i = 0;
  for (auto _ : state) {
    query.Query(*atlas, poses[i++ & 1023], 0.0, 0.0, &r);
    benchmark::DoNotOptimize(r.translation.signed_distance);
  }
}
BENCHMARK(BM_AtlasPoseQuery)->Unit(benchmark::kMicrosecond);

// One live refresh (slice + query structure, the default live resolutions 4 mm / 2 deg) of the dexterous (arg 0) or
// rotational (arg 1) slice, at the home pose (the largest dexterous slice) and at rpy (0, 5, 10) deg / 30 mm off.
void BM_LiveRefresh(benchmark::State& state) {
  LiveBoundary live(Rsr(), Hc());
  const bool dexterous = state.range(0) == 0;
  const bool home = state.range(1) == 0;
  const Eigen::Vector3d p = Rsr().geometry().X_FM_home.translation() + (home ? Eigen::Vector3d::Zero()
                                                                             : Eigen::Vector3d(0.03, 0, 0));
  const Eigen::Vector3d rpy = home ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0, DegToRad(5), DegToRad(10));
  std::size_t triangles = 0;
  for (auto _ : state) {
    const auto slice = live.Generate(dexterous ? SliceKind::kRsrDexterous : SliceKind::kRsrRotational,
                                     dexterous ? rpy : p);
    triangles = slice ? slice->field->mesh().triangles.size() : 0;
  }
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_LiveRefresh)->Args({0, 0})->Args({0, 1})->Args({1, 0})->Args({1, 1})->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// The haptic tick's pose query on live slices, as mesh-live runs it (inside cutoff 5 mm / 2 deg): a coherent path
// (1 kHz samples of a 20 mm circle at 50 mm/s through the +x wall, with a slow yaw swing) against the live slices
// made at its start.
void BM_LivePoseQuery(benchmark::State& state) {
  LiveBoundary live(Rsr(), Hc());
  const Eigen::Vector3d home = Rsr().geometry().X_FM_home.translation();
  live.PostPose(Rsr().geometry().X_FM_home);
  live.RefreshNow();
  LivePoseQuery query;
  query.SetInsideCutoff(0.005, DegToRad(2));
  PoseBoundaryResult r;
  std::vector<Eigen::Isometry3d> path(2513);
  for (std::size_t k = 0; k < path.size(); ++k) {
    const double a = 2 * kPi * k / path.size();
    path[k] = PoseFromPositionRpy(home + Eigen::Vector3d(0.13 + 0.02 * std::cos(a), 0.02 * std::sin(a), 0),
                                  Eigen::Vector3d(0, 0, DegToRad(0.5) * std::sin(a)));
  }
  Latencies latencies;
  std::size_t i = 0;
  for (auto _ : state) {
    latencies.Time([&] { query.Query(live, nullptr, path[i++ % path.size()], 0.0, 0.0, &r); });
    benchmark::DoNotOptimize(r.translation.signed_distance);
  }
  latencies.Report(state);
}
BENCHMARK(BM_LivePoseQuery)->Unit(benchmark::kMicrosecond);

}  // namespace
