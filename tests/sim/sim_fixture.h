#pragma once
// Shared, loaded once per test binary: the default RSR model, sim.yaml and the femur fragments (reading the STL
// and cutting it takes a fraction of a second; every simulation test reuses them).

#include "robot/rsr_model.h"
#include "robot/sim/bone_fragments.h"
#include "robot/sim/sim_config.h"
#include "src/core/config.h"

namespace robossis::sim::testing {

struct SimFixtureData {
  robot::RsrModel model = robot::RsrModel::Default();
  SimConfig config = LoadSimConfig(DefaultDataDir() / "config" / "sim.yaml", DefaultDataDir());
  BoneFragments fragments = BuildBoneFragments(config, model);
};

inline const SimFixtureData& Data() {
  static const SimFixtureData data;
  return data;
}

}  // namespace robossis::sim::testing
