// Hostile command lines and configs of the motion commands (`robossis move`, `robossis transfer`, the teleop
// runtime's options): moves shorter than one actuation tick, speed caps and rates without bounds, the step-rate
// figure one window edge off, the actuation rate in two configs, method lists with empty names. Each runs the
// robossis binary as a user would.

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "src/core/config.h"
#include "tests/support/hostile_cli_test.h"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using robossis::testing::CommandRun;

class HostileMotionTest : public robossis::testing::HostileCliTest {
 protected:
  fs::path Out() const { return dir_ / "out"; }
  std::string MoveArgs(const std::string& extra) const {
    return "move --no-plots --out " + Q(Out()) + " " + extra;
  }
  static nlohmann::json Json(const CommandRun& run) {
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return run.exit_code == 0 ? nlohmann::json::parse(run.output) : nlohmann::json::object();
  }
};

// --- Moves shorter than one actuation tick; the peak of the profile, not the mean -------------------------------

TEST_F(HostileMotionTest, AMoveShorterThanOneTickIsRefusedNamingDurationS) {
  // 5 mm in 1e-15 s: zero ticks, so no sample between the ends was judged (it exited 0 and moved).
  const CommandRun run = RunBounded(MoveArgs("--delta-mm 0,0,5 --duration-s 1e-15"));
  ExpectError(run, "--duration-s 1e-15 s is shorter than one actuation tick (0.0001 s at 10000 Hz");
  EXPECT_THAT(run.output, HasSubstr("the shortest --duration-s within the caps is 0.786 s"));
  EXPECT_FALSE(fs::exists(Out()));
  // Half a tick, and a peak speed that makes the move last a femtosecond.
  ExpectError(RunBounded(MoveArgs("--delta-mm 0,0,0.0001 --duration-s 5e-5")), "shorter than one actuation tick");
  ExpectError(RunBounded(MoveArgs("--delta-mm 0,0,5 --speed-mm-s 1e300")),
              "the duration of --speed-mm-s/--speed-deg-s");
  ExpectError(RunBounded(MoveArgs("--delta-mm 0,0,5 --speed-mm-s 1e300")), "shorter than one actuation tick");
  EXPECT_FALSE(fs::exists(Out()));
}

TEST_F(HostileMotionTest, ASubTickMoveToAnInfeasiblePoseIsRefusedAsLeavingTheWorkspace) {
  // 200 mm up in 1e-15 s ends far outside the strokes: the end pose is always among the samples.
  const CommandRun run = RunBounded(MoveArgs("--delta-mm 0,0,200 --duration-s 1e-15"));
  ExpectError(run, "move: the move leaves the RSR's workspace (joint limits) at 100.00 % of its path");
  EXPECT_FALSE(fs::exists(Out()));
}

TEST_F(HostileMotionTest, ThePeakSpeedOfAOneTickMoveIsHeldAgainstTheCaps) {
  // 0.9 µm in one tick: a mean of 9 mm/s under the 10 mm/s cap, but eq. 9 peaks at pi/2 of it, 14.1 mm/s.
  const CommandRun run = RunBounded(MoveArgs("--delta-mm 0,0,0.0009 --duration-s 1e-4"));
  ExpectError(run, "move: the move breaks the speed caps (caps 10 mm/s, 1 deg/s): its peak speeds are 14.1372 mm/s");
  EXPECT_THAT(run.output, HasSubstr("the shortest --duration-s within the caps is 0.001 s"));
  // Within the caps at its peak, one tick is a move like any other.
  EXPECT_EQ(RunBounded(MoveArgs("--delta-mm 0,0,0.0005 --duration-s 1e-4")).exit_code, 0);
}

// --- Speed caps: one checker with documented maxima, for the command line and transfer.yaml -----------------------

