#pragma once
// Shared helpers for the haptics tests.

#include <Eigen/Geometry>

#include "haptics/haptics_config.h"
#include "haptics/rendering/haptic_types.h"
#include "robot/rsr_kinematics.h"
#include "src/core/config.h"

namespace robossis::haptics::testing {

inline const robot::RsrModel& Rsr() {
  static const robot::RsrModel model = robot::RsrModel::Default();
  return model;
}

inline const HapticsConfig& Config() {
  static const HapticsConfig config = HapticsConfig::FromYaml(DefaultDataDir() / "config" / "haptics.yaml");
  return config;
}

// Identity mapping: the HC pose IS the RSR pose (tests talk in RSR space).
inline HcToRsrMap IdentityMap() { return HcToRsrMap{}; }

inline Eigen::Isometry3d Home() { return Rsr().geometry().X_FM_home; }

inline Eigen::Isometry3d Translated(const Eigen::Isometry3d& X, const Eigen::Vector3d& d) {
  Eigen::Isometry3d Y = X;
  Y.translation() += d;
  return Y;
}

// Holds a pose still for `ticks` ticks (fills the moving-average window) and returns the last output.
inline HapticOutput Hold(HapticRenderer& r, const Eigen::Isometry3d& X, int ticks = 8,
                         const Eigen::Vector3d& v = Eigen::Vector3d::Zero()) {
  HapticInput in;
  in.X_OH = X;
  in.v_O = v;
  HapticOutput out;
  for (int k = 0; k < ticks; ++k) r.Tick(in, out);
  return out;
}

}  // namespace robossis::haptics::testing
