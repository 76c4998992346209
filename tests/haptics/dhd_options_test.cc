// The `--device dhd[:key=value,...]` spec and dhd.yaml.

#include <gtest/gtest.h>

#include "haptics/device/dhd_options.h"
#include "src/core/config.h"

namespace robossis::haptics {
namespace {

TEST(DhdOptions, PlainDhdKeepsTheDefaults) {
  const DhdOptions o = ParseDhdOptions("dhd");
  EXPECT_TRUE(o.library_path.empty());
  EXPECT_EQ(o.serial, -1);
  EXPECT_EQ(o.index, -1);
  EXPECT_FALSE(o.enable_hold);
}

TEST(DhdOptions, KeysOverrideTheDefaults) {
  const DhdOptions o = ParseDhdOptions("dhd:serial=123,lib=/opt/fd/lib/libdhd.so,window_ms=4");
  EXPECT_EQ(o.serial, 123);
  EXPECT_EQ(o.library_path, "/opt/fd/lib/libdhd.so");
  EXPECT_EQ(o.velocity_window_ms, 4);
  EXPECT_EQ(ParseDhdOptions("dhd:index=1").index, 1);
  const DhdOptions held = ParseDhdOptions("dhd:drd=/opt/fd/lib/libdrd.so");
  EXPECT_TRUE(held.enable_hold);
  EXPECT_EQ(held.drd_library_path, "/opt/fd/lib/libdrd.so");
  EXPECT_TRUE(ParseDhdOptions("dhd:hold=1").enable_hold);
}

TEST(DhdOptions, BadSpecsNameTheKeyAndWhatWasExpected) {
  auto message = [](const std::string& spec) {
    try {
      ParseDhdOptions(spec);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("sim").find("expected 'dhd'"), std::string::npos);
  EXPECT_NE(message("dhd:serial=abc").find("'serial' expected an integer"), std::string::npos);
  EXPECT_NE(message("dhd:index=-2").find("'index'"), std::string::npos);
  EXPECT_NE(message("dhd:colour=red").find("unknown key 'colour'"), std::string::npos);
  EXPECT_NE(message("dhd:serial").find("expected key=value"), std::string::npos);
  EXPECT_NE(message("dhd:serial=1,index=0").find("not both"), std::string::npos);
  EXPECT_NE(message("dhd:window_ms=0").find("'window_ms'"), std::string::npos);
}

TEST(DhdOptions, TheShippedConfigShortensTheSdkVelocityWindow) {
  const DhdOptions o = DhdOptionsFromYaml(DefaultDataDir() / "config" / "dhd.yaml");
  EXPECT_GE(o.velocity_window_ms, 1);
  EXPECT_LT(o.velocity_window_ms, 20);  // the SDK's default window
}

}  // namespace
}  // namespace robossis::haptics
