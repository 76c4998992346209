// The HAL config and the generated HAL files: every number comes from actuation.yaml or hal.yaml, and the files
// shipped in data/hal/ are the generator's current output.

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "robot/drivers/hal_file.h"
#include "src/core/config.h"

namespace robossis::drivers {
namespace {

std::filesystem::path DataDir() { return DefaultDataDir(); }
HalConfig LoadHalConfig() { return HalConfig::FromYaml(DataDir() / "config" / "hal.yaml"); }
actuation::ActuationConfig LoadActuationConfig() {
  return actuation::ActuationConfig::FromYaml(DataDir() / "config" / "actuation.yaml");
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The `setp NAME VALUE` lines of a HAL file.
std::map<std::string, double> SetpValues(const std::string& hal) {
  std::map<std::string, double> values;
  std::istringstream lines(hal);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string cmd, name, value;
    if (words >> cmd >> name >> value && cmd == "setp") values[name] = std::stod(value);
  }
  return values;
}

TEST(HalFileTest, ShippedFilesAreTheGeneratorsCurrentOutput) {
  for (HalTarget target : {HalTarget::kSoftwareStepgen, HalTarget::kMesa7i76e}) {
    const std::filesystem::path shipped = DataDir() / "hal" / ShippedHalFileName(target);
    EXPECT_EQ(ReadFile(shipped), GenerateHalFile(LoadHalConfig(), LoadActuationConfig(), target))
        << shipped << " is stale: run `robossis hal config --target " << ToString(target) << " --out " << shipped
        << "`";
  }
}

TEST(HalFileTest, StepgenScalesAndLimitsAreTheActuationConfigs) {
  const HalConfig hal = LoadHalConfig();
  const actuation::ActuationConfig act = LoadActuationConfig();
  const struct {
    HalTarget target;
    std::string prefix;
  } cases[] = {{HalTarget::kSoftwareStepgen, "stepgen."}, {HalTarget::kMesa7i76e, "hm2_7i76e.0.stepgen.0"}};
  for (const auto& c : cases) {
    const auto values = SetpValues(GenerateHalFile(hal, act, c.target));
    for (int m = 0; m < actuation::kNumMotors; ++m) {
      const std::string gen = c.prefix + std::to_string(m);
      ASSERT_TRUE(values.count(gen + ".position-scale")) << ToString(c.target) << " " << gen;
      const double scale = values.at(gen + ".position-scale");
      const double maxvel = values.at(gen + ".maxvel");
      const double maxaccel = values.at(gen + ".maxaccel");
      EXPECT_NEAR(scale, act.motors[m].steps_per_unit, 1e-10 * scale) << gen;
      // At maxvel the motor steps at its cap: the follower's joint-speed cap of eq. 17.
      EXPECT_NEAR(maxvel * scale, act.motors[m].max_step_rate_hz, 1e-8 * act.motors[m].max_step_rate_hz) << gen;
      EXPECT_NEAR(maxaccel * hal.accel_time_s, maxvel, 1e-10 * maxvel) << gen;
      EXPECT_EQ(values.at(gen + ".steplen"), hal.timing.steplen_ns) << gen;
      EXPECT_EQ(values.at(gen + ".dirsetup"), hal.timing.dirsetup_ns) << gen;
    }
  }
}

TEST(HalFileTest, FilesCarryTheConfiguredThreadsAndComponent) {
  HalConfig hal = LoadHalConfig();
  hal.component_name = "rsr2";
  hal.base_period_ns = 25000;
  const std::string file = GenerateHalFile(hal, LoadActuationConfig(), HalTarget::kSoftwareStepgen);
  EXPECT_NE(file.find("period1=25000 "), std::string::npos);
  EXPECT_NE(file.find("net rsr2-j5-pos-cmd stepgen.5.position-cmd"), std::string::npos);
  EXPECT_EQ(file.find("robossis-"), std::string::npos);
}

TEST(HalConfigTest, BadValuesAreNamedErrors) {
  HalConfig hal = LoadHalConfig();
  hal.component_name = "two words";
  EXPECT_THROW(hal.Validate(), std::invalid_argument);
  hal = LoadHalConfig();
  hal.feedback_timeout_s = 0.5 * hal.servo_period_s();
  try {
    hal.Validate();
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("two servo periods"), std::string::npos) << e.what();
  }
  hal = LoadHalConfig();
  hal.base_period_ns = 2 * hal.servo_period_ns;
  EXPECT_THROW(hal.Validate(), std::invalid_argument);
  try {
    ParseHalTarget("7i96");
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'stepgen' or '7i76e'"), std::string::npos) << e.what();
  }
}

TEST(HalConfigTest, MissingKeyNamesTheFileAndTheKey) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "robossis-hal-missing.yaml";
  std::string yaml = ReadFile(DataDir() / "config" / "hal.yaml");
  const auto pos = yaml.find("  dirhold_ns:");
  ASSERT_NE(pos, std::string::npos);
  yaml.erase(pos, yaml.find('\n', pos) - pos + 1);
  {
    std::ofstream(file) << yaml;
  }
  try {
    HalConfig::FromYaml(file);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("dirhold_ns"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("robossis-hal-missing.yaml"), std::string::npos) << e.what();
  }
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace robossis::drivers
