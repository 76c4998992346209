#include <unistd.h>

#include <filesystem>
#include <fstream>
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

TEST(StagedOutputDirTest, ASecondRunReplacesTheFolderWholeWithoutStaleFiles) {
  const auto target = std::filesystem::temp_directory_path() / "robossis_staged_replace";
  std::filesystem::remove_all(target);
  {
    StagedOutputDir out(target);
    out.Write("old_figure.svg", "stale");
    out.Write("data.csv", "1");
    out.Commit();
  }
  {
    StagedOutputDir out(target);
    out.Write("data.csv", "2");
    out.Commit();
  }
  EXPECT_EQ(ReadTextFile(target / "data.csv"), "2");
  EXPECT_FALSE(std::filesystem::exists(target / "old_figure.svg"));
  std::filesystem::remove_all(target);
}

TEST(StagedOutputDirTest, RefusesAForeignNonEmptyFolderUnlessForced) {
  const auto target = std::filesystem::temp_directory_path() / "robossis_staged_foreign";
  std::filesystem::remove_all(target);
  std::filesystem::create_directories(target);
  WriteFileAtomically(target / "thesis.tex", "precious");
  try {
    StagedOutputDir out(target);
    FAIL() << "accepted a foreign folder";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("not an earlier robossis output"));
  }
  EXPECT_EQ(ReadTextFile(target / "thesis.tex"), "precious");
  {
    StagedOutputDir out(target, OutputPolicy(/*replace_any=*/true, {}));
    out.Write("a.txt", "new");
    out.Commit();
  }
  EXPECT_FALSE(std::filesystem::exists(target / "thesis.tex"));
  EXPECT_THROW(StagedOutputDir("."), std::invalid_argument);
  std::filesystem::remove_all(target);
}

TEST(StagedOutputDirTest, LeftoversOfDeadRunsAreRemovedAndLiveOnesKept) {
  const auto base = std::filesystem::temp_directory_path() / "robossis_staged_leftovers";
  std::filesystem::remove_all(base);
  std::filesystem::create_directories(base);
  const auto target = base / "out";
  // PID 999999999 is above Linux's pid_max (4194304), so no process has it: a dead run's leftovers.
  for (const char* stale : {"out.partial-999999999", "out.tmp-999999999", "out.old-999999999"}) {
    std::filesystem::create_directories(base / stale);
  }
  const std::string live = "out.partial-" + std::to_string(::getppid());  // a live process (our parent)
  std::filesystem::create_directories(base / live);
  std::filesystem::create_directories(base / "outer.partial-999999999");  // another output's: not ours to touch
  {
    StagedOutputDir out(target);
    out.Commit();
  }
  EXPECT_FALSE(std::filesystem::exists(base / "out.partial-999999999"));
  EXPECT_FALSE(std::filesystem::exists(base / "out.tmp-999999999"));
  EXPECT_FALSE(std::filesystem::exists(base / "out.old-999999999"));
  EXPECT_TRUE(std::filesystem::exists(base / live));
  EXPECT_TRUE(std::filesystem::exists(base / "outer.partial-999999999"));
  std::filesystem::remove_all(base);
}


// The message of the std::invalid_argument `f` throws ("" if it throws nothing or something else).
template <typename F>
std::string InvalidArgumentText(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(OutputPolicyTest, RefusesAnOutputThatIsContainsOrIsInsideAnInput) {
  namespace fs = std::filesystem;
  const fs::path base = fs::temp_directory_path() / ("robossis_policy_" + std::to_string(::getpid()));
  fs::remove_all(base);
  fs::create_directories(base / "run" / "sub");
  const OutputPolicy policy(false, {{"--hc", base / "run" / "hc.csv"}, {"--atlas", base / "atlas", true},
                             {"--x", ""}});
  EXPECT_THAT(InvalidArgumentText([&] { policy.RefuseOutputOverInputs("--out", base / "run"); }),
              HasSubstr("contains --hc"));
  EXPECT_THAT(InvalidArgumentText([&] { policy.RefuseOutputOverInputs("--out", base / "run" / "hc.csv"); }),
              HasSubstr("is --hc"));
  EXPECT_THAT(InvalidArgumentText([&] { policy.RefuseOutputOverInputs("--out", base / "atlas" / "x"); }),
              HasSubstr("is inside --atlas"));
  // The same folder spelled through '..', '.' and a trailing slash; a symbolic link to it.
  EXPECT_THAT(InvalidArgumentText([&] { policy.CheckFolder("--out", base / "run" / "sub" / ".." / "." / ""); }),
              HasSubstr("contains --hc"));
  fs::create_directory_symlink(base / "run", base / "link");
  EXPECT_THAT(InvalidArgumentText([&] { policy.CheckFolder("--out", base / "link"); }), HasSubstr("contains --hc"));
  // Whole path components: "runner" is not inside "run"; an empty input is no input.
  EXPECT_NO_THROW(policy.CheckFolder("--out", base / "runner"));
  EXPECT_NO_THROW(policy.CheckFolder("--out", base / "atlas2"));
  EXPECT_THROW(StagedOutputDir(base / "run", policy), std::invalid_argument);
  fs::remove_all(base);
}

TEST(OutputPolicyTest, WriteOutputFileIsAtomicAndLeavesNoTemporary) {
  namespace fs = std::filesystem;
  const fs::path base = fs::temp_directory_path() / ("robossis_outfile_" + std::to_string(::getpid()));
  fs::remove_all(base);
  fs::create_directories(base / "folder");
  const OutputPolicy policy(false, {{"--reference", base / "ref.csv"}});
  // A dead run's temporary is removed; the file is written whole.
  { std::ofstream(base / "take.csv.tmp-999999999") << "half"; }
  WriteOutputFile(policy, base / "take.csv", "whole\n");
  EXPECT_EQ(ReadTextFile(base / "take.csv"), "whole\n");
  EXPECT_FALSE(fs::exists(base / "take.csv.tmp-999999999"));
  // A folder, the input itself, a device: refused before anything is written, and no temporary is left.
  EXPECT_THAT(InvalidArgumentText([&] { WriteOutputFile(policy, base / "folder", "x"); }), HasSubstr("is a folder"));
  EXPECT_THAT(InvalidArgumentText([&] { WriteOutputFile(policy, base / "ref.csv", "x"); }),
              HasSubstr("is --reference"));
  EXPECT_THAT(InvalidArgumentText([&] { WriteOutputFile(policy, "/dev/null", "x"); }),
              HasSubstr("not a regular file"));
  for (const auto& entry : fs::directory_iterator(base)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
  fs::remove_all(base);
}

}  // namespace
}  // namespace robossis