TEST_F(HostileMotionTest, SpeedCapsAreBoundedOnEveryCommandThatTakesThem) {
  const std::string linear = "--max-speed-mm-s: expected a speed cap in (0, 1000] mm/s, got ";
  const std::string angular = "--max-angular-speed-deg-s: expected a speed cap in (0, 360] deg/s, got ";
  ExpectError(RunBounded(MoveArgs("--delta-mm 0,0,5 --duration-s 1 --max-speed-mm-s 1e300")), linear + "1e+300 mm/s");
  ExpectError(RunBounded(MoveArgs("--delta-mm 0,0,5 --duration-s 1 --max-speed-mm-s 1000.5")), linear + "1000.5 mm/s");
  ExpectError(RunBounded(MoveArgs("--delta-mm 0,0,5 --duration-s 1 --max-speed-mm-s nan")), linear + "nan mm/s");
  ExpectError(RunBounded(MoveArgs("--delta-deg 0,0,1 --duration-s 1 --max-angular-speed-deg-s 1e300")),
              angular + "1e+300 deg/s");
  ExpectError(RunBounded(MoveArgs("--delta-deg 0,0,1 --duration-s 1 --max-angular-speed-deg-s -1")),
              angular + "-1 deg/s");
  ExpectError(RunBounded("transfer --scenario slow --no-plots --max-speed-mm-s 1e300 --out " + Q(Out())),
              linear + "1e+300 mm/s");
  ExpectError(RunBounded("teleop --clock simulated --follower recorder --duration-s 0.1 --no-plots "
                         "--max-speed-mm-s 1e300 "
                  "--out " + Q(Out())),
              linear + "1e+300 mm/s");
  ExpectError(RunBounded("teleop --clock simulated --follower recorder --duration-s 0.1 --no-plots "
                  "--max-angular-speed-deg-s 400 --out " + Q(Out())),
              angular + "400 deg/s");
  EXPECT_FALSE(fs::exists(Out()));
  // The maxima themselves are caps like any other, and --help says what they are.
  EXPECT_EQ(RunBounded(MoveArgs("--delta-mm 0,0,5 --duration-s 1 --max-speed-mm-s 1000 --max-angular-speed-deg-s 360"))
                .exit_code,
            0);
  EXPECT_THAT(RunBounded("move --help").output, HasSubstr("Linear speed cap in (0, 1000] mm/s"));
  EXPECT_THAT(RunBounded("teleop --help").output, HasSubstr("Angular speed cap in (0, 360] deg/s"));
}

TEST_F(HostileMotionTest, SpeedCapsInTransferYamlGoThroughTheSameChecker) {
  const fs::path data = DataDirWith("transfer.yaml", [](const std::string& t) {
    return Replace(t, "max_linear_speed_mm_s: 10", "max_linear_speed_mm_s: 1e300");
  });
  const CommandRun run = RunBounded("--data-dir " + Q(data) + " " + MoveArgs("--delta-mm 0,0,5 --duration-s 1"));
  ExpectError(run, "transfer.yaml: transfer config: 'caps.max_linear_speed_mm_s': expected a speed cap in (0, 1000] "
                   "mm/s, got 1e+300 mm/s");
  const fs::path angular = DataDirWith("transfer.yaml", [](const std::string& t) {
    return Replace(t, "max_angular_speed_deg_s: 1", "max_angular_speed_deg_s: 0");
  });
  ExpectError(RunBounded("--data-dir " + Q(angular) + " " + MoveArgs("--delta-mm 0,0,5 --duration-s 1")),
              "'caps.max_angular_speed_deg_s': expected a speed cap in (0, 360] deg/s, got 0 deg/s");
  EXPECT_FALSE(fs::exists(Out()));
}

// --- The step-rate figure: a half-open window -------------------------------------------------------------------

