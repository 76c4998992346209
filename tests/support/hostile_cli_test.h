#pragma once
// The fixture of the hostile-input CLI suites: a folder of each test's own, small file helpers, shell quoting, and
// the check every refused input must pass (exit 1, one "robossis: error: ..." line naming what is wrong, never a
// library's raw text).

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

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
