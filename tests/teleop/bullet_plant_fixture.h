#pragma once
// The follower tests' Bullet robot: the simulation on its own plant loop, without bone or muscles, at `start`, and
// the operator's enable that lets a follower unit drive it.

#include <memory>

#include "robot/sim/rsr_simulation.h"
#include "robot/sim/sim_config.h"
#include "robot/sim/simulated_plant.h"
#include "src/core/config.h"
#include "src/teleop/in_process_link.h"

namespace robossis::teleop {

inline sim::SimulatedPlant UnloadedBulletPlant(const robot::RsrModel& model, const Eigen::Isometry3d& start) {
  sim::SimOptions options;
  options.with_bone = false;
  options.with_traction = false;
  const sim::SimConfig config = sim::LoadSimConfig(DefaultDataDir() / "config" / "sim.yaml", DefaultDataDir());
  return sim::SimulatedPlant(std::make_unique<sim::RsrSimulation>(model, config, nullptr, nullptr, start, options));
}

inline void SendEnable(InProcessLink& link) {
  StateCommandMessage enable;
  enable.command = StateCommand::kEnable;
  enable.sequence = 1;
  link.operator_commands().Send(enable);
}

}  // namespace robossis::teleop
