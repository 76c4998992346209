// Scenarios and the trajectory CSV replay.

#include <filesystem>
#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "haptics/rendering/renderer_factory.h"
#include "haptics/scenarios/scenario.h"
#include "test_util.h"

namespace robossis::haptics {
namespace {

using ::testing::HasSubstr;
using testing::Config;
using testing::Rsr;

std::filesystem::path WriteTemp(const std::string& name, const std::string& text) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() / ("robossis_haptics_" + name);
  std::ofstream(p) << text;
  return p;
}

TEST(Scenario, PushEdgesStartInsideAndCrossTheBoundaryAtThePaperSpeeds) {
  const Scenario s = MakeScenario("push-edges", Rsr(), Config().hand, 800, false);
  ASSERT_EQ(s.episodes.size(), 12u);
  for (const Episode& e : s.episodes) {
    EXPECT_TRUE(robot::IsPoseFeasible(Rsr(), e.X_FM_start)) << e.label;
    EXPECT_GT(e.boundary_s, 0) << e.label;
    // Target speed along the push: 10 mm/s (translation) or 1 deg/s (rotation), paper §VI-B.
    const double t = 1.0, h = 1e-3;
    const Eigen::Isometry3d a = e.target_FM(t), b = e.target_FM(t + h);
    const double speed = e.rotational ? RotationAngleBetween(a.linear(), b.linear()) / h
                                      : (b.translation() - a.translation()).norm() / h;
    EXPECT_NEAR(speed, e.rotational ? 3.14159265358979 / 180 : 0.01, 1e-6) << e.label;
  }
}

TEST(Scenario, EveryScriptedScenarioStartsInFreeSpaceForThePointClouds) {
  // The energy metric counts from the start of each contact, assuming an unloaded wall then. Before the fix the x, y
  // and yaw pushes, the x-y slide and the strike started within the rotational cloud's reach of a limit: the
  // paper's point cloud pushed 0.22–0.3 N·m on a hand at rest at t = 0.
  for (const char* name : {"push-edges", "explore", "strike"}) {
    for (const bool fast : {false, true}) {
      const Scenario s = MakeScenario(name, Rsr(), Config().hand, 800, fast);
      for (const Episode& e : s.episodes) {
        for (const char* method : {"pointcloud", "pointcloud-safe"}) {
          HcToRsrMap map;
          map.X_FM_anchor = e.X_FM_anchor;
          const std::unique_ptr<HapticRenderer> r = MakeRenderer(method, Config(), Rsr(), map, 1000);
          r->Reset(map.ToHc(e.X_FM_start));
          HapticInput in;
          in.X_OH = map.ToHc(e.X_FM_start);
          HapticOutput out;
          r->Tick(in, out);
          EXPECT_EQ(out.status, HapticStatus::kFree) << name << (fast ? " --fast " : " ") << e.label << " " << method;
        }
      }
    }
  }
}

TEST(Scenario, UnknownNameIsRejectedWithTheKnownOnes) {
  try {
    MakeScenario("wiggle", Rsr(), Config().hand, 800, true);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("push-edges"));
  }
}

TEST(Scenario, CsvReplayInterpolatesTheTrajectory) {
  const auto p = WriteTemp("ok.csv",
                           "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n"
                           "0,0,0,284,0,0,0\n"
                           "1,10,0,284,0,0,0\n");
  const Scenario s = LoadTrajectoryCsv(p, Config().hand);
  ASSERT_EQ(s.episodes.size(), 1u);
  EXPECT_NEAR(s.duration_s(), 1.0, 1e-12);
  EXPECT_NEAR(s.episodes[0].target_FM(0.5).translation().x(), 0.005, 1e-12);
}

TEST(Scenario, CsvErrorsNameTheLineAndColumn) {
  auto message = [](const std::string& text) {
    try {
      LoadTrajectoryCsv(WriteTemp("bad.csv", text), Config().hand);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string header = "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n";
  EXPECT_THAT(message("t,x\n0,1\n"), HasSubstr("line 1"));
  EXPECT_THAT(message(header + "0,0,0,284,0,0,0\n1,abc,0,284,0,0,0\n"), HasSubstr("line 3, column 2 (x_mm): got 'abc'"));
  EXPECT_THAT(message(header + "0,0,0,284,0,0,0\n0,0,0,284,0,0,0\n"), HasSubstr("increase"));
  EXPECT_THAT(message(header + "0,0,0,284,0,0\n"), HasSubstr("6 cells; expected exactly 7"));
  EXPECT_THAT(message(header + "0,0,0,284,0,0,0\n1,0,0,284,0,0,0,9\n"), HasSubstr("8 cells; expected exactly 7"));
  EXPECT_THAT(message(header + "0,0,0,284,0,0,0\n"), HasSubstr("at least 2"));
  // The span is bounded before the replay starts (a 2-row file spanning 1e7 s would simulate for hours).
  EXPECT_THAT(message(header + "0,0,0,284,0,0,0\n1e7,0,0,284,0,0,0\n"), HasSubstr("expected a time in [0, 600]"));
}

}  // namespace
}  // namespace robossis::haptics
