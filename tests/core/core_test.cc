#include <filesystem>
#include <random>
#include <stdexcept>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "src/core/files.h"
#include "src/core/parse.h"
#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis {
namespace {

using ::testing::HasSubstr;

TEST(PoseTest, RpyConventionIsZYX) {
  const Eigen::Matrix3d R = RotationFromRpy(Eigen::Vector3d(0.1, 0.2, 0.3));
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_LE((R - expected).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(PoseTest, RpyRoundTrip) {
  std::mt19937 gen{42};
  std::uniform_real_distribution<double> a(-3.1, 3.1), p(-1.55, 1.55);
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Vector3d rpy(a(gen), p(gen), a(gen));
    EXPECT_LE((RpyFromRotation(RotationFromRpy(rpy)) - rpy).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(PoseTest, MmDegRoundTrip) {
  Vector6d v;
  v << 10, -20, 284, 5, -7, 30;
  EXPECT_LE((MmDegFromPose(PoseFromMmDeg(v)) - v).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(ParseTest, ParsesLists) {
  EXPECT_EQ(ParseNumberList("1, 2.5,-3", 3, "--x", "A,B,C"), (std::vector<double>{1, 2.5, -3}));
}

TEST(ParseTest, WrongCountNamesOptionAndCount) {
  EXPECT_THROW(ParseNumberList("1,2", 3, "--x", "A,B,C"), std::invalid_argument);
  try {
    ParseNumberList("1,2", 3, "--pose", "A,B,C");
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("--pose: expected 3 comma-separated numbers (A,B,C), got 2"));
  }
}

TEST(ParseTest, FieldsAreTrimmedOfBlanksQuotesAndCarriageReturns) {
  EXPECT_EQ(TrimField(" \t\"12.5\"\r"), "12.5");
  double v = 0;
  EXPECT_TRUE(TryParseNumber(" +3.25 ", &v));
  EXPECT_DOUBLE_EQ(v, 3.25);
  EXPECT_TRUE(TryParseNumber("\"-1e-3\"\r", &v));
  EXPECT_DOUBLE_EQ(v, -1e-3);
  EXPECT_FALSE(TryParseNumber("", &v));
  EXPECT_FALSE(TryParseNumber("1.5x", &v));
  EXPECT_FALSE(TryParseNumber("1e999", &v));
  EXPECT_FALSE(TryParseNumber("nan", &v));
}

TEST(ParseTest, RejectsNanInfAndGarbage) {
  for (const char* bad : {"1,nan,3", "1,inf,3", "1,x,3", "1,,3", "1,2e999,3"}) {
    EXPECT_THROW(ParseNumberList(bad, 3, "--x", "A,B,C"), std::invalid_argument) << bad;
  }
  EXPECT_THROW(ParseNumber("12abc", "--rate-hz"), std::invalid_argument);
}

TEST(StagedOutputDirTest, NothingAppearsUnlessCommitted) {
  const auto target = std::filesystem::temp_directory_path() / "robossis_staged_test";
  std::filesystem::remove_all(target);
  {
    StagedOutputDir out(target);
    out.Write("a.txt", "partial");
  }  // not committed: as if an error had been thrown
  EXPECT_FALSE(std::filesystem::exists(target));
  {
    StagedOutputDir out(target);
    out.Write("sub/b.txt", "done");
    out.Commit();
  }
  EXPECT_EQ(ReadTextFile(target / "sub" / "b.txt"), "done");
  std::filesystem::remove_all(target);
}

}  // namespace
}  // namespace robossis
