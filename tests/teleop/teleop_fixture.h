#pragma once
// Shared set-up of the teleoperation tests: the models and configs of data/config, a coarse boundary atlas for the
// mesh methods (built once per test binary), and a leader link that keeps what the leader sent.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "geometry/boundary_atlas.h"
#include "haptics/haptics_config.h"
#include "haptics/rendering/renderer_factory.h"
#include "haptics/transfer/transfer_config.h"
#include "robot/rsr_model.h"
#include "robot/sigma7_model.h"
#include "src/core/config.h"
#include "src/teleop/leader_config.h"
#include "src/teleop/link.h"
#include "tests/support/scratch_dir.h"

namespace robossis::teleop::testing {

inline const robot::RsrModel& Rsr() {
  static const robot::RsrModel m = robot::RsrModel::Default();
  return m;
}
inline const robot::Sigma7Model& Sigma7() {
  static const robot::Sigma7Model m = robot::Sigma7Model::Default();
  return m;
}
inline std::filesystem::path ConfigPath(const std::string& name) { return DefaultDataDir() / "config" / name; }
inline const haptics::HapticsConfig& Haptics() {
  static const haptics::HapticsConfig c = haptics::HapticsConfig::FromYaml(ConfigPath("haptics.yaml"));
  return c;
}
inline LeaderConfig Leader() { return LeaderConfig::FromYaml(ConfigPath("leader.yaml")); }
inline transfer::TransferConfig Transfer() { return transfer::TransferConfig::FromYaml(ConfigPath("transfer.yaml")); }
inline std::filesystem::path FastHand() { return DefaultDataDir() / "teleop" / "fast_hand.csv"; }
inline std::filesystem::path RecordedHand() { return DefaultDataDir() / "teleop" / "recorded_hand.csv"; }

inline std::shared_ptr<const geometry::BoundaryAtlas> CoarseAtlas() {
  static const robossis::testing::ScratchDir dir("robossis_teleop_test_atlas");  // outlives the atlas below
  static std::shared_ptr<const geometry::BoundaryAtlas> atlas = std::make_shared<const geometry::BoundaryAtlas>(
      geometry::BuildAtlas(Rsr(), Sigma7(), geometry::AtlasSpec::Coarse(Rsr()), dir.path() / "atlas"));
  return atlas;
}

inline std::unique_ptr<haptics::HapticRenderer> Renderer(const std::string& method, double rate_hz) {
  const bool mesh = method.rfind("mesh", 0) == 0;
  return haptics::MakeRenderer(method, Haptics(), Rsr(), haptics::HcToRsrMap{}, rate_hz,
                               mesh ? CoarseAtlas() : nullptr);
}

// Keeps every set-point (up to the reserved capacity: no allocation while the leader runs).
class RecordingLeaderLink final : public LeaderLink {
 public:
  explicit RecordingLeaderLink(std::size_t capacity) { sent.reserve(capacity); }
  void SendSetPoint(const SetPointMessage& m) noexcept override {
    last = m;
    ++count;
    if (sent.size() < sent.capacity()) sent.push_back(m);
  }
  // A follower's status, taken afresh at every tick while `follower_speaks` (none by default: a bench without one).
  bool TakeFollowerStatus(FollowerStatusMessage& status) noexcept override {
    if (!follower_speaks) return false;
    status = follower;
    return true;
  }
  bool SendCommand(const StateCommandMessage&) noexcept override { return true; }
  void SendEStop() noexcept override { ++estops; }
  int estops = 0;
  bool follower_speaks = false;
  FollowerStatusMessage follower;
  std::vector<SetPointMessage> sent;
  SetPointMessage last;
  std::size_t count = 0;
};

}  // namespace robossis::teleop::testing
