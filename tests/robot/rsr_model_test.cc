#include "robot/rsr_model.h"

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "src/core/config.h"
#include "src/core/files.h"

namespace robossis::robot {
namespace {

using ::testing::HasSubstr;

// Writes the default rsr.yaml with one line replaced, and returns the file's path.
std::filesystem::path ConfigWith(const std::string& pattern, const std::string& replacement) {
  const std::string text = ReadTextFile(DefaultDataDir() / "config" / "rsr.yaml");
  const std::string edited = std::regex_replace(text, std::regex(pattern), replacement);
  EXPECT_NE(text, edited) << "pattern not found: " << pattern;
  const auto path = std::filesystem::temp_directory_path() /
                    ("rsr_" + std::to_string(std::hash<std::string>{}(edited)) + ".yaml");
  WriteFileAtomically(path, edited);
  return path;
}

std::string LoadError(const std::filesystem::path& path) {
  try {
    RsrModel::FromYaml(path);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(RsrModelTest, DefaultConfigMatchesDesignBrief) {
  const RsrModel m = RsrModel::Default();
  EXPECT_DOUBLE_EQ(m.limits().stroke_min_m, 0.214);
  EXPECT_DOUBLE_EQ(m.limits().stroke_max_m, 0.354);
  EXPECT_NEAR(m.p_FA(1).y(), 0.200, 1e-15);  // arm 2 at gamma = 90 deg, R_a = 0.2 m
}

TEST(RsrModelTest, MissingFileIsNamed) {
  EXPECT_THAT(LoadError("/nonexistent/rsr.yaml"), HasSubstr("/nonexistent/rsr.yaml: config file not found"));
}

TEST(RsrModelTest, NonNumericValueNamesTheKey) {
  EXPECT_THAT(LoadError(ConfigWith("fixed_ring_radius_m: 0.200", "fixed_ring_radius_m: abc")),
              HasSubstr("'geometry.fixed_ring_radius_m': expected a finite number, got 'abc'"));
}

TEST(RsrModelTest, WrongListLengthNamesTheKey) {
  EXPECT_THAT(LoadError(ConfigWith("arm_angles_deg: \\[-30, 90, 210\\]", "arm_angles_deg: [-30, 90]")),
              HasSubstr("'geometry.arm_angles_deg': expected a list of 3 numbers"));
}

TEST(RsrModelTest, MissingKeyIsNamed) {
  EXPECT_THAT(LoadError(ConfigWith("  stroke_min_m: 0.214\n", "")), HasSubstr("'limits.stroke_min_m': missing"));
}

TEST(RsrModelTest, InvertedStrokeLimitsAreRejected) {
  EXPECT_THAT(LoadError(ConfigWith("stroke_max_m: 0.354", "stroke_max_m: 0.200")),
              HasSubstr("'limits.stroke_max_m': must be greater than stroke_min_m"));
}

TEST(RsrModelTest, HomeOutsideLimitsIsRejected) {
  EXPECT_THAT(LoadError(ConfigWith("position_mm: \\[0, 0, 284\\]", "position_mm: [0, 0, 400]")),
              HasSubstr("home pose violates the stroke limit"));
}

TEST(RsrModelTest, InvalidYamlIsRejected) {
  EXPECT_THAT(LoadError(ConfigWith("geometry:", "geometry: [")), HasSubstr("not valid YAML"));
}

}  // namespace
}  // namespace robossis::robot
