// The comparison: summary keys, table, and that the metrics see what they should.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "haptics/scenarios/compare.h"
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

}  // namespace
}  // namespace robossis::haptics
