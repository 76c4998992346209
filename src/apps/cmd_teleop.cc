// `robossis teleop` (a leader-follower session: device → leader unit → link → follower unit → back end) and
// `robossis replay` (a session log back into CSV, summary and figures). Parse, call src/teleop, print.

#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "geometry/boundary_atlas.h"
#include "src/apps/cmd_teleop.h"
#include "src/apps/plotting.h"
#include "src/core/files.h"
#include "src/core/units.h"
#include "src/teleop/teleop_session.h"

namespace robossis::apps {

namespace {

void WriteOutputs(const StagedOutputDir& out, const teleop::TeleopOutputs& o, bool plots) {
  out.Write("summary.json", o.summary.dump(2) + "\n");
  out.Write("leader.csv", o.leader_csv);
  out.Write("follower.csv", o.follower_csv);
  out.Write("loop_periods.csv", o.periods_csv);
  if (!plots) return;
  const PlotResult r = RunPlotScript("teleop_session.py", {"--dir", out.staging().string(), "--out",
                                                           out.Path("teleop.png").string()});
  if (!r.ok) std::cerr << "robossis: warning: teleop.png not rendered: " << r.message << "\n";
}

}  // namespace

void RegisterTeleopCommands(CLI::App& app, const AppContext& context) {
  struct Options {
    std::string device = "sim";
    std::string method;  // default: haptics.yaml hardware_default_method
    std::string follower = "sim";
    double rate_hz = 1000;
    double duration_s = 10;
    std::string clock = "simulated";
    std::string out;
    std::string atlas;
    std::optional<double> max_speed_mm_s;
    std::optional<double> max_angular_speed_deg_s;
    bool no_plots = false;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "teleop", "Teleoperation on one machine: the haptic device through the walls into the follower, each unit on "
                "its own loop, every tick in a session log");
  cmd->add_option("--device", o->device,
                  "sim | replay:FILE.csv (t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg) | dhd[:lib=PATH,serial=N,index=N,"
                  "hold=1,window_ms=MS] (a sigma.7 through the Force Dimension SDK)");
  cmd->add_option("--method", o->method, "Rendering method (render-compare's list; default: haptics.yaml hardware_default_method)");
  cmd->add_option("--follower", o->follower,
                  "sim (Bullet) | recorder (pulse recorder) | hal (step/direction drives through LinuxCNC HAL, hal.yaml)");
  cmd->add_option("--rate-hz", o->rate_hz, "Leader loop rate: 1000 or 4000 (a multiple of the 1 kHz transfer)");
  cmd->add_option("--duration-s", o->duration_s, "Run time (a replay ends 0.5 s after its last sample)");
  cmd->add_option("--clock", o->clock, "real (threads on wall-clock deadlines) | simulated (deterministic, fast)")
      ->check(CLI::IsMember({"real", "simulated"}));
  cmd->add_option("--out", o->out, "Output folder (written atomically: complete or untouched)")->required();
  cmd->add_option("--atlas", o->atlas, "Boundary atlas folder for mesh/mesh-live (default: build the coarse one)");
  cmd->add_option("--max-speed-mm-s", o->max_speed_mm_s, "Linear speed cap (default: transfer.yaml, 10 mm/s)");
  cmd->add_option("--max-angular-speed-deg-s", o->max_angular_speed_deg_s,
                  "Angular speed cap (default: transfer.yaml, 1 deg/s)");
  cmd->add_flag("--no-plots", o->no_plots, "Skip the figure");
  cmd->add_flag("--json", o->json, "Print summary.json to stdout");
  cmd->callback([o, &context] {
    const robot::RsrModel rsr = context.LoadRsr();
    const robot::Sigma7Model sigma7 = context.LoadSigma7();
    teleop::TeleopSetup setup = teleop::TeleopSetup::Load(context.data_dir, rsr, sigma7);
    if (o->max_speed_mm_s) {
      if (!(*o->max_speed_mm_s > 0 && std::isfinite(*o->max_speed_mm_s))) {
        throw std::invalid_argument("--max-speed-mm-s: expected a positive finite speed, got " +
                                    std::to_string(*o->max_speed_mm_s));
      }
      setup.transfer.caps.max_linear_speed_m_s = MmToM(*o->max_speed_mm_s);
    }
    if (o->max_angular_speed_deg_s) {
      if (!(*o->max_angular_speed_deg_s > 0 && std::isfinite(*o->max_angular_speed_deg_s))) {
        throw std::invalid_argument("--max-angular-speed-deg-s: expected a positive finite speed, got " +
                                    std::to_string(*o->max_angular_speed_deg_s));
      }
      setup.transfer.caps.max_angular_speed_rad_s = DegToRad(*o->max_angular_speed_deg_s);
    }
    setup.transfer.Validate();
    setup.follower.setpoint.caps = setup.transfer.caps;  // the follower checks the caps the leader applies
    teleop::TeleopRequest request;
    request.device = o->device;
    request.method = o->method.empty() ? setup.haptics.hardware_default_method : o->method;
    request.follower = o->follower;
    request.rate_hz = o->rate_hz;
    request.duration_s = o->duration_s;
    request.real_clock = o->clock == "real";
    StagedOutputDir out(o->out);
    if (request.method.rfind("mesh", 0) == 0) {
      request.atlas = std::make_shared<const geometry::BoundaryAtlas>(
          o->atlas.empty() ? geometry::BuildAtlas(rsr, sigma7, geometry::AtlasSpec::Coarse(rsr), out.Path("atlas"))
                           : geometry::BoundaryAtlas::Load(o->atlas));
    }
    const teleop::TeleopOutputs outputs = teleop::RunTeleop(request, setup, out.Path("session.rlog"));
    for (const std::string& w : outputs.warnings) std::cerr << "robossis: warning: " << w << "\n";
    WriteOutputs(out, outputs, !o->no_plots);
    out.Commit();
    if (o->json) {
      PrintJson(outputs.summary);
    } else {
      std::cout << "teleop: " << outputs.summary["leader_ticks"] << " leader and " << outputs.summary["follower_ticks"]
                << " follower ticks, " << outputs.summary["follower_limit_violations"]
                << " limit violations, max force " << outputs.summary["max_force_n"] << " N → " << o->out << "\n";
    }
  });

  struct ReplayOptions {
    std::string log;
    std::string out;
    bool no_plots = false;
    bool json = false;
  };
  auto r = std::make_shared<ReplayOptions>();
  CLI::App* replay = app.add_subcommand("replay", "A session log (robossis teleop) back into CSV, summary and figures");
  replay->add_option("LOG", r->log, "Session log (DIR/session.rlog)")->required()->check(CLI::ExistingFile);
  replay->add_option("--out", r->out, "Output folder (written atomically)")->required();
  replay->add_flag("--no-plots", r->no_plots, "Skip the figure");
  replay->add_flag("--json", r->json, "Print summary.json to stdout");
  replay->callback([r] {
    const teleop::TeleopOutputs outputs = teleop::ReplaySessionLog(r->log);
    for (const std::string& w : outputs.warnings) std::cerr << "robossis: warning: " << w << "\n";
    StagedOutputDir out(r->out);
    WriteOutputs(out, outputs, !r->no_plots);
    out.Commit();
    if (r->json) PrintJson(outputs.summary);
    else std::cout << "replay: " << r->log << " → " << r->out << "\n";
  });
}

}  // namespace robossis::apps
