// Demo report, section 7: the whole follower chain. The Fig. 8 hand trajectory goes through motion transfer and
// actuation (section 4) and the joint commands drive the Bullet simulation (section 5) through robot::Follower,
// exactly as they would drive the motor drivers.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "haptics/transfer/hc_trajectory.h"
#include "robot/sim/rsr_simulation.h"
#include "robot/sim/sim_config.h"
#include "src/apps/demo.h"
#include "src/apps/transfer_run.h"
#include "src/core/units.h"

namespace robossis::apps {

namespace {
std::string Num(double v, const char* format = "%.4f") { return FormatNumber(v, format); }
}  // namespace

void WriteChainSection(DemoContext& demo) {
  demo.Progress("chain: Fig. 8 hand -> transfer -> actuation -> Bullet follower");
  const robot::RsrModel model = demo.app.LoadRsr();
  const ChainSetup setup = DefaultChainSetup(demo.app, model);
  const TransferTrace trace = RunTransferChain(transfer::MakeScenario("fig8"), setup);

  // The mechanism alone (no fragments: at the home pose the distal fragment sits against the proximal one, and the
  // Fig. 8 motion would push it into the bone), with gravity.
  const sim::SimConfig config = sim::LoadSimConfig(demo.app.ConfigPath("sim.yaml"), demo.app.data_dir);
  sim::SimOptions options;
  options.with_bone = false;
  options.with_traction = false;
  sim::RsrSimulation follower(model, config, nullptr, nullptr, setup.X_FM_start, options);

  // The simulation steps at its own rate; each step gets the newest 10 kHz command issued by then.
  const double t_end = demo.fast ? std::min(2.0, trace.t.back()) : trace.t.back();
  const teleop::FollowerReplay replay =
      teleop::ReplayOnFollower(trace, model, follower, setup.X_FM_start, follower.step_s(), t_end);
  demo.out.Write("chain/fig8_through_bullet.csv", replay.csv);
  const double max_e_p = MToMm(replay.max_translation_error_m), max_e_r = RadToDeg(replay.max_rotation_error_rad);
  const double mean_e_p = MToMm(replay.mean_translation_error_m), mean_e_r = RadToDeg(replay.mean_rotation_error_rad);

  std::ostringstream& r = demo.report;
  r << "## 7. The whole follower chain\n\n"
    << "The Fig. 8 hand trajectory of section 4 (1 kHz with breakage) → incremental mapping with dynamic scaling → "
       "10 kHz up-sampling and Kalman filter → Jacobian and eq. 16 joint integration → joint commands into the Bullet "
       "model of section 5 through `robot::Follower` (the mechanism alone, with gravity), over "
    << Num(replay.duration_s, "%.1f") << " s at " << Num(1.0 / follower.step_s(), "%.0f")
    << " Hz. The pose Bullet measures against the pose the commanded joints define (FK):\n\n"
    << "| | mean | max |\n|---|---|---|\n"
    << "| translation error (mm) | " << Num(mean_e_p, "%.2e") << " | " << Num(max_e_p, "%.2e") << " |\n"
    << "| rotation error (°) | " << Num(mean_e_r, "%.2e") << " | " << Num(max_e_r, "%.2e")
    << " |\n\nData: `chain/fig8_through_bullet.csv` (every 10th step).\n\n";
}

}  // namespace robossis::apps
