// The command line as a user meets it: outputs, and a one-line error with a non-zero exit for bad input.

#include <cstdio>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/robossis_cli.h"

namespace {

using ::testing::HasSubstr;

using robossis::testing::CommandRun;
using robossis::testing::Robossis;

nlohmann::json JsonOf(const CommandRun& run) {
  EXPECT_EQ(run.exit_code, 0) << run.output;
  return nlohmann::json::parse(run.output);
}

TEST(CliTest, RobotInfoJson) {
  const auto doc = JsonOf(Robossis("robot info --json"));
  ASSERT_EQ(doc["fixed_ring_joints_m"].size(), 3u);
  ASSERT_EQ(doc["moving_ring_joints_m"].size(), 3u);
  EXPECT_EQ(doc["arm_angles_deg"].size(), 3u);
  EXPECT_NEAR(doc["home_pose"]["position_mm"][2].get<double>(), 284.0, 1e-9);
  EXPECT_NEAR(doc["limits"]["stroke_max_mm"].get<double>(), 354.0, 1e-9);
}

TEST(CliTest, RobotIkJsonAtHome) {
  const auto doc = JsonOf(Robossis("robot ik --pose 0,0,284,0,0,0 --json"));
  EXPECT_TRUE(doc["feasible"].get<bool>());
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(doc["d_mm"][i].get<double>(), 284.0, 1e-9);
  EXPECT_TRUE(doc["violations"].empty());
}

TEST(CliTest, RobotIkReportsViolations) {
  const auto doc = JsonOf(Robossis("robot ik --pose 0,0,400,0,0,0 --json"));
  EXPECT_FALSE(doc["feasible"].get<bool>());
  ASSERT_EQ(doc["violations"].size(), 3u);
  EXPECT_EQ(doc["violations"][0]["joint"], "stroke");
  EXPECT_NEAR(doc["violations"][0]["limit"].get<double>(), 354.0, 1e-9);
}

TEST(CliTest, RobotFkInvertsIk) {
  const auto ik = JsonOf(Robossis("robot ik --pose 20,-10,290,3,-4,10 --json"));
  char joints[256];
  std::snprintf(joints, sizeof joints, "%.12f,%.12f,%.12f,%.12f,%.12f,%.12f", ik["theta_deg"][0].get<double>(),
                ik["theta_deg"][1].get<double>(), ik["theta_deg"][2].get<double>(), ik["d_mm"][0].get<double>(),
                ik["d_mm"][1].get<double>(), ik["d_mm"][2].get<double>());
  const auto fk = JsonOf(Robossis(std::string("robot fk --joints ") + joints + " --json"));
  EXPECT_TRUE(fk["converged"].get<bool>());
  EXPECT_NEAR(fk["position_mm"][0].get<double>(), 20.0, 1e-6);
  EXPECT_NEAR(fk["rpy_deg"][2].get<double>(), 10.0, 1e-6);
}

TEST(CliTest, StaticsAndJacobian) {
  const auto st = JsonOf(Robossis("robot statics --pose 0,0,284,0,0,0 --wrench 0,0,-517,0,0,0 --json"));
  EXPECT_NEAR(st["linear_force_n"][1].get<double>(), 517.0 / 3, 1e-6);
  const auto jac = JsonOf(Robossis("robot jacobian --pose 0,0,284,0,0,0 --json"));
  EXPECT_EQ(jac["jacobian"].size(), 6u);
}

TEST(CliTest, HcIkAndFk) {
  const auto fk = JsonOf(Robossis("hc fk --joints 30,30,30 --json"));
  const auto p = fk["position_mm"];
  const auto ik = JsonOf(Robossis("hc ik --position " + std::to_string(p[0].get<double>()) + "," +
                                  std::to_string(p[1].get<double>()) + "," + std::to_string(p[2].get<double>()) +
                                  " --json"));
  EXPECT_TRUE(ik["reachable"].get<bool>());
  EXPECT_NEAR(ik["theta1_deg"][0].get<double>(), 30.0, 1e-3);
}

struct BadInput {
  const char* args;
  const char* message;
};

class CliBadInputTest : public ::testing::TestWithParam<BadInput> {};

TEST_P(CliBadInputTest, OneLineErrorAndNonZeroExit) {
  const CommandRun run = Robossis(GetParam().args);
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr(GetParam().message));
}

INSTANTIATE_TEST_SUITE_P(
    BadInputs, CliBadInputTest,
    ::testing::Values(
        BadInput{"robot ik --pose 1,2,3", "--pose: expected 6 comma-separated numbers"},
        BadInput{"robot ik --pose 1,2,3,4,5,nan", "value 6 is 'nan'"},
        BadInput{"robot ik --pose 1,2,x,4,5,6", "value 3 is 'x'"},
        BadInput{"robot ik", "--pose is required"},
        BadInput{"robot fk --joints 0,0,0,284,284", "--joints: expected 6 comma-separated numbers"},
        BadInput{"robot fk --joints 0,0,0,-284,284,284", "D1_MM must be positive"},
        BadInput{"robot fk --joints 0,0,0,10,900,10", "forward kinematics did not converge"},
        BadInput{"robot statics --pose 0,0,284,0,0,0 --wrench 1,2", "--wrench: expected 6"},
        BadInput{"hc ik --position 1,2", "--position: expected 3"},
        BadInput{"hc fk --joints 400,400,400", "does not assemble"},
        BadInput{"--data-dir /nonexistent robot info", "--data-dir"},
        BadInput{"robot ik --pose 0,0,284,0,0,0 --bogus", "--bogus"}));

TEST(CliTest, MissingConfigIsNamed) {
  const CommandRun run = Robossis("--data-dir /tmp robot info");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("/tmp/config/rsr.yaml: config file not found"));
}

}  // namespace
