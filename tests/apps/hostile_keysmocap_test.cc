// Hostile command lines of `keys init`, `mocap simulate` and `track-eval`: a topic namespace that would widen or
// break the signed permissions, rigid body names that break the written CSV, occlusion gaps that merged, options
// that were checked only when another option was given. Each runs the robossis binary as a user would.

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/hostile_cli_test.h"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using robossis::testing::CommandRun;
using robossis::testing::Robossis;

class HostileKeysMocapTest : public robossis::testing::HostileCliTest {
 protected:
  CommandRun Simulate(const fs::path& out, const std::string& extra) const {
    return Robossis("mocap simulate --reference " + Q(dir_ / "commanded.csv") + " --out " + Q(out) + " " + extra);
  }
  static nlohmann::json Inspect(const fs::path& take) {
    const CommandRun run = Robossis("mocap inspect --json " + Q(take), false);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return run.exit_code == 0 ? nlohmann::json::parse(run.output) : nlohmann::json::object();
  }

};

// --- keys init: the topic namespace is not the user's to choose ------------------------------------------------

TEST_F(HostileKeysMocapTest, KeysInitRefusesEveryNamespaceAndWritesNothing) {
  for (const std::string& ns : std::vector<std::string>{"*", "rsr</topic><topic>*", "", "rsr<x>", "rsr", "other"}) {
    const fs::path keys = dir_ / "keys";
    const CommandRun run = Robossis("keys init " + Q(keys) + " --namespace " + Q(ns));
    ExpectError(run, "--namespace");
    EXPECT_FALSE(fs::exists(keys)) << ns;
  }
}

TEST_F(HostileKeysMocapTest, KeysInitPermissionsGrantOnlyTheLinksOwnTopics) {
  const fs::path keys = dir_ / "keys";
  const CommandRun run = Robossis("keys init " + Q(keys));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::regex topic("<topic>([^<]*)</topic>");
  for (const std::string& role : std::vector<std::string>{"leader", "follower", "panel"}) {
    const std::string xml = Read(keys / role / (role + "_permissions.xml"));
    int topics = 0;
    for (auto it = std::sregex_iterator(xml.begin(), xml.end(), topic); it != std::sregex_iterator(); ++it) {
      ++topics;
      EXPECT_TRUE(std::regex_match((*it)[1].str(), std::regex("rt/rsr/[a-z_]+"))) << role << ": " << (*it)[1];
    }
    EXPECT_GE(topics, 3) << role;
    EXPECT_EQ(xml.find('*'), std::string::npos) << role;
  }
}

TEST_F(HostileKeysMocapTest, KeysInitObserverPublishesNothingOfTheRobots) {
  const fs::path keys = dir_ / "keys";
  const CommandRun run = Robossis("keys init " + Q(keys));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string xml = Read(keys / "observer" / "observer_permissions.xml");
  const std::regex publish("<publish>([\\s\\S]*?)</publish>");
  const std::regex topic("<topic>([^<]*)</topic>");
  int published = 0;
  for (auto p = std::sregex_iterator(xml.begin(), xml.end(), publish); p != std::sregex_iterator(); ++p) {
    const std::string block = (*p)[1].str();
    for (auto it = std::sregex_iterator(block.begin(), block.end(), topic); it != std::sregex_iterator(); ++it) {
      ++published;
      const std::string name = (*it)[1].str();
      EXPECT_NE(name.rfind("rt/rsr", 0), 0u) << name;          // nothing of the robot's
      EXPECT_NE(name.rfind("rt/*", 0), 0u) << name;            // no pattern that would cover it
      EXPECT_NE(name, "*");
    }
  }
  EXPECT_GT(published, 0) << "the observer should publish ROS 2's own topics";
  EXPECT_NE(xml.find("rt/rsr/measured_cp"), std::string::npos);
}

// --- mocap simulate: rigid body names a CSV cell can hold -------------------------------------------------------

TEST_F(HostileKeysMocapTest, SimulateRefusesNamesThatBreakTheCsv) {
  MovingReference();
  for (const std::string& name : std::vector<std::string>{
           "a,b", "", "a\"b", "a\nb", "a\rb", " a", "a ", std::string(65, 'r')}) {
    const fs::path take = dir_ / "take.csv";
    ExpectError(Simulate(take, "--rigid-body " + Q(name)), "--rigid-body");
    EXPECT_FALSE(fs::exists(take)) << name;
  }
  ExpectError(Simulate(dir_ / "take.csv", "--rigid-body 'a,b'"), "the name contains a comma");
  ExpectError(Simulate(dir_ / "take.csv", "--rigid-body ''"), "the name is empty");
}

