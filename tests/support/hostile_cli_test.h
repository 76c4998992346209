#pragma once
// The fixture of the hostile-input CLI suites: a folder of each test's own, small file helpers, an edited copy of
// the project's data folder, a moving reference trajectory, shell quoting, and the check every refused input must
// pass (exit 1, one "robossis: error: ..." line naming what is wrong, never a library's raw text).

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "src/core/config.h"
#include "tests/support/robossis_cli.h"

namespace robossis::testing {

class HostileCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() / ("robossis_hostile_" + std::to_string(::getpid()) + "_" +
                                                     info->test_suite_name() + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path Write(const std::string& name, const std::string& text) const {
    const std::filesystem::path p = dir_ / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  static std::string Read(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream os;
    os << in.rdbuf();
    return os.str();
  }
  // A fresh copy of the project's data folder (replacing the test's previous copy) whose config `name` (e.g.
  // "rsr.yaml") is replaced by edit(its text).
  template <typename Edit>
  std::filesystem::path DataDirWith(const std::string& name, Edit edit) const {
    const std::filesystem::path data = dir_ / "data";
    std::filesystem::remove_all(data);
    std::filesystem::copy(DefaultDataDir(), data, std::filesystem::copy_options::recursive);
    const std::filesystem::path file = data / "config" / name;
    const std::string text = Read(file);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << edit(text);
    return data;
  }
  // `text` with the first `from` replaced by `to` (the test fails if `from` is not there).
  static std::string Replace(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
  }
  // A moving reference trajectory (15 s at 100 Hz, mm and degrees about the home pose) for the mocap commands.
  std::filesystem::path MovingReference(const std::string& name = "commanded.csv") const {
    std::ostringstream csv;
    csv << "t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n";
    for (int k = 0; k <= 1500; ++k) {
      const double t = k * 0.01, e = 0.5 * (1 - std::cos(2 * M_PI * t / 15.0));
      csv << t << "," << e * 20 * std::sin(0.7 * t) << "," << e * 15 * std::sin(1.1 * t + 1) << ","
          << 284 + e * 8 * std::sin(0.9 * t) << "," << e * 5 * std::sin(1.3 * t) << ","
          << e * 4 * std::sin(0.8 * t + 2) << "," << e * 9 * std::sin(0.6 * t + 0.5) << "\n";
    }
    return Write(name, csv.str());
  }
  // `robossis ARGS` with a time limit: an input that used to hang fails its test instead of stalling the suite.
  static CommandRun RunBounded(const std::string& args, bool with_stderr = true) {
    return RunShell("timeout 300 " + std::string(ROBOSSIS_BINARY) + " " + args +
                    (with_stderr ? " 2>&1" : " 2>/dev/null"));
  }
  // The run failed with exit 1 and one "robossis: error: ..." line containing `expected`.
  static void ExpectError(const CommandRun& run, const std::string& expected) {
    using ::testing::HasSubstr;
    using ::testing::Not;
    EXPECT_EQ(run.exit_code, 1) << run.output;
    EXPECT_THAT(run.output, HasSubstr("robossis: error: ")) << run.output;
    EXPECT_THAT(run.output, HasSubstr(expected)) << run.output;
    EXPECT_THAT(run.output, Not(HasSubstr("filesystem error"))) << run.output;
    EXPECT_THAT(run.output, Not(HasSubstr("bad_alloc"))) << run.output;
  }
  static std::string Q(const std::string& s) {  // single-quoted for the shell
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
  }
  static std::string Q(const std::filesystem::path& p) { return Q(p.string()); }

  std::filesystem::path dir_;
};

}  // namespace robossis::testing
