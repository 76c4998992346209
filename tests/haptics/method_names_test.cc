// The one parser of rendering method names: exact names only, no empty entry anywhere in a list.

#include <stdexcept>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "haptics/rendering/method_names.h"

namespace robossis::haptics {
namespace {

using ::testing::HasSubstr;

std::string ErrorOf(const std::string& list) {
  try {
    ParseMethodList(list, "--methods");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(MethodNamesTest, ListsParseExactlyAndInOrder) {
  EXPECT_EQ(ParseMethodList("proxy", "--methods"), std::vector<std::string>{"proxy"});
  EXPECT_EQ(ParseMethodList("mesh,pointcloud-pc,proxy", "--methods"),
            (std::vector<std::string>{"mesh", "pointcloud-pc", "proxy"}));
  std::string all;
  for (const std::string& m : KnownMethods()) all += (all.empty() ? "" : ",") + m;
  EXPECT_EQ(ParseMethodList(all, "--methods"), KnownMethods());
}

TEST(MethodNamesTest, EmptyEntriesAreErrorsWhereverTheyAre) {
  for (const std::string& list : std::vector<std::string>{"proxy,", ",proxy", "proxy,,mesh", ",", ",,"}) {
    EXPECT_THAT(ErrorOf(list), HasSubstr("--methods: empty entry")) << list;
    EXPECT_THAT(ErrorOf(list), HasSubstr("known: " + KnownMethodsText())) << list;
  }
  EXPECT_THAT(ErrorOf("proxy,"), HasSubstr("empty entry 2 in 'proxy,'"));
  EXPECT_THAT(ErrorOf(""), HasSubstr("--methods: expected a comma-separated list of methods, got nothing"));
}

TEST(MethodNamesTest, UnknownRepeatedAndBlankNamesAreErrors) {
  EXPECT_THAT(ErrorOf("proxy,magic"), HasSubstr("--methods: unknown method 'magic'; known: pointcloud, "));
  EXPECT_THAT(ErrorOf(" proxy"), HasSubstr("unknown method ' proxy'"));
  EXPECT_THAT(ErrorOf("PROXY"), HasSubstr("unknown method 'PROXY'"));
  EXPECT_THAT(ErrorOf("proxy,mesh,proxy"), HasSubstr("'proxy' is listed twice"));
  EXPECT_EQ(ParseMethodName("mesh-live", "--method"), "mesh-live");
  try {
    ParseMethodName("", "--method");
    ADD_FAILURE() << "an empty name accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "--method: expected a rendering method, got an empty name; known: " +
                                         KnownMethodsText());
  }
}

}  // namespace
}  // namespace robossis::haptics
