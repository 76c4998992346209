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
  std::string csv = "t_s,cmd_x_mm,cmd_y_mm,cmd_z_mm,meas_x_mm,meas_y_mm,meas_z_mm,translation_error_mm,"
                    "rotation_error_deg\n";
  double max_e_p = 0, sum_e_p = 0, max_e_r = 0, sum_e_r = 0;
  long samples = 0;
  std::size_t k = 0;
  Eigen::Isometry3d X_cmd = setup.X_FM_start;
  while (follower.time_s() + follower.step_s() <= t_end + 1e-12) {
    const double t_next = follower.time_s() + follower.step_s();
    while (k + 1 < trace.t.size() && trace.t[k + 1] <= t_next + 1e-12) ++k;
    robot::RsrJointCommand command{trace.t[k], trace.q[k], trace.q_dot[k]};
    follower.Command(command);
    if (follower.Step() == sim::SimStepStatus::kUnstable) throw std::runtime_error("chain: the simulation became unstable");
    // The pose the commanded joints define (FK, warm-started at the previous one) against the pose Bullet measures.
    const robot::RsrFkResult fk = robot::CalcForwardKinematics(model, trace.q[k], X_cmd);
    if (!fk.converged()) throw std::runtime_error("chain: FK of the commanded joints did not converge");
    X_cmd = fk.X_FM;
    const robot::RsrFollowerState state = follower.State();
    const double e_p = MToMm((state.X_FM.translation() - X_cmd.translation()).norm());
    const double e_r = RadToDeg(RotationAngleBetween(state.X_FM.linear(), X_cmd.linear()));
    max_e_p = std::max(max_e_p, e_p), max_e_r = std::max(max_e_r, e_r);
    sum_e_p += e_p, sum_e_r += e_r, ++samples;
    if (samples % 10 == 0) {
      const Eigen::Vector3d c = X_cmd.translation() * kMToMm, m = state.X_FM.translation() * kMToMm;
      csv += Num(follower.time_s()) + "," + Num(c.x()) + "," + Num(c.y()) + "," + Num(c.z()) + "," + Num(m.x()) +
             "," + Num(m.y()) + "," + Num(m.z()) + "," + Num(e_p, "%.3e") + "," + Num(e_r, "%.3e") + "\n";
    }
  }
  demo.out.Write("chain/fig8_through_bullet.csv", csv);

  std::ostringstream& r = demo.report;
  r << "## 7. The whole follower chain\n\n"
    << "The Fig. 8 hand trajectory of section 4 (1 kHz with breakage) → incremental mapping with dynamic scaling → "
       "10 kHz up-sampling and Kalman filter → Jacobian and eq. 16 joint integration → joint commands into the Bullet "
       "model of section 5 through `robot::Follower` (the mechanism alone, with gravity), over "
    << Num(follower.time_s(), "%.1f") << " s at " << Num(1.0 / follower.step_s(), "%.0f")
    << " Hz. The pose Bullet measures against the pose the commanded joints define (FK):\n\n"
    << "| | mean | max |\n|---|---|---|\n"
    << "| translation error (mm) | " << Num(sum_e_p / std::max<long>(samples, 1), "%.2e") << " | "
    << Num(max_e_p, "%.2e") << " |\n"
    << "| rotation error (°) | " << Num(sum_e_r / std::max<long>(samples, 1), "%.2e") << " | " << Num(max_e_r, "%.2e")
    << " |\n\nData: `chain/fig8_through_bullet.csv` (every 10th step).\n\n";
}

}  // namespace robossis::apps
