// Time-domain passivity observer + controller, and the energy the methods put into the hand in closed loop.

#include <gtest/gtest.h>

#include "haptics/scenarios/compare.h"
#include "test_util.h"

namespace robossis::haptics {
namespace {

using testing::Config;
using testing::Home;
using testing::IdentityMap;
using testing::Rsr;

// A deliberately active "wall": negative damping, F = +b·v (it pushes the hand along its motion).
class ActiveWall final : public HapticRenderer {
 public:
  ActiveWall() : HapticRenderer(Rsr(), IdentityMap(), WrenchLimits{}, 1000) {}
  const char* name() const noexcept override { return "active"; }

 protected:
  HapticStatus Render(const RsrSideState& s, Eigen::Vector3d& f, Eigen::Vector3d& tau) noexcept override {
    f = 20.0 * s.v_F;
    tau = 0.05 * s.w_F;
    return HapticStatus::kContact;
  }
  void ResetMethod(const Eigen::Isometry3d&) noexcept override {}
};

double EnergyIntoHand(ActiveWall& wall) {
  HapticInput in;
  in.X_OH = Home();
  HapticOutput out;
  double energy = 0;
  for (int k = 0; k < 1000; ++k) {
    in.v_O = Eigen::Vector3d(0.05 * std::sin(0.01 * k), 0.02, 0);
    in.w_O = Eigen::Vector3d(0, 0.3 * std::cos(0.02 * k), 0);
    wall.Tick(in, out);
    energy += (out.f_O.dot(in.v_O) + out.tau_O.dot(in.w_O)) * wall.dt();
  }
  return energy;
}

TEST(Passivity, ControllerCancelsTheEnergyAnActiveWallInjects) {
  ActiveWall open_loop;
  EXPECT_GT(EnergyIntoHand(open_loop), 1e-3);  // the wall is indeed active
  ActiveWall controlled;
  PassivityParams pc;
  pc.enabled = true;
  controlled.SetPassivity(pc);
  EXPECT_LE(EnergyIntoHand(controlled), 1e-12);
  EXPECT_GE(controlled.observed_energy_force_j(), -1e-12);
  EXPECT_GE(controlled.observed_energy_torque_j(), -1e-12);
}

TEST(Passivity, PassiveMethodsGenerateNoNetEnergyOnTheScenarios) {
  const robot::Sigma7Model sigma7 = robot::Sigma7Model::Default();
  CompareSettings settings;
  settings.keep_trace = false;
  for (const char* name : {"push-edges", "explore"}) {
    const Scenario s = MakeScenario(name, Rsr(), Config().hand, Config().strike_hand_stiffness_n_per_m, true);
    for (const char* method : {"proxy", "proxy-pc"}) {
      const MethodRun run = RunMethod(s, method, Config(), Rsr(), sigma7, settings);
      EXPECT_LT(run.metrics.energy_generated_j, 1e-5) << name << " " << method;
    }
  }
}

}  // namespace
}  // namespace robossis::haptics
