#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "src/core/config.h"

namespace robossis {
namespace {

using ::testing::HasSubstr;

std::filesystem::path WriteYaml(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("robossis_config_test_" + name + ".yaml");
  std::ofstream(path) << text;
  return path;
}

// A loader in the style of the project's: reads two keys of the root and one child mapping, then checks.
void LoadSample(const std::filesystem::path& file) {
  const ConfigNode root = ConfigNode::Load(file);
  root.Number("rate_hz");
  root.NumberOr("gain", 1.0);
  root.Child("limits").Integer("count");
  root.RejectUnreadKeys();
}

std::string ErrorOf(const std::filesystem::path& file) {
  try {
    LoadSample(file);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(ConfigTest, AcceptsAFileWithOnlyKnownKeys) {
  EXPECT_EQ(ErrorOf(WriteYaml("ok", "rate_hz: 100\nlimits:\n  count: 3\n")), "");
}

TEST(ConfigTest, UnknownKeyNamesFileKeyLineAndNearestValidKey) {
  const auto file = WriteYaml("typo", "rate_hz: 100\ngian: 2\nlimits:\n  count: 3\n");
  const std::string e = ErrorOf(file);
  EXPECT_THAT(e, HasSubstr(file.string()));
  EXPECT_THAT(e, HasSubstr("'gian' (line 2): unknown key"));
  EXPECT_THAT(e, HasSubstr("nearest valid key is 'gain'"));
}

TEST(ConfigTest, UnknownKeyInsideAChildMappingNamesItsPath) {
  const std::string e = ErrorOf(WriteYaml("child", "rate_hz: 100\nlimits:\n  count: 3\n  cuont: 4\n"));
  EXPECT_THAT(e, HasSubstr("'limits.cuont' (line 4): unknown key; the nearest valid key is 'count'"));
}

TEST(ConfigTest, AnotherLoaderOfTheSameParseJudgesOnlyTheKeysItAsked) {
  const ConfigNode doc = ConfigNode::Load(WriteYaml("two_loaders", "rate_hz: 100\nlimits:\n  count: 3\n"));
  doc.Number("rate_hz");
  doc.Child("limits").Integer("count");
  EXPECT_NO_THROW(doc.RejectUnreadKeys());
  const ConfigNode second = doc.ForAnotherLoader();
  second.Number("rate_hz");
  try {
    second.RejectUnreadKeys();
    FAIL() << "'limits' was read by the first loader only";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("'limits' (line 2): unknown key"));
  }
}

TEST(ConfigTest, DuplicatedKeyIsAnErrorNamingBothLines) {
  const std::string e = ErrorOf(WriteYaml("dup", "rate_hz: 100\nlimits:\n  count: 3\nrate_hz: 200\n"));
  EXPECT_THAT(e, HasSubstr("'rate_hz': duplicated key (lines 1 and 4)"));
}

TEST(ConfigTest, IntegersAreExact) {
  for (const char* count : {"2.5", "2.0", "1e3", "abc"}) {
    const std::string e = ErrorOf(WriteYaml("int", std::string("rate_hz: 1\nlimits:\n  count: ") + count + "\n"));
    EXPECT_THAT(e, HasSubstr("'limits.count': expected an integer")) << count;
  }
}

TEST(ConfigTest, IntegerInRangeNamesTheRange) {
  const ConfigNode root = ConfigNode::Load(WriteYaml("range", "n: 0\n"));
  try {
    root.IntegerInRange("n", 1, 10);
    FAIL() << "accepted 0";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("'n': expected an integer in [1, 10], got 0"));
  }
}

TEST(ConfigTest, DirectoryAndDeviceAreNotCalledMissingOrEmpty) {
  const std::string dir = ErrorOf(std::filesystem::temp_directory_path());
  EXPECT_THAT(dir, HasSubstr("expected a regular file (YAML config file)"));
  EXPECT_THAT(ErrorOf("/dev/zero"), HasSubstr("expected a regular file (YAML config file)"));
  EXPECT_THAT(ErrorOf("/nonexistent/robossis.yaml"), HasSubstr("config file not found"));
}

TEST(ConfigTest, ASecondDocumentIsRefusedWithItsLine) {
  EXPECT_THAT(ErrorOf(WriteYaml("two", "n: 1\n---\nn: 2\n")), HasSubstr("two.yaml line 2: a second YAML document"));
  EXPECT_THAT(ErrorOf(WriteYaml("two_marked", "# c\n---\nn: 1\n---\nn: 2\n")),
              HasSubstr("line 4: a second YAML document"));
  EXPECT_NO_THROW(ConfigNode::Load(WriteYaml("one_marked", "---\nn: 1\n...\n")));
}

// Found by fuzz_yaml_configs: an alias of its own ancestor made the document a cycle, and walking it overflowed
// the stack.
TEST(ConfigTest, AnAliasIsRefusedWithItsLine) {
  EXPECT_THAT(ErrorOf(WriteYaml("cycle", "a: &u\n  b: *u\n")),
              HasSubstr("cycle.yaml line 2: a YAML alias ('*name'); expected no aliases in a config file"));
  EXPECT_THAT(ErrorOf(WriteYaml("shared", "a: &v 1\nb: 2\nc: *v\n")), HasSubstr("shared.yaml line 3: a YAML alias"));
  EXPECT_NO_THROW(ConfigNode::Load(WriteYaml("star_in_a_string", "a: '*v'\nb: \"&v\"\n")));
}

TEST(ConfigTest, OversizedFileIsRefusedBeforeParsing) {
  const auto file = WriteYaml("big", "rate_hz: 1\n# " + std::string(ConfigNode::kMaxFileBytes, 'x') + "\n");
  EXPECT_THAT(ErrorOf(file), HasSubstr("expected a YAML config file of at most"));
}

}  // namespace
}  // namespace robossis