TEST_F(HostileMotionTest, AStepTrainAtTheMotorsMaximumRateReadsThatRate) {
  // 40 mm in 2 s peaks at 31 mm/s of stroke, above the linear motors' 4000 steps/s (20 mm/s): the actuation holds
  // them at exactly 4000 Hz, which the closed window read as 4100 Hz.
  const nlohmann::json summary =
      Json(RunBounded(MoveArgs("--json --delta-mm 0,0,40 --duration-s 2 --max-speed-mm-s 40"), false));
  EXPECT_GT(summary.value("rate_limited_ticks", 0), 1000) << summary.dump();
  EXPECT_DOUBLE_EQ(summary.value("max_step_rate_hz", 0.0), 4000.0) << summary.dump();
}

// --- Rates: bounded, in transfer.yaml, the actuation rate in one place ----------------------------------------

TEST_F(HostileMotionTest, TransferAndActuationRatesOutOfTheirRangesAreRefusedNamingFileAndKey) {
  struct Case {
    std::string transfer_hz, actuation_hz, key, expected;
  };
  const std::vector<Case> cases = {
      {"0.001", "0.001", "'rates.transfer_rate_hz'", "expected a rate in [100, 10000] Hz, got 0.001"},  // exited 0
      {"99", "990", "'rates.transfer_rate_hz'", "expected a rate in [100, 10000] Hz, got 99"},
      {"1e9", "1e9", "'rates.transfer_rate_hz'", "expected a rate in [100, 10000] Hz, got 1e+09"},  // hung
      {"1000", "1e7", "'rates.actuation_rate_hz'", "expected a rate in [transfer_rate_hz, 20000] Hz"},  // hung
      {"1000", "20001", "'rates.actuation_rate_hz'", "got 20001"},
      {"1000", "500", "'rates.actuation_rate_hz'", "(transfer_rate_hz is 1000), got 500"},
  };
  for (const Case& c : cases) {
    const fs::path data = DataDirWith("transfer.yaml", [&](const std::string& t) {
      return Replace(Replace(t, "transfer_rate_hz: 1000 ", "transfer_rate_hz: " + c.transfer_hz + " "),
                     "actuation_rate_hz: 10000 ", "actuation_rate_hz: " + c.actuation_hz + " ");
    });
    const CommandRun run = RunBounded("--data-dir " + Q(data) + " " + MoveArgs("--delta-mm 0,0,1 --duration-s 1"));
    ExpectError(run, "transfer.yaml: transfer config: " + c.key);
    EXPECT_THAT(run.output, HasSubstr(c.expected)) << c.transfer_hz << " " << c.actuation_hz;
  }
  EXPECT_FALSE(fs::exists(Out()));
}

TEST_F(HostileMotionTest, TheRateBoundsThemselvesAreAccepted) {
  const fs::path data = DataDirWith("transfer.yaml", [](const std::string& t) {
    return Replace(Replace(t, "transfer_rate_hz: 1000 ", "transfer_rate_hz: 100 "), "actuation_rate_hz: 10000 ",
                   "actuation_rate_hz: 20000 ");
  });
  const nlohmann::json summary =
      Json(RunBounded("--data-dir " + Q(data) + " " + MoveArgs("--json --delta-mm 0,0,1 --duration-s 0.5"), false));
  // The move (0.5 s) and its settling (0.2 s) at transfer.yaml's 20 kHz: the chain ticks at that one rate.
  EXPECT_EQ(summary.value("ticks_10khz", 0), 14000) << summary.dump();
}

