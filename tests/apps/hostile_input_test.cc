// The hostile-input regression suite: one case (or a few) per input class that once gave a silently wrong answer,
// a hang, a leftover or a vague error. Each runs the robossis binary as a user would and checks the exit code and
// the one-line error (RELIABILITY.md has the table).

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "src/core/config.h"
#include "tests/support/hostile_cli_test.h"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using robossis::testing::CommandRun;
using robossis::testing::Robossis;

class HostileInputTest : public robossis::testing::HostileCliTest {};

// --- YAML: unknown and duplicated keys, exact types -------------------------------------------------------------

TEST_F(HostileInputTest, YamlUnknownKeyNamesTheNearestValidKey) {
  const fs::path data = DataDirWith("rsr.yaml", [](std::string t) { return t + "home_pos:\n  x: 1\n"; });
  ExpectError(Robossis("--data-dir " + Q(data) + " robot info"), "'home_pos' (line");
  ExpectError(Robossis("--data-dir " + Q(data) + " robot info"), "the nearest valid key is 'home_pose'");
}

TEST_F(HostileInputTest, YamlDuplicatedKeyIsAnError) {
  const fs::path data = DataDirWith("rsr.yaml", [](std::string t) { return t + "limits:\n  rotary_max_deg: 10\n"; });
  ExpectError(Robossis("--data-dir " + Q(data) + " robot info"), "'limits': duplicated key");
}

TEST_F(HostileInputTest, YamlNonIntegerCountIsAnError) {
  const fs::path data = DataDirWith("haptics.yaml", [](std::string t) {
    const std::string key = "translation_points: 200";
    return t.replace(t.find(key), key.size(), "translation_points: 2.5");
  });
  ExpectError(Robossis("--data-dir " + Q(data) + " workspace query --live --pose 0,0,284,0,0,0"),
              "'point_cloud.translation_points': expected an integer, got '2.5'");
}

// --- CSV: exact columns, duplicate headers, bounded and monotonic times -------------------------------------------

