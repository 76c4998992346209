// `robossis sim` as a user meets it: the outputs of a short run, and one-line errors that leave nothing behind.

#include <unistd.h>

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

std::filesystem::path TempDir(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("robossis-sim-test-" + std::to_string(getpid()) + "-" + name);
}

TEST(SimCliTest, ShortReductionWritesTheOutputsWithTheIssueKeys) {
  const auto dir = TempDir("ok");
  const CommandRun run = Robossis("sim --scenario reduction --load-n 517 --load-nm 74 --duration-s 1 --out " +
                                  dir.string() + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const char* f : {"trajectory.csv", "summary.json", "details.json", "fragment_proximal.stl",
                        "fragment_distal.stl", "NOTICE_femur.txt"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  }
  std::ifstream in(dir / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  std::vector<std::string> keys;
  for (const auto& [key, value] : summary.items()) keys.push_back(key);
  EXPECT_THAT(keys, ::testing::UnorderedElementsAre("max_translation_error_mm", "mean_translation_error_mm",
                                                    "max_rotation_error_deg", "mean_rotation_error_deg",
                                                    "max_actuator_force_n", "max_actuator_torque_nm",
                                                    "realtime_factor"));
  std::ifstream stl(dir / "fragment_distal.stl");
  std::string first_line;
  std::getline(stl, first_line);
  EXPECT_THAT(first_line, HasSubstr("ALTERED"));
  std::filesystem::remove_all(dir);
}

TEST(SimCliTest, BadScenarioIsAOneLineErrorAndWritesNothing) {
  const auto dir = TempDir("bad-scenario");
  const CommandRun run = Robossis("sim --scenario circle --out " + dir.string());
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("--scenario"));
  EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
  EXPECT_FALSE(std::filesystem::exists(dir));
}

TEST(SimCliTest, BadLoadAndDurationNameTheirOption) {
  const auto dir = TempDir("bad-load");
  CommandRun run = Robossis("sim --load-n -3 --out " + dir.string());
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("--load-n"));
  run = Robossis("sim --duration-s abc --out " + dir.string());
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("--duration-s"));
  EXPECT_FALSE(std::filesystem::exists(dir));
}

}  // namespace