TEST_F(HostileMotionTest, TheActuationRateLivesInTransferYamlAlone) {
  // The shipped actuation.yaml has no rate of its own.
  EXPECT_THAT(Read(robossis::DefaultDataDir() / "config" / "actuation.yaml"), Not(HasSubstr("\nactuation_rate_hz:")));
  // A rate put back into actuation.yaml (which could disagree with transfer.yaml's silently) is refused, saying
  // where the rate lives now.
  const fs::path data = DataDirWith("actuation.yaml", [](const std::string& t) {
    return Replace(t, "ik_correction_gain_per_s: 20", "actuation_rate_hz: 5000\nik_correction_gain_per_s: 20");
  });
  for (const std::string& command :
       {MoveArgs("--delta-mm 0,0,1 --duration-s 1"), std::string("hal config --target stepgen")}) {
    const CommandRun run = RunBounded("--data-dir " + Q(data) + " " + command);
    ExpectError(run, "actuation.yaml: 'actuation_rate_hz': this key moved to transfer.yaml 'rates.actuation_rate_hz'");
  }
  // actuation.yaml's checks that need the rate take transfer.yaml's: 75 000 steps/s cannot fit the per-tick pulse
  // buffer at 10 kHz.
  const fs::path fast = DataDirWith("actuation.yaml", [](const std::string& t) {
    return Replace(t, "max_step_rate_hz: 4000 ", "max_step_rate_hz: 75000 ");
  });
  const CommandRun run = RunBounded("--data-dir " + Q(fast) + " " + MoveArgs("--delta-mm 0,0,1 --duration-s 1"));
  ExpectError(run, "actuation.yaml: actuation config: motor 1: 'max_step_rate_hz' 75000");
  EXPECT_THAT(run.output, HasSubstr("(transfer.yaml 'rates.actuation_rate_hz')"));
  EXPECT_FALSE(fs::exists(Out()));
}

// --- Method names: one parser, no empty names -------------------------------------------------------------------

TEST_F(HostileMotionTest, MethodListsWithEmptyEntriesAreRefusedWithTheKnownMethods) {
  const std::string known = "known: pointcloud, pointcloud-safe, pointcloud-pc, mesh, mesh-live, mesh-proxy, "
                            "mesh-proxy-safe, proxy, proxy-safe, proxy-pc";
  for (const std::string& list : std::vector<std::string>{"proxy,", ",proxy", "proxy,,pointcloud", ","}) {
    const CommandRun run =
        RunBounded("render-compare --fast --scenario strike --methods " + Q(list) + " --out " + Q(Out()));
    ExpectError(run, "--methods: empty entry");
    EXPECT_THAT(run.output, HasSubstr(known)) << list;
  }
  ExpectError(RunBounded("render-compare --fast --scenario strike --methods '' --out " + Q(Out())),
              "--methods: expected a comma-separated list of methods, got nothing; " + known);
  ExpectError(RunBounded("render-compare --fast --scenario strike --methods ' proxy' --out " + Q(Out())),
              "--methods: unknown method ' proxy'; " + known);
  ExpectError(RunBounded("render-compare --fast --scenario strike --methods proxy,proxy --out " + Q(Out())),
              "--methods: 'proxy' is listed twice");
  EXPECT_FALSE(fs::exists(Out()));
}

TEST_F(HostileMotionTest, AnEmptyOrUnknownMethodNameIsRefusedEverywhere) {
  const std::string session = "teleop --clock simulated --follower recorder --duration-s 0.1 --no-plots ";
  // An empty --method ran the haptics.yaml default silently.
  ExpectError(RunBounded(session + "--method '' --out " + Q(Out())),
              "--method: expected a rendering method, got an empty name; known: pointcloud");
  ExpectError(RunBounded(session + "--method 'proxy,' --out " + Q(Out())),
              "--method: unknown method 'proxy,'; known: ");
  EXPECT_FALSE(fs::exists(Out()));
  const fs::path data = DataDirWith("haptics.yaml", [](const std::string& t) {
    const std::size_t at = t.find("hardware_default_method:");
    EXPECT_NE(at, std::string::npos);
    return t.substr(0, at) + "hardware_default_method: ''\n" + t.substr(t.find('\n', at) + 1);
  });
  ExpectError(RunBounded("--data-dir " + Q(data) + " " + session + "--out " + Q(Out())),
              "haptics.yaml: hardware_default_method: expected a rendering method, got an empty name; known: ");
}

}  // namespace
