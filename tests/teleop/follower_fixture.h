#pragma once
// The follower unit tests' shared set-up: the RSR model, its home pose, and the shipped actuation and transfer
// configs (data/config).

#include "robot/actuation/actuation_config.h"
#include "robot/rsr_model.h"
#include "src/core/config.h"
#include "src/teleop/follower_config.h"

namespace robossis::teleop {

struct ShippedFollowerSetup {
  const robot::RsrModel model_ = robot::RsrModel::Default();
  const Eigen::Isometry3d home_ = model_.geometry().X_FM_home;
  const actuation::ActuationConfig actuation_ =
      actuation::ActuationConfig::FromYaml(DefaultDataDir() / "config" / "actuation.yaml");
  const transfer::TransferConfig transfer_ =
      transfer::TransferConfig::FromYaml(DefaultDataDir() / "config" / "transfer.yaml");
  // follower.yaml with the transfer's speed caps (as TeleopSetup::Load makes it).
  FollowerConfig ShippedFollowerConfig() const {
    return FollowerConfig::FromYaml(DefaultDataDir() / "config" / "follower.yaml", transfer_.caps);
  }
};

}  // namespace robossis::teleop
