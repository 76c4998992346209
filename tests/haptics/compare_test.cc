// The comparison: summary keys, table, and that the metrics see what they should.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "haptics/rendering/boundary_probe.h"
#include "haptics/scenarios/compare.h"
#include "src/core/units.h"
#include "test_util.h"

namespace robossis::haptics {
namespace {

using testing::Config;
using testing::Rsr;

TEST(Compare, SummaryHasTheIssueKeysForEveryMethod) {
  const robot::Sigma7Model sigma7 = robot::Sigma7Model::Default();
  HapticsConfig config = Config();
  config.cloud.translation_points = 40;
  config.cloud.rotation_points = 40;
  const Scenario s = MakeScenario("strike", Rsr(), config.hand, config.strike_hand_stiffness_n_per_m, true);
  CompareSettings settings;
  std::vector<MethodRun> runs;
  for (const char* m : {"pointcloud", "proxy"}) runs.push_back(RunMethod(s, m, config, Rsr(), sigma7, settings));
  const nlohmann::ordered_json j = SummaryJson(s, settings, runs);
  for (const char* m : {"pointcloud", "proxy"}) {
    for (const char* key : {"max_penetration_mm", "max_penetration_deg", "direction_error_deg_p95",
                            "max_force_step_n", "energy_generated_j", "tick_us_p50", "tick_us_p99", "tick_us_max"}) {
      ASSERT_TRUE(j["methods"][m].contains(key)) << m << " " << key;
      EXPECT_TRUE(j["methods"][m][key].is_number());
    }
  }
  // The firm-grip strike pushes harder than the 15 N cap: the proxy (a spring from the true boundary) is
  // penetrated; the point cloud starts pushing 15 mm early.
  // (beyond the +x edge the spherical-cone limit can also be escaped by tilting: the penetration is counted in
  // whichever unit is the cheaper escape, 15 mm ≡ 5°)
  EXPECT_TRUE(runs[1].metrics.max_penetration_mm > 1.0 || runs[1].metrics.max_penetration_deg > 0.3)
      << runs[1].metrics.max_penetration_mm << " mm, " << runs[1].metrics.max_penetration_deg << " deg";
  EXPECT_GT(runs[1].metrics.saturation_time_s, 0.0);
  EXPECT_EQ(runs[0].trace.size(), runs[1].trace.size());
  const std::string table = MarkdownTable(runs);
  EXPECT_NE(table.find("| pointcloud |"), std::string::npos);
  EXPECT_NE(table.find("| proxy |"), std::string::npos);
  EXPECT_NE(table.find("*best*"), std::string::npos);
}

TEST(Compare, DirectionErrorScoresTheWallNotTheDamper) {
  // On the strike's fast withdrawal (100 mm/s) the point cloud's force is its damper −c_f·v, toward the wall, on
  // ticks that count as contact because the ROTATIONAL cloud still touches the cone limits (up to 36 mm inside).
  // The direction error must score the wall, not that viscous drag (which is the same in free space): before the
  // fix every such tick scored ~180°.
  const robot::Sigma7Model sigma7 = robot::Sigma7Model::Default();
  HapticsConfig config = Config();
  config.cloud.translation_points = 40;
  config.cloud.rotation_points = 40;
  const Scenario s = MakeScenario("strike", Rsr(), config.hand, config.strike_hand_stiffness_n_per_m, true);
  const MethodRun run = RunMethod(s, "pointcloud", config, Rsr(), sigma7, CompareSettings{});
  int withdrawing_damper_ticks = 0;
  for (std::size_t k = 1; k < run.trace.size(); ++k) {
    const TickRecord& r = run.trace[k];
    const double vx_mm_s = (r.pose_mm_deg[0] - run.trace[k - 1].pose_mm_deg[0]) * 1000;
    // Withdrawing fast, beyond the translational cloud's 15 mm reach: only the damper acts in translation.
    if (vx_mm_s < -50 && r.push_signed < -16 && r.force_n.norm() > 1.0) {
      ++withdrawing_damper_ticks;
      EXPECT_LT(r.force_direction_error_deg, 0) << "scored at t = " << r.t_s << " s: " << r.force_direction_error_deg;
    }
  }
  EXPECT_GT(withdrawing_damper_ticks, 20);  // the case is exercised
}

// The fast settings the other tests use: small point clouds, --fast scenarios.
HapticsConfig FastConfig() {
  HapticsConfig config = Config();
  config.cloud.translation_points = 40;
  config.cloud.rotation_points = 40;
  return config;
}

// Linear-interpolation percentile, written out here so the test does not reuse the code it checks.
double PercentileOf(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const double pos = q * (v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(pos);
  return i + 1 < v.size() ? v[i] + (pos - i) * (v[i + 1] - v[i]) : v[i];
}

// Every summary figure that a trace row carries, recomputed from the trace (kept at every tick).
void ExpectSummaryFromTrace(const MethodRun& run, double rate_hz) {
  const MethodMetrics& m = run.metrics;
  SCOPED_TRACE(run.method);
  ASSERT_EQ(static_cast<int>(run.trace.size()), m.ticks);
  double max_mm = 0, max_deg = 0, free_f = 0, free_tau = 0, f_step = 0, tau_step = 0, saturated_s = 0;
  int beyond = 0, t_beyond = 0, r_beyond = 0, scored = 0, left_out = 0, deep_status = 0, faults = 0;
  int free = 0, shallow = 0, deep = 0;
  std::vector<double> all, force, torque;
  for (std::size_t k = 0; k < run.trace.size(); ++k) {
    const TickRecord& r = run.trace[k];
    // The flags say where the reference's range ends; the raw value there is the range, never more.
    EXPECT_EQ(r.penetration_mm_beyond_reference, r.penetration_mm >= MToMm(kPenetrationRangeM) - 1e-9) << r.t_s;
    EXPECT_EQ(r.penetration_deg_beyond_reference, r.penetration_deg >= RadToDeg(kPenetrationRangeRad) - 1e-9)
        << r.t_s;
    t_beyond += r.penetration_mm_beyond_reference;
    r_beyond += r.penetration_deg_beyond_reference;
    switch (r.penetration_counted) {
      case PenetrationCount::kFree:
        EXPECT_EQ(r.penetration_mm, 0) << r.t_s;
        EXPECT_EQ(r.penetration_deg, 0) << r.t_s;
        ++free;
        free_f = std::max(free_f, r.force_n.norm());
        free_tau = std::max(free_tau, r.torque_nm.norm());
        break;
      case PenetrationCount::kTranslation:
        EXPECT_FALSE(r.penetration_mm_beyond_reference) << r.t_s;
        max_mm = std::max(max_mm, r.penetration_mm);
        ++(r.penetration_mm <= kShallowPenetrationMm ? shallow : deep);
        break;
      case PenetrationCount::kRotation:
        EXPECT_FALSE(r.penetration_deg_beyond_reference) << r.t_s;
        max_deg = std::max(max_deg, r.penetration_deg);
        ++(r.penetration_deg <= kShallowPenetrationDeg ? shallow : deep);
        break;
      case PenetrationCount::kBeyondReference:
        EXPECT_TRUE(r.penetration_mm_beyond_reference && r.penetration_deg_beyond_reference) << r.t_s;
        ++beyond;
        ++deep;
        break;
    }
    // A direction is scored or left out, never both; left out only where the reference's normal is not defined.
    EXPECT_FALSE(r.force_direction_left_out && r.force_direction_error_deg >= 0) << r.t_s;
    EXPECT_FALSE(r.torque_direction_left_out && r.torque_direction_error_deg >= 0) << r.t_s;
    if (r.penetration_mm_beyond_reference) {
      EXPECT_LT(r.force_direction_error_deg, 0) << r.t_s;
    }
    if (r.penetration_deg_beyond_reference) {
      EXPECT_LT(r.torque_direction_error_deg, 0) << r.t_s;
    }
    if (r.force_direction_error_deg >= 0) force.push_back(r.force_direction_error_deg), all.push_back(force.back());
    if (r.torque_direction_error_deg >= 0) torque.push_back(r.torque_direction_error_deg), all.push_back(torque.back());
    scored += r.force_direction_error_deg >= 0 || r.torque_direction_error_deg >= 0;
    left_out += r.force_direction_left_out || r.torque_direction_left_out;
    // Steps within an episode (the device is reset between episodes).
    if (k > 0 && run.trace[k - 1].episode == r.episode) {
      f_step = std::max(f_step, (r.force_n - run.trace[k - 1].force_n).norm());
      tau_step = std::max(tau_step, (r.torque_nm - run.trace[k - 1].torque_nm).norm());
    }
    saturated_s += r.saturated ? 1 / rate_hz : 0;
    deep_status += r.status == static_cast<int>(HapticStatus::kDeepPenetration);
    faults += r.status == static_cast<int>(HapticStatus::kFault);
  }
  EXPECT_EQ(m.max_penetration_mm, max_mm);
  EXPECT_EQ(m.max_penetration_deg, max_deg);
  EXPECT_EQ(m.penetration_beyond_reference_ticks, beyond);
  EXPECT_EQ(m.translation_beyond_reference_ticks, t_beyond);
  EXPECT_EQ(m.rotation_beyond_reference_ticks, r_beyond);
  EXPECT_EQ(m.max_free_space_force_n, free_f);
  EXPECT_EQ(m.max_free_space_torque_nm, free_tau);
  EXPECT_DOUBLE_EQ(m.direction_error_deg_p95, PercentileOf(all, 0.95));
  EXPECT_DOUBLE_EQ(m.force_direction_error_deg_p95, PercentileOf(force, 0.95));
  EXPECT_DOUBLE_EQ(m.torque_direction_error_deg_p95, PercentileOf(torque, 0.95));
  EXPECT_EQ(m.direction_error_scored_ticks, scored);
  EXPECT_EQ(m.direction_error_left_out_ticks, left_out);
  EXPECT_EQ(m.max_force_step_n, f_step);
  EXPECT_EQ(m.max_torque_step_nm, tau_step);
  EXPECT_NEAR(m.saturation_time_s, saturated_s, 1e-9);
  EXPECT_EQ(m.deep_penetration_ticks, deep_status);
  EXPECT_EQ(m.fault_ticks, faults);
  EXPECT_DOUBLE_EQ(m.free_share, static_cast<double>(free) / m.ticks);
  EXPECT_DOUBLE_EQ(m.shallow_share, static_cast<double>(shallow) / m.ticks);
  EXPECT_DOUBLE_EQ(m.deep_share, static_cast<double>(deep) / m.ticks);
  std::printf("%s: %d ticks, direction error scored on %d, left out on %d; beyond reference %d\n",
              run.method.c_str(), m.ticks, scored, left_out, beyond);
}

class SummaryFromTrace : public ::testing::TestWithParam<std::string> {};

TEST_P(SummaryFromTrace, AgreesTickByTick) {
  const robot::Sigma7Model sigma7 = robot::Sigma7Model::Default();
  const HapticsConfig config = FastConfig();
  const Scenario s = MakeScenario(GetParam(), Rsr(), config.hand, config.strike_hand_stiffness_n_per_m, true);
  CompareSettings settings;
  for (const char* method : {"pointcloud", "proxy"}) {
    const MethodRun run = RunMethod(s, method, config, Rsr(), sigma7, settings);
    std::printf("%s ", GetParam().c_str());
    ExpectSummaryFromTrace(run, settings.rate_hz);
    const nlohmann::ordered_json j = SummaryJson(s, settings, {run});
    EXPECT_EQ(j["methods"][method]["max_penetration_mm"].get<double>(), run.metrics.max_penetration_mm);
    EXPECT_EQ(j["methods"][method]["penetration_beyond_reference_ticks"].get<int>(),
              run.metrics.penetration_beyond_reference_ticks);
  }
}

INSTANTIATE_TEST_SUITE_P(BuiltInScenarios, SummaryFromTrace, ::testing::ValuesIn(KnownScenarios()),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(Compare, HandFarBeyondTheReferenceIsCountedNotCapped) {
  // A replay holding the hand at x = 1000 mm: no position within the reference's 200 mm and no orientation at all
  // is feasible. Before the fix every trace row said 200 mm / 40.107° (the search's caps) and the summary counted
  // 40.107° as the maximum penetration, and scored the wall's direction against the normal of a far-away limit.
  const std::filesystem::path csv = std::filesystem::temp_directory_path() / "robossis_compare_far_hand.csv";
  {
    std::ofstream out(csv);
    out << "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n0,1000,0,0,0,0,0\n0.3,1000,0,0,0,0,0\n";
  }
  const HapticsConfig config = FastConfig();
  const Scenario s = MakeScenario(csv.string(), Rsr(), config.hand, config.strike_hand_stiffness_n_per_m, false);
  std::filesystem::remove(csv);
  CompareSettings settings;
  const MethodRun run = RunMethod(s, "proxy", config, Rsr(), robot::Sigma7Model::Default(), settings);
  ExpectSummaryFromTrace(run, settings.rate_hz);
  const MethodMetrics& m = run.metrics;
  EXPECT_EQ(m.penetration_beyond_reference_ticks, m.ticks);
  EXPECT_EQ(m.max_penetration_mm, 0.0);
  EXPECT_EQ(m.max_penetration_deg, 0.0);  // not the search's cap
  EXPECT_EQ(m.deep_share, 1.0);
  EXPECT_EQ(m.direction_error_scored_ticks, 0);
  EXPECT_GT(m.direction_error_left_out_ticks, 0);  // the proxy pushes at its cap: the samples exist, left out
  const nlohmann::ordered_json j = SummaryJson(s, settings, {run});
  EXPECT_EQ(j["methods"]["proxy"]["penetration_beyond_reference_ticks"].get<int>(), m.ticks);
  EXPECT_EQ(j["reference"]["translation_range_mm"].get<double>(), MToMm(kPenetrationRangeM));
  const std::string trace = TraceCsv(run);
  EXPECT_NE(trace.find(",penetration_counted_as,"), std::string::npos);
  EXPECT_NE(trace.find(",beyond_reference,"), std::string::npos);
  EXPECT_NE(MarkdownTable({run}).find("| proxy | " + std::to_string(m.ticks) + " of " + std::to_string(m.ticks)),
            std::string::npos);
}

// Several methods at a time on threads of their own: every metric and trace is the one RunMethod gives alone (only
// the tick times, measured on the machine, may differ).
TEST(Compare, RunMethodsInParallelGivesTheRunsOfRunMethod) {
  const robot::Sigma7Model sigma7 = robot::Sigma7Model::Default();
  const HapticsConfig config = FastConfig();
  const Scenario s = MakeScenario("strike", Rsr(), config.hand, config.strike_hand_stiffness_n_per_m, true);
  const CompareSettings settings;
  const std::vector<std::string> methods = {"pointcloud", "mesh-live", "proxy", "proxy-pc"};
  std::vector<MethodRun> alone;
  for (const std::string& m : methods) alone.push_back(RunMethod(s, m, config, Rsr(), sigma7, settings));
  std::vector<std::size_t> started, done;
  MethodRunEvents events;
  events.started = [&](std::size_t i) { started.push_back(i); };
  events.done = [&](std::size_t i, MethodRun& run, double wall_s) {
    EXPECT_EQ(run.method, methods[i]);
    EXPECT_GE(wall_s, 0.0);
    done.push_back(i);
  };
  std::vector<MethodRun> parallel = RunMethods(s, methods, config, Rsr(), sigma7, settings, nullptr, 2, events);
  ASSERT_EQ(parallel.size(), methods.size());
  EXPECT_EQ(started.size(), methods.size());
  EXPECT_EQ(done.size(), methods.size());
  // Tick times aside (wall clock), the summaries and the traces are the same.
  auto without_tick_times = [](std::vector<MethodRun> runs) {
    for (MethodRun& run : runs) {
      run.metrics.tick_us_p50 = run.metrics.tick_us_p99 = run.metrics.tick_us_max = 0;
      for (TickRecord& r : run.trace) r.tick_us = 0;
    }
    return runs;
  };
  const std::vector<MethodRun> a = without_tick_times(alone), p = without_tick_times(parallel);
  EXPECT_EQ(SummaryJson(s, settings, a).dump(), SummaryJson(s, settings, p).dump());
  for (std::size_t i = 0; i < methods.size(); ++i) {
    EXPECT_EQ(p[i].method, methods[i]);
    EXPECT_FALSE(a[i].trace.empty());
    EXPECT_EQ(TraceCsv(a[i]), TraceCsv(p[i])) << methods[i];
  }
}

TEST(Compare, RunMethodsRefusesNoJobsAndPassesOnARunsError) {
  const HapticsConfig config = FastConfig();
  const Scenario s = MakeScenario("strike", Rsr(), config.hand, config.strike_hand_stiffness_n_per_m, true);
  const robot::Sigma7Model sigma7 = robot::Sigma7Model::Default();
  EXPECT_THROW(RunMethods(s, {"proxy"}, config, Rsr(), sigma7, CompareSettings{}, nullptr, 0), std::invalid_argument);
  EXPECT_THROW(RunMethods(s, {"proxy", "no-such-method"}, config, Rsr(), sigma7, CompareSettings{}, nullptr, 2),
               std::invalid_argument);
}

}  // namespace
}  // namespace robossis::haptics
