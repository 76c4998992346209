// `robossis render-compare` as a user meets it.

#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/robossis_cli.h"

namespace {

using ::testing::HasSubstr;

using robossis::testing::CommandRun;
using robossis::testing::Robossis;

TEST(RenderCompareCli, WritesSummaryTracesAndTable) {
  const std::filesystem::path out = std::filesystem::temp_directory_path() / "robossis_render_compare_cli";
  std::filesystem::remove_all(out);
  const CommandRun run = Robossis("render-compare --scenario strike --fast --methods pointcloud,proxy --rate-hz 1000 "
                                  "--out " + out.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream in(out / "summary.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_TRUE(j["methods"].contains("pointcloud"));
  EXPECT_TRUE(j["methods"]["proxy"].contains("direction_error_deg_p95"));
  EXPECT_TRUE(std::filesystem::exists(out / "traces" / "proxy.csv"));
  EXPECT_TRUE(std::filesystem::exists(out / "summary.md"));
}

TEST(RenderCompareCli, UnknownMethodIsAOneLineError) {
  const std::filesystem::path out = std::filesystem::temp_directory_path() / "robossis_render_compare_bad";
  std::filesystem::remove_all(out);
  const CommandRun run = Robossis("render-compare --scenario strike --methods pointcloud,magic --out " + out.string());
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("--methods: unknown method 'magic'"));
  EXPECT_FALSE(std::filesystem::exists(out));  // nothing half-written
}

TEST(RenderCompareCli, BadRateAndMissingFileAreErrors) {
  EXPECT_THAT(Robossis("render-compare --rate-hz 5 --methods proxy --out /tmp/robossis_rc_rate").output,
              HasSubstr("--rate-hz"));
  const CommandRun run = Robossis("render-compare --scenario /nonexistent/path.csv --methods proxy --out /tmp/x_rc");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("/nonexistent/path.csv"));
}

}  // namespace
