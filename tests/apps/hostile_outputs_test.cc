// Hostile output paths of every command: --force that must reach the output, an --out over one of the run's own
// inputs (which replacing the target whole would delete), single output files that must be atomic and leave no
// temporary, and an atlas whose failed or interrupted build must never look complete. Each runs the robossis
// binary as a user would.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "src/core/config.h"
#include "tests/support/hostile_cli_test.h"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using robossis::testing::CommandRun;
using robossis::testing::Robossis;

class HostileOutputsTest : public robossis::testing::HostileCliTest {
 protected:
  // A folder someone else's: never an earlier robossis output.
  fs::path Foreign(const std::string& name) const {
    Write(name + "/thesis.tex", "precious");
    return dir_ / name;
  }
  // No `NAME.tmp-PID` or `NAME.partial-PID` is left in the test's folder.
  void ExpectNoTemporaries() const {
    for (const auto& entry : fs::recursive_directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_EQ(name.find(".tmp-"), std::string::npos) << entry.path();
      EXPECT_EQ(name.find(".partial-"), std::string::npos) << entry.path();
    }
  }
};

// --- --force reaches every command's output --------------------------------------------------------------------

TEST_F(HostileOutputsTest, ForceLetsEveryFolderCommandReplaceAForeignFolder) {
  const std::vector<std::string> commands = {
      "move --delta-mm 0,0,1 --duration-s 0.5 --no-plots",
      "transfer --scenario fig8 --no-plots",
      "workspace atlas --coarse --error-samples 0",
      "workspace hc --resolution-mm 10 --resolution-deg 10",
  };
  for (const std::string& command : commands) {
    const fs::path out = Foreign("out");
    ExpectError(Robossis(command + " --out " + Q(out)), "not an earlier robossis output");
    EXPECT_EQ(Read(out / "thesis.tex"), "precious") << command;
    const CommandRun forced = Robossis("--force " + command + " --out " + Q(out));
    EXPECT_EQ(forced.exit_code, 0) << command << "\n" << forced.output;
    EXPECT_FALSE(fs::exists(out / "thesis.tex")) << command;
    EXPECT_TRUE(fs::exists(out / ".robossis-output")) << command;
    fs::remove_all(out);
  }
}

// --- --out over one of the run's inputs: refused before any work, with or without --force -----------------------

TEST_F(HostileOutputsTest, OutOverAnInputOfTheRunIsRefusedAndTheInputKept) {
  // An HC trajectory inside an earlier transfer output: replacing that output whole would delete it.
  ASSERT_EQ(Robossis("transfer --scenario fig8 --no-plots --out " + Q(dir_ / "t1")).exit_code, 0);
  const std::string hc = Read(dir_ / "t1" / "hc.csv");
  for (const std::string force : {"", "--force "}) {
    ExpectError(Robossis(force + "transfer --hc " + Q(dir_ / "t1" / "hc.csv") + " --no-plots --out " + Q(dir_ / "t1")),
                "contains --hc");
    EXPECT_EQ(Read(dir_ / "t1" / "hc.csv"), hc);
  }
  // A session log replayed into its own session folder.
  ASSERT_EQ(Robossis("teleop --clock simulated --duration-s 0.5 --no-plots --out " + Q(dir_ / "tel")).exit_code, 0);
  ExpectError(Robossis("replay " + Q(dir_ / "tel" / "session.rlog") + " --no-plots --out " + Q(dir_ / "tel")),
              "--out '" + (dir_ / "tel").string() + "' contains LOG");
  EXPECT_TRUE(fs::exists(dir_ / "tel" / "session.rlog"));
  // An atlas given to render-compare as its own output, and an output inside the atlas.
  ASSERT_EQ(Robossis("workspace atlas --coarse --error-samples 0 --out " + Q(dir_ / "A")).exit_code, 0);
  ExpectError(Robossis("render-compare --fast --methods mesh --atlas " + Q(dir_ / "A") + " --out " + Q(dir_ / "A")),
              "is --atlas");
  ExpectError(Robossis("render-compare --fast --methods mesh --atlas " + Q(dir_ / "A") + " --out " +
                       Q(dir_ / "A" / "cmp")),
              "is inside --atlas");
  EXPECT_TRUE(fs::exists(dir_ / "A" / "manifest.json"));
  // A Motive take evaluated into its own folder (foreign, so only --force would have replaced it).
  const fs::path reference = MovingReference();
  ASSERT_EQ(Robossis("mocap simulate --reference " + Q(reference) + " --out " + Q(dir_ / "M" / "take.csv")).exit_code,
            0);
  ExpectError(Robossis("--force track-eval --mocap " + Q(dir_ / "M" / "take.csv") + " --rigid-body MovingRing " +
                       "--reference " + Q(reference) + " --no-plot --out " + Q(dir_ / "M")),
              "contains --mocap");
  EXPECT_TRUE(fs::exists(dir_ / "M" / "take.csv"));
  // A single output file over its input, and over the configs of --data-dir.
  const std::string before = Read(reference);
  ExpectError(Robossis("mocap simulate --reference " + Q(reference) + " --out " + Q(reference)), "is --reference");
  EXPECT_EQ(Read(reference), before);
  const fs::path data = DataDirWith("rsr.yaml", [](const std::string& t) { return t; });
  const std::string hal_yaml = Read(data / "config" / "hal.yaml");
  ExpectError(Robossis("--data-dir " + Q(data) + " hal config --out " + Q(data / "config" / "hal.yaml")),
              "is inside --data-dir");
  EXPECT_EQ(Read(data / "config" / "hal.yaml"), hal_yaml);
  // Elsewhere in the data dir is fine (the README's `hal config --out data/hal/...`).
  EXPECT_EQ(Robossis("--data-dir " + Q(data) + " hal config --out " + Q(data / "hal" / "new.hal")).exit_code, 0);
  ExpectNoTemporaries();
}