TEST_F(HostileInputTest, HcCsvWithAnExtraCellIsRefused) {
  const fs::path hc = Write("hc.csv", "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n0,0,0,0,0,0,0\n"
                                      "0.1,1,0,0,0,0,0,9\n");
  ExpectError(Robossis("transfer --hc " + Q(hc) + " --out " + Q(dir_ / "out")), "line 3: 8 cells; expected exactly 7");
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(HostileInputTest, HcCsvWithADuplicatedHeaderIsRefused) {
  const fs::path hc = Write("hc.csv", "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,yaw_deg\n0,0,0,0,0,0,0,0\n");
  ExpectError(Robossis("transfer --hc " + Q(hc) + " --out " + Q(dir_ / "out")), "'yaw_deg' appears twice");
}

TEST_F(HostileInputTest, HcCsvWithNegativeTimesIsRefusedBeforeWork) {
  const fs::path hc = Write("hc.csv", "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n-1e9,0,0,0,0,0,0\n"
                                      "0,1,0,0,0,0,0\n");
  ExpectError(Robossis("transfer --hc " + Q(hc) + " --out " + Q(dir_ / "out")),
              "column 1 (time_s): got '-1e9'; expected a time in [0, 600]");
}

TEST_F(HostileInputTest, ScenarioCsvSpanningDaysIsRefusedBeforeWork) {
  const fs::path csv = Write("span.csv", "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n0,0,0,284,0,0,0\n"
                                         "1e7,0,0,284,0,0,0\n");
  ExpectError(Robossis("render-compare --scenario " + Q(csv) + " --methods pointcloud --out " + Q(dir_ / "out")),
              "expected a time in [0, 600]");
}

TEST_F(HostileInputTest, HeaderlessReferenceIsNotGuessedAsTum) {
  const fs::path ref = Write("ref.csv", "0,0,0,0.284,1,0,0,0\n0.1,0,0,0.284,1,0,0,0\n");
  ExpectError(Robossis("mocap simulate --reference " + Q(ref) + " --out " + Q(dir_ / "take.csv")),
              "commas in a TUM line");
  EXPECT_FALSE(fs::exists(dir_ / "take.csv"));
}

// --- Files that are not files -------------------------------------------------------------------------------------

TEST_F(HostileInputTest, DirectoryAndDeviceAreNotCalledEmptyFiles) {
  for (const std::string& input : {dir_.string(), std::string("/dev/zero")}) {
    const CommandRun run = Robossis("mocap simulate --reference " + Q(input) + " --out " + Q(dir_ / "take.csv"));
    ExpectError(run, "expected a regular file");
    EXPECT_THAT(run.output, Not(HasSubstr("empty")));
  }
}

// --- Numeric options: bounded, finite, 0 is a value ---------------------------------------------------------------

TEST_F(HostileInputTest, NumericOptionsAreBoundedAndFinite) {
  const fs::path ref = Write("ref.csv", "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0.284,1,0,0,0\n1,0,0,0.285,1,0,0,0\n");
  const std::string simulate = "mocap simulate --reference " + Q(ref) + " --out " + Q(dir_ / "take.csv");
  ExpectError(Robossis(simulate + " --gaps 2000000000"), "--gaps: expected 0 to 10000");
  ExpectError(Robossis(simulate + " --rate-hz inf"), "--rate-hz: expected a finite number in [1, 10000] Hz");
  ExpectError(Robossis(simulate + " --offset-s nan"), "--offset-s: expected a finite number");
  ExpectError(Robossis("workspace query --live --pose 0,0,284,0,0,0 --radius-mm inf"),
              "--radius-mm: expected a finite number in [0, 1000] mm");
  ExpectError(Robossis("workspace hc --resolution-mm 1e-9 --out " + Q(dir_ / "hc")),
              "--resolution-mm: expected a finite number in [0.5, 50] mm");
}

// Options CLI11 itself refuses (a range check, a missing or unknown option) are input errors like the others: exit
// 1 and one "robossis: error: --option: ..." line naming the option and the expected range (were exits 105 to 109
// with CLI11's two-line text).
TEST_F(HostileInputTest, OptionsRefusedByTheParserAreOneLineErrorsWithExit1) {
  ExpectError(Robossis("render-compare --trace-decimation 0 --out " + Q(dir_ / "rc")),
              "robossis: error: --trace-decimation: Value 0 not in range 1 to 1000\n");
  ExpectError(Robossis("keys init --days 99999999999999999999"), "--days: Value 99999999999999999999 not in range 1 to");
  ExpectError(Robossis("robot ik"), "robossis: error: --pose is required\n");
  ExpectError(Robossis("robot ik --pose 0,0,284,0,0,0 --bogus 1"), "not expected");
  for (const char* args : {"render-compare --trace-decimation 0", "robot ik", "nosuchcommand"}) {
    const CommandRun run = Robossis(args);
    EXPECT_EQ(run.exit_code, 1) << args;
    EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
    EXPECT_THAT(run.output, Not(HasSubstr("Run with --help"))) << run.output;
  }
  EXPECT_EQ(Robossis("robot ik --help").exit_code, 0);
}

// --- --out: fresh folder replaced whole, foreign folders refused, leftovers of dead runs removed -----------------

TEST_F(HostileInputTest, OutRefusesAForeignFolderAndReplacesItsOwnWhole) {
  const fs::path out = dir_ / "hc";
  Write("hc/thesis.tex", "precious");
  const std::string run = "workspace hc --resolution-mm 10 --resolution-deg 10 --out " + Q(out);
  ExpectError(Robossis(run), "not an earlier robossis output");
  EXPECT_EQ(Read(out / "thesis.tex"), "precious");
  ASSERT_EQ(Robossis("--force " + run).exit_code, 0);
  EXPECT_FALSE(fs::exists(out / "thesis.tex"));
  Write("hc/stale_figure.svg", "from an older run");
  // PID 999999999 is above Linux's pid_max: the leftovers of runs that died.
  fs::create_directories(dir_ / "hc.partial-999999999");
  Write("hc.tmp-999999999", "half");
  ASSERT_EQ(Robossis(run).exit_code, 0);
  EXPECT_FALSE(fs::exists(out / "stale_figure.svg"));
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_FALSE(fs::exists(dir_ / "hc.partial-999999999"));
  EXPECT_FALSE(fs::exists(dir_ / "hc.tmp-999999999"));
}

// --- Atlases: fingerprint, off-grid poses -------------------------------------------------------------------------

TEST_F(HostileInputTest, AtlasRefusesAnotherGeometryAndReportsOffGridPoses) {
  const fs::path atlas = dir_ / "atlas";
  ASSERT_EQ(Robossis("workspace atlas --coarse --out " + Q(atlas)).exit_code, 0);
  const fs::path data = DataDirWith("rsr.yaml", [](std::string t) {
    const std::string key = "rotary_max_deg: 30";
    return t.replace(t.find(key), key.size(), "rotary_max_deg: 25");
  });
  ExpectError(Robossis("--data-dir " + Q(data) + " workspace query --atlas " + Q(atlas) + " --pose 0,0,284,0,0,0"),
              "the atlas was built for another robot geometry or other limits");
  const CommandRun far = Robossis("workspace query --atlas " + Q(atlas) + " --pose 0,0,284,60,0,0 --json", false);
  ASSERT_EQ(far.exit_code, 0) << far.output;
  EXPECT_THAT(far.output, HasSubstr("\"translation\": \"off_grid\""));
  EXPECT_THAT(far.output, HasSubstr("\"signed_distance_mm\": null"));
}

// --- Motive exports that are not what they claim; registration residuals that say so ---------------------------

class HostileMotiveTest : public HostileInputTest {
 protected:
  // A moving reference (the same kind as the mocap CLI test's) and a simulated Motive take of it in metres.
  void SetUp() override {
    HostileInputTest::SetUp();
    reference_ = MovingReference();
    const CommandRun sim = Robossis("mocap simulate --reference " + Q(reference_) + " --out " + Q(dir_ / "take.csv"));
    ASSERT_EQ(sim.exit_code, 0) << sim.output;
    take_ = Read(dir_ / "take.csv");
  }
  // The take with `from` replaced by `to` (first occurrence), as a file.
  fs::path Edited(const std::string& name, const std::string& from, const std::string& to) {
    return Write(name, Replace(take_, from, to));
  }
  CommandRun Eval(const fs::path& take) {
    return Robossis("track-eval --mocap " + Q(take) + " --rigid-body MovingRing --reference " + Q(reference_) +
                    " --out " + Q(dir_ / "eval") + " --no-plot");
  }
  fs::path reference_;
  std::string take_;
};

TEST_F(HostileMotiveTest, WrongLengthUnitsFailThePlausibilityCheck) {
  ASSERT_EQ(Eval(dir_ / "take.csv").exit_code, 0);  // the genuine take evaluates
  fs::remove_all(dir_ / "eval");
  // Metres labelled millimetres: the motion shrinks 1000-fold and no rigid transform fits it.
  ExpectError(Eval(Edited("millimetres.csv", "Length Units,Meters", "Length Units,Millimeters")),
              "the tracker-to-robot registration leaves an RMS residual");
  EXPECT_FALSE(fs::exists(dir_ / "eval"));
}

TEST_F(HostileMotiveTest, HeaderThatLiesIsRefused) {
  ExpectError(Eval(Edited("v99.csv", "Format Version,1.23", "Format Version,9.9")), "'Format Version' is 9.9");
  ExpectError(Eval(Edited("rate0.csv", "Export Frame Rate,120.000000", "Export Frame Rate,0")),
              "'Export Frame Rate' is '0'; expected a rate in [1, 100000] Hz");
  ExpectError(Eval(Edited("rate-120.csv", "Export Frame Rate,120.000000", "Export Frame Rate,-120")),
              "'Export Frame Rate' is '-120'");
  const std::size_t type_row = take_.find("\n,Type,");
  ASSERT_NE(type_row, std::string::npos);
  const std::size_t end = take_.find('\n', type_row + 1);
  ExpectError(Eval(Write("no_type.csv", take_.substr(0, type_row) + take_.substr(end))), "is the Type row missing?");
}

TEST_F(HostileMotiveTest, ARateNoTrackerHasIsRefusedNamingTheRate) {
  // 1e-300 Hz is positive, but no tracker's: refused as the rate, not blamed on a time cell 300 digits long.
  ExpectError(Eval(Edited("rate_tiny.csv", "Export Frame Rate,120.000000", "Export Frame Rate,1e-300")),
              "'Export Frame Rate' is '1e-300'; expected a rate in [1, 100000] Hz");
}

TEST_F(HostileMotiveTest, ATakeNameWithACommaIsReadAsWritten) {
  // Motive writes the take's name unquoted: "Take Name,Knee, left,Capture Frame Rate,..." keeps its pairs.
  const std::size_t at = take_.find("Take Name,");
  ASSERT_NE(at, std::string::npos);
  std::string t = take_;
  t.insert(at + std::string("Take Name,").size(), "Knee, left ");
  const CommandRun run = Eval(Write("comma.csv", t));
  EXPECT_EQ(run.exit_code, 0) << run.output;
}

TEST_F(HostileMotiveTest, NanAndGarbageCellsAreNotOcclusions) {
  // The first frame row: "0,0.000000,<rotation x>,..." → its first rigid-body cell replaced.
  const std::size_t frame0 = take_.find("\n0,");
  ASSERT_NE(frame0, std::string::npos);
  const std::size_t cell = take_.find(',', take_.find(',', frame0 + 1) + 1) + 1;
  const std::size_t cell_end = take_.find(',', cell);
  for (const std::string bad : {"nan", "abc", "inf"}) {
    std::string t = take_;
    t.replace(cell, cell_end - cell, bad);
    ExpectError(Eval(Write("cell_" + bad + ".csv", t)), "got '" + bad + "'; expected a finite number, or an empty cell");
  }
}

// --- Singular poses: no NaN/inf with exit 0 -----------------------------------------------------------------------

TEST_F(HostileInputTest, SingularPoseIsAnErrorNotNan) {
  // Both rings at the origin: every arm has zero length, its direction is undefined.
  for (const char* cmd : {"robot jacobian", "robot ik"}) {
    const CommandRun run = Robossis(std::string(cmd) + " --pose 0,0,0,0,0,0");
    ExpectError(run, "not finite at this pose");
    EXPECT_THAT(run.output, Not(HasSubstr("nan")));
  }
}

// --- Version ------------------------------------------------------------------------------------------------------

TEST_F(HostileInputTest, VersionNamesTheGitRevision) {
  const CommandRun run = Robossis("--version");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_THAT(run.output, ::testing::MatchesRegex("robossis [0-9]+\\.[0-9]+\\.[0-9]+ \\(git [0-9a-f]+.*\\)\n"));
}

}  // namespace
