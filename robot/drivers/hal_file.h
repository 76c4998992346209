#pragma once
// HAL files for the follower, generated from the actuation and HAL configs so that each number has one place: the
// steps per unit of each motor (eq. 17's resolution) become stepgen's position-scale, the step-rate caps its maxvel,
// and hal.yaml's acceleration time, step timing, threads and watchdogs the rest. data/hal/ holds the generated
// files; `robossis hal config` rewrites them and a test checks that they are current.

#include <array>
#include <string>

#include "robot/actuation/actuation_config.h"
#include "robot/drivers/hal_config.h"

namespace robossis::drivers {

enum class HalTarget {
  kSoftwareStepgen,  // stepgen(9) on a 50 us base thread (step_type=0, position control)
  kMesa7i76e,        // hostmot2's hardware stepgens on a Mesa 7i76E through hm2_eth(9)
};
const char* ToString(HalTarget target);                 // "stepgen", "7i76e"
HalTarget ParseHalTarget(const std::string& name);      // throws std::invalid_argument naming the choices
std::string ShippedHalFileName(HalTarget target);       // the file in data/hal/

// Per-joint caps the drives enforce (joint units: rad or m): the motor's step-rate cap over its steps per unit,
// and that speed reached in accel_time_s.
struct JointCaps {
  double max_velocity = 0;
  double max_acceleration = 0;
};
std::array<JointCaps, actuation::kNumMotors> CalcJointCaps(const HalConfig& hal,
                                                           const actuation::ActuationConfig& actuation);

std::string GenerateHalFile(const HalConfig& hal, const actuation::ActuationConfig& actuation, HalTarget target);

}  // namespace robossis::drivers
