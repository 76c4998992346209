// libFuzzer target: every YAML config loader of data/config (rsr, sigma7, haptics, transfer, actuation, sim,
// follower, leader, link, panel, hal, dhd) on the same bytes. A loader either returns a validated config or throws
// std::runtime_error / std::invalid_argument.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "haptics/device/dhd_options.h"
#include "haptics/haptics_config.h"
#include "haptics/transfer/transfer_config.h"
#include "robot/actuation/actuation_config.h"
#include "robot/drivers/hal_config.h"
#include "robot/rsr_model.h"
#include "robot/sigma7_model.h"
#include "robot/sim/sim_config.h"
#include "src/link/link_options.h"
#include "src/panel/panel_config.h"
#include "src/teleop/follower_config.h"
#include "src/teleop/leader_config.h"
#include "tests/fuzz/fuzz_input_file.h"

namespace {
template <typename Fn>
void Try(Fn fn) {
  try {
    fn();
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace robossis;
  const auto file = fuzz::InputFile(data, size, "config.yaml");
  Try([&] { robot::RsrModel::FromYaml(file); });
  Try([&] { robot::Sigma7Model::FromYaml(file); });
  Try([&] { haptics::HapticsConfig::FromYaml(file); });
  Try([&] { transfer::TransferConfig::FromYaml(file); });
  Try([&] { actuation::ActuationConfig::FromYaml(file); });
  Try([&] { sim::LoadSimConfig(file, fuzz::FuzzDir()); });
  Try([&] { teleop::FollowerConfig::FromYaml(file, transfer::SpeedCaps{}); });
  Try([&] { teleop::LeaderConfig::FromYaml(file); });
  Try([&] { link::LinkTuning::FromYaml(file); });
  Try([&] { panel::PanelConfig::FromYaml(file); });
  Try([&] { drivers::HalConfig::FromYaml(file); });
  Try([&] { haptics::DhdOptionsFromYaml(file); });
  return 0;
}
