// libFuzzer target: every YAML config loader of data/config (rsr, sigma7, haptics, transfer, actuation, sim,
// follower, leader, link, panel, hal, dhd) on the same bytes, parsed once. A loader either returns a validated config
// or throws std::runtime_error / std::invalid_argument.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>

#include "haptics/device/dhd_options.h"
#include "haptics/haptics_config.h"
#include "haptics/transfer/transfer_config.h"
#include "robot/actuation/actuation_config.h"
#include "robot/drivers/hal_config.h"
#include "robot/rsr_model.h"
#include "robot/sigma7_model.h"
#include "robot/sim/sim_config.h"
#include "src/core/config.h"
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
  // The file checks, the parse and the duplicate-key check once (three quarters of the time when every loader
  // loaded the file itself), then each loader on a fresh log of read keys, as FromYaml gives it.
  std::optional<ConfigNode> parsed;
  Try([&] { parsed.emplace(ConfigNode::Load(file)); });
  if (!parsed) return 0;
  const ConfigNode& doc = *parsed;
  Try([&] { robot::RsrModel::FromConfig(doc.ForAnotherLoader()); });
  Try([&] { robot::Sigma7Model::FromConfig(doc.ForAnotherLoader()); });
  Try([&] { haptics::HapticsConfig::FromConfig(doc.ForAnotherLoader()); });
  Try([&] { transfer::TransferConfig::FromConfig(doc.ForAnotherLoader()); });
  Try([&] { actuation::ActuationConfig::FromConfig(doc.ForAnotherLoader()); });
  Try([&] { sim::LoadSimConfig(doc.ForAnotherLoader(), fuzz::FuzzDir()); });
  Try([&] { teleop::FollowerConfig::FromConfig(doc.ForAnotherLoader(), transfer::SpeedCaps{}); });
  Try([&] { teleop::LeaderConfig::FromConfig(doc.ForAnotherLoader()); });
  Try([&] { link::LinkTuning::FromConfig(doc.ForAnotherLoader()); });
  Try([&] { panel::PanelConfig::FromConfig(doc.ForAnotherLoader()); });
  Try([&] { drivers::HalConfig::FromConfig(doc.ForAnotherLoader()); });
  Try([&] { haptics::DhdOptionsFromConfig(doc.ForAnotherLoader()); });
  return 0;
}