TEST_F(HostileKeysMocapTest, SimulatedNamesReadBack) {
  MovingReference();
  for (const std::string& name : std::vector<std::string>{"My Ring_1", "ring:2", std::string(64, 'r')}) {
    const fs::path take = dir_ / "take.csv";
    ASSERT_EQ(Simulate(take, "--rigid-body " + Q(name)).exit_code, 0) << name;
    const nlohmann::json j = Inspect(take);
    ASSERT_EQ(j["rigid_bodies"].size(), 1u) << name;
    EXPECT_EQ(j["rigid_bodies"][0]["name"], name);
  }
}

// --- mocap simulate: the gaps asked for are the gaps written ---------------------------------------------------

TEST_F(HostileKeysMocapTest, SimulateWritesExactlyTheRequestedGaps) {
  MovingReference();
  const CommandRun too_many = Simulate(dir_ / "take.csv", "--gaps 1000");
  ExpectError(too_many, "--gaps 1000: at most ");
  EXPECT_THAT(too_many.output, HasSubstr("of up to 0.3 s"));
  EXPECT_FALSE(fs::exists(dir_ / "take.csv"));
  std::smatch m;
  ASSERT_TRUE(std::regex_search(too_many.output, m, std::regex("at most ([0-9]+) ")));
  const int max_gaps = std::stoi(m[1]);
  ASSERT_GT(max_gaps, 10);
  ExpectError(Simulate(dir_ / "take.csv", "--gaps " + std::to_string(max_gaps + 1)),
              "at most " + std::to_string(max_gaps) + " ");
  for (int gaps : {1, 3, 10, max_gaps}) {
    const fs::path take = dir_ / ("take" + std::to_string(gaps) + ".csv");
    const CommandRun run = Simulate(take, "--gaps " + std::to_string(gaps) + " --seed " + std::to_string(gaps));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_THAT(run.output, HasSubstr(" " + std::to_string(gaps) + " gaps ("));
    const nlohmann::json j = Inspect(take);
    ASSERT_EQ(j["rigid_bodies"].size(), 1u);
    EXPECT_EQ(j["rigid_bodies"][0]["gaps"], gaps);
    const long long frames = j["frames"].get<long long>();
    const long long present = j["rigid_bodies"][0]["frames_present"].get<long long>();
    EXPECT_LE(frames - present, gaps * 37LL) << "each gap is at most 0.3 s at 120 Hz";
    EXPECT_GE(frames - present, gaps * 2LL) << "each gap is at least 0.02 s at 120 Hz";
  }
}

// --- track-eval: every option is checked, used or not ------------------------------------------------------------

TEST_F(HostileKeysMocapTest, TrackEvalChecksTheOffsetOptionsAlways) {
  MovingReference();
  ASSERT_EQ(Simulate(dir_ / "take.csv", "--offset-s 2.5 --gaps 3").exit_code, 0);
  const std::string eval = "track-eval --mocap " + Q(dir_ / "take.csv") + " --rigid-body MovingRing --reference " +
                           Q(dir_ / "commanded.csv") + " --out " + Q(dir_ / "ev") + " --no-plot ";
  for (const std::string& bad : std::vector<std::string>{"nan", "-1", "0", "1e9", "inf"}) {
    ExpectError(Robossis(eval + "--offset-window-s " + bad), "--offset-window-s: expected a finite number in");
    ExpectError(Robossis(eval + "--offset-s 2.5 --offset-window-s " + bad),
                "--offset-window-s: expected a finite number in");
    EXPECT_FALSE(fs::exists(dir_ / "ev")) << bad;
  }
  for (const std::string& bad : std::vector<std::string>{"nan", "inf", "2e6", "-2e6"}) {
    ExpectError(Robossis(eval + "--offset-s " + bad), "--offset-s: expected a finite number in");
  }
  ExpectError(Robossis(eval + "--offset-window-s 1"), "--offset-window-s: only meaningful with --offset-s");
  EXPECT_FALSE(fs::exists(dir_ / "ev"));
  const CommandRun ok = Robossis(eval + "--offset-s 2.4 --offset-window-s 1");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_THAT(ok.output, HasSubstr("clock offset at mid-take"));
  EXPECT_THAT(ok.output, HasSubstr("): 2500.0"));  // ms: the true 2.5 s, not the 2.4 s it started from
  // A window that does not hold the offset: an error naming the window, not an offset from outside it.
  fs::remove_all(dir_ / "ev");
  ExpectError(Robossis(eval + "--offset-s 2.0 --offset-window-s 0.01"), "outside the window 2 s +- 0.01 s");
  EXPECT_FALSE(fs::exists(dir_ / "ev"));
}

}  // namespace