// --- Single output files: atomic, no temporary left, never a library's text -------------------------------------

TEST_F(HostileOutputsTest, SingleOutputFilesRefuseFoldersAndLeaveNoTemporaries) {
  const fs::path reference = MovingReference();
  fs::create_directories(dir_ / "adir");
  ExpectError(Robossis("hal config --out " + Q(dir_ / "adir")),
              "--out: '" + (dir_ / "adir").string() + "' is a folder");
  ExpectError(Robossis("mocap simulate --reference " + Q(reference) + " --out " + Q(dir_ / "adir")), "is a folder");
  ExpectNoTemporaries();
  // The leftovers of runs that died (PID 999999999 is above Linux's pid_max) are removed by the next run.
  Write("take.csv.tmp-999999999", "half");
  Write("robossis.hal.tmp-999999999", "half");
  ASSERT_EQ(Robossis("mocap simulate --reference " + Q(reference) + " --out " + Q(dir_ / "take.csv")).exit_code, 0);
  ASSERT_EQ(Robossis("hal config --out " + Q(dir_ / "robossis.hal")).exit_code, 0);
  EXPECT_FALSE(fs::exists(dir_ / "take.csv.tmp-999999999"));
  EXPECT_FALSE(fs::exists(dir_ / "robossis.hal.tmp-999999999"));
  EXPECT_THAT(Read(dir_ / "robossis.hal"), HasSubstr("Generated by `robossis hal config"));
  ExpectNoTemporaries();
}

// --- An atlas is committed only when everything, atlas_error.json included, succeeded -----------------------------

TEST_F(HostileOutputsTest, AFailedOrInterruptedAtlasNeverLooksComplete) {
  // A config the error measurement reads is refused before the build, and no atlas appears.
  const fs::path data = DataDirWith("haptics.yaml", [](const std::string& t) { return t + "bogus_key: 1\n"; });
  ExpectError(Robossis("--data-dir " + Q(data) + " workspace atlas --coarse --error-samples 2 --out " + Q(dir_ / "A")),
              "'bogus_key'");
  EXPECT_FALSE(fs::exists(dir_ / "A"));
  // Interrupted during the error measurement (SIGINT after the slices were built): the target does not appear.
  const CommandRun interrupted = robossis::testing::RunShell(
      "timeout -s INT 6 " + std::string(ROBOSSIS_BINARY) + " workspace atlas --coarse --error-samples 100000 --out " +
      Q(dir_ / "B") + " >/dev/null 2>&1; echo $?");
  EXPECT_THAT(interrupted.output, HasSubstr("124"));  // timeout's code: the run was still going
  EXPECT_FALSE(fs::exists(dir_ / "B"));
  // A complete run holds the atlas and its error measurement together.
  ASSERT_EQ(Robossis("workspace atlas --coarse --error-samples 2 --out " + Q(dir_ / "C")).exit_code, 0);
  EXPECT_TRUE(fs::exists(dir_ / "C" / "manifest.json"));
  EXPECT_TRUE(fs::exists(dir_ / "C" / "atlas_error.json"));
  ExpectError(Robossis("workspace query --atlas " + Q(dir_ / "B") + " --pose 0,0,284,0,0,0"), "does not exist");
}

}  // namespace
