// `robossis teleop` (a leader-follower session: device → leader unit → link → follower unit → back end),
// `robossis leader` and `robossis follower` (the same units as two processes over the DDS link, on one machine or
// two), and `robossis replay` (a session log back into CSV, summary and figures). Parse, call, print.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "src/apps/cmd_teleop.h"
#include "src/apps/link_cli.h"
#include "src/apps/teleop_options.h"
#include "src/core/child_process.h"
#include "src/core/files.h"
#include "src/core/parse.h"
#include "src/core/rt/clock.h"
#include "src/link/dds_follower_link.h"
#include "src/link/dds_leader_link.h"
#include "src/link/estop_sender.h"
#include "src/link/two_process_session.h"
#include "src/teleop/bilateral_harness.h"
#include "src/teleop/split_session.h"

namespace robossis::apps {

namespace {

// SIGINT and SIGTERM end a leader or follower run cleanly (forces off, drives disabled, the log complete).
std::atomic<bool> g_stop{false};
void OnStopSignal(int) { g_stop.store(true); }
void StopOnSignals() {
  std::signal(SIGINT, OnStopSignal);
  std::signal(SIGTERM, OnStopSignal);
}

void PrintOutcome(const char* what, const nlohmann::ordered_json& s, const std::string& out) {
  std::cout << what << ": " << s["leader_ticks"] << " leader and " << s["follower_ticks"] << " follower ticks, "
            << s["follower_limit_violations"] << " limit violations, max force " << s["max_force_n"] << " N → "
            << out << "\n";
}

// The options `robossis teleop --link dds` hands on to both processes (the caller checked them; each gets its own
// credentials folder of --keys: TwoProcessRequest::keys_dir).
std::vector<std::string> LinkArgs(const link::LinkOptions& l) {
  std::vector<std::string> a;
  if (l.insecure) a.push_back("--insecure");
  a.insert(a.end(), {"--domain", std::to_string(l.domain_id), "--interface", l.network_interface});
  for (const std::string& p : l.peers) a.insert(a.end(), {"--peer", p});
  return a;
}

std::vector<std::string> CapArgs(const TeleopCliOptions& o) {
  std::vector<std::string> a;
  if (o.max_speed_mm_s) a.insert(a.end(), {"--max-speed-mm-s", std::to_string(*o.max_speed_mm_s)});
  if (o.max_angular_speed_deg_s) {
    a.insert(a.end(), {"--max-angular-speed-deg-s", std::to_string(*o.max_angular_speed_deg_s)});
  }
  return a;
}

// The inputs of a teleop, leader or follower run: the atlas, a replayed hand, the link's credentials.
OutputPolicy TeleopOutputPolicy(const AppContext& context, const TeleopCliOptions& o, const link::LinkOptions& l) {
  return context.Output(
      {{"--atlas", o.atlas, true}, {"--device", DeviceInputPath(o.device)}, {"--keys", l.keys_dir, true}});
}

void RegisterTeleop(CLI::App& app, const AppContext& context) {
  struct Options : TeleopCliOptions {
    std::string clock = "simulated";
    std::string link = "inprocess";
    link::LinkOptions link_options;
    double link_delay_ms = 0;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "teleop", "Teleoperation: the haptic device through the walls into the follower, each unit on its own loop, "
                "every tick in a session log; in one process, or as two processes over DDS (--link dds)");
  AddTeleopOptions(*cmd, *o, TeleopUnits::kBoth);
  CLI::Option* clock_option = cmd->add_option("--clock", o->clock, "real (threads on wall-clock deadlines) | simulated (deterministic, fast)")
      ->check(CLI::IsMember({"real", "simulated"}))
      ->capture_default_str();
  cmd->add_option("--link", o->link,
                  "inprocess (one process) | dds (`robossis follower` and `robossis leader` as two processes over "
                  "Cyclone DDS, real clock)")
      ->check(CLI::IsMember({"inprocess", "dds"}))
      ->capture_default_str();
  AddLinkOptions(*cmd, o->link_options);
  cmd->add_option("--link-delay-ms", o->link_delay_ms,
                  "--link inprocess: one-way delay of both directions, ms (set-points and the follower's status)")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  cmd->callback([o, clock_option, &context] {
    if (o->link == "dds" && o->link_delay_ms > 0) {
      throw std::invalid_argument("--link-delay-ms: delays the in-process link only; over --link dds the fault "
                                  "relay (src/link/fault_relay.h) delays and drops packets");
    }
    if (o->link == "dds" && clock_option->count() > 0 && o->clock != "real") {
      throw std::invalid_argument("--clock " + o->clock + ": --link dds runs two processes on wall-clock time; "
                                  "use --clock real or leave --clock out");
    }
    StagedOutputDir out(o->out, TeleopOutputPolicy(context, *o, o->link_options));
    if (o->link == "dds") {
      CheckLinkOptions(o->link_options, std::cerr);
      TeleopInputs inputs(context, *o, true);  // checks the options before the processes start
      link::TwoProcessRequest r;
      r.program = SelfExecutable();
      r.global_args = {"--data-dir", context.data_dir.string()};
      r.link_args = LinkArgs(o->link_options);
      if (!o->link_options.insecure) r.keys_dir = o->link_options.keys_dir;
      r.leader_args = {"--device", o->device, "--method", inputs.request.method, "--rate-hz",
                       std::to_string(o->rate_hz)};
      if (!o->atlas.empty()) r.leader_args.insert(r.leader_args.end(), {"--atlas", o->atlas});
      const auto feedback = FeedbackArgs(*o);
      r.leader_args.insert(r.leader_args.end(), feedback.begin(), feedback.end());
      r.follower_args = {"--follower", o->follower};
      const auto load = SimLoadArgs(*o);
      r.follower_args.insert(r.follower_args.end(), load.begin(), load.end());
      // The follower process decides its start commands from the same flags.
      if (o->home) r.follower_args.push_back("--home");
      if (o->enable) r.follower_args.push_back("--enable");
      if (o->no_enable) r.follower_args.push_back("--no-enable");
      for (auto* args : {&r.leader_args, &r.follower_args}) {
        const auto caps = CapArgs(*o);
        args->insert(args->end(), caps.begin(), caps.end());
      }
      r.duration_s = o->duration_s;
      r.out_dir = out.staging();
      const link::TwoProcessResult result = link::RunTwoProcessSession(r);
      // The shown load against the follower's true load needs both processes' records: from both logs.
      nlohmann::ordered_json summary = {{"link", "dds"},
                                        {"secure", !o->link_options.insecure},
                                        {"feedback_force_error_n_rms",
                                         result.joined_summary.at("feedback_force_error_n_rms")},
                                        {"leader", result.leader_summary},
                                        {"follower", result.follower_summary}};
      out.Write("summary.json", summary.dump(2) + "\n");
      out.Commit();
      if (o->json) PrintJson(summary);
      else std::cout << "teleop --link dds: leader " << result.leader_summary["leader_ticks"] << " ticks, follower "
                     << result.follower_summary["follower_ticks"] << " ticks, "
                     << result.follower_summary["setpoints_accepted"] << " set-points accepted, "
                     << result.follower_summary["follower_limit_violations"] << " limit violations → " << o->out
                     << "\n";
      return;
    }
    TeleopInputs inputs(context, *o, o->clock == "real");
    inputs.request.link_delay_s = 1e-3 * o->link_delay_ms;
    inputs.LoadAtlasIfNeeded(*o, out.staging());
    inputs.request.csv_dir = out.staging();
    const teleop::TeleopOutputs outputs = teleop::RunTeleop(inputs.request, inputs.setup, out.Path("session.rlog"));
    for (const std::string& w : outputs.warnings) std::cerr << "robossis: warning: " << w << "\n";
    CommitTeleopOutputs(out, outputs, TeleopUnits::kBoth, !o->no_plots);
    if (o->json) PrintJson(outputs.summary);
    else PrintOutcome("teleop", outputs.summary, o->out);
  });
}

void RegisterLeader(CLI::App& app, const AppContext& context) {
  struct Options : TeleopCliOptions {
    link::LinkOptions link_options;
    std::optional<double> wait_for_follower_s;  // default: link.yaml's discovery.peer_wait_s
  };
  auto o = std::make_shared<Options>();
  o->link_options.role = link::Role::kLeader;
  CLI::App* cmd = app.add_subcommand(
      "leader", "The leader unit alone (PC 1 of Fig. 2): the haptic device, the walls and the motion transfer, "
                "sending set-points to `robossis follower` over DDS; real time");
  AddTeleopOptions(*cmd, *o, TeleopUnits::kLeader);
  AddLinkOptions(*cmd, o->link_options);
  cmd->add_option("--wait-for-follower-s", o->wait_for_follower_s,
                  "How long to wait for a follower authenticated and heard before the loop starts, else exit naming "
                  "the cause (default: link.yaml's discovery.peer_wait_s). The wait is part of --duration-s: the "
                  "loop runs for what is left of it")
      ->check(CLI::Range(0.0, 3600.0));
  cmd->callback([o, &context] {
    const OutputPolicy output = TeleopOutputPolicy(context, *o, o->link_options);
    output.CheckFolder("--out", o->out);
    CheckLinkOptions(o->link_options, std::cerr);
    TeleopInputs inputs(context, *o, true);
    StagedOutputDir out(o->out, output);
    inputs.LoadAtlasIfNeeded(*o, out.staging());
    o->link_options.tuning = link::LinkTuning::FromYaml(context.ConfigPath("link.yaml"));
    link::DdsLeaderLink link(o->link_options);
    const auto wait_start = std::chrono::steady_clock::now();
    // One bound on the wait, within --duration-s: --duration-s bounds the whole run, the wait included.
    const double wait_s = o->wait_for_follower_s.value_or(o->link_options.tuning.peer_wait_s);
    link.WaitForFollower(std::min(wait_s, o->duration_s));
    const double waited_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wait_start).count();
    std::cerr << "leader: follower authenticated and heard after " << waited_s << " s\n";
    if (!(o->duration_s - waited_s > 0)) {
      throw std::runtime_error("--duration-s " + FormatNumber(o->duration_s) + ": the follower was heard only after " +
                               FormatNumber(waited_s, "%.1f") + " s, nothing is left for the loop");
    }
    inputs.request.duration_s = o->duration_s - waited_s;
    StopOnSignals();
    inputs.request.csv_dir = out.staging();
    teleop::TeleopOutputs outputs =
        teleop::RunLeader(inputs.request, inputs.setup, link, out.Path("session.rlog"), &g_stop);
    outputs.summary["link"] = link::ToJson(link.Statistics());
    // Together --duration-s: the wait for the follower, then the loop.
    outputs.summary["follower_wait_s"] = waited_s;
    outputs.summary["loop_duration_s"] = inputs.request.duration_s;
    for (const std::string& w : outputs.warnings) std::cerr << "robossis: warning: " << w << "\n";
    CommitTeleopOutputs(out, outputs, TeleopUnits::kLeader, false);
    if (o->json) PrintJson(outputs.summary);
    else PrintOutcome("leader", outputs.summary, o->out);
  });
}

void RegisterFollower(CLI::App& app, const AppContext& context) {
  struct Options : TeleopCliOptions {
    link::LinkOptions link_options;
  };
  auto o = std::make_shared<Options>();
  o->duration_s = 3600;
  o->link_options.role = link::Role::kFollower;
  CLI::App* cmd = app.add_subcommand(
      "follower", "The follower unit alone (PC 2 of Fig. 2): validates the leader's set-points from DDS and runs the "
                  "10 kHz actuation into its back end until stopped (Ctrl-C) or --duration-s; real time");
  AddTeleopOptions(*cmd, *o, TeleopUnits::kFollower);
  AddLinkOptions(*cmd, o->link_options);
  cmd->callback([o, &context] {
    const OutputPolicy output = TeleopOutputPolicy(context, *o, o->link_options);
    output.CheckFolder("--out", o->out);
    CheckLinkOptions(o->link_options, std::cerr);
    TeleopInputs inputs(context, *o, true);
    StagedOutputDir out(o->out, output);
    rt::MonotonicClock clock;
    o->link_options.tuning = link::LinkTuning::FromYaml(context.ConfigPath("link.yaml"));
    link::DdsFollowerLink link(o->link_options, clock);
    StopOnSignals();
    inputs.request.csv_dir = out.staging();
    // Announced for whoever starts a leader after it (the two-process session): the loops run, the state is sent.
    teleop::TeleopOutputs outputs =
        teleop::RunFollower(inputs.request, inputs.setup, link, clock, out.Path("session.rlog"), &g_stop,
                            [] { std::cerr << link::kFollowerRunningLine << std::endl; });
    outputs.summary["link"] = link::ToJson(link.Statistics());
    for (const std::string& w : outputs.warnings) std::cerr << "robossis: warning: " << w << "\n";
    CommitTeleopOutputs(out, outputs, TeleopUnits::kFollower, false);
    if (o->json) PrintJson(outputs.summary);
    else PrintOutcome("follower", outputs.summary, o->out);
  });
}

void RegisterEStop(CLI::App& app) {
  struct EStopOptions {
    link::LinkOptions link_options;
    double timeout_s = 5;
  };
  auto o = std::make_shared<EStopOptions>();
  o->link_options.role = link::Role::kPanel;
  CLI::App* cmd = app.add_subcommand(
      "estop", "E-stop the follower over DDS (as the panel participant) and wait until it reports ESTOP; it leaves "
               "the E-stop only by a reset. Exit status 1 if no follower confirmed within --timeout-s");
  AddLinkOptions(*cmd, o->link_options);
  cmd->add_option("--timeout-s", o->timeout_s, "How long to wait for the follower's confirmation (s)")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 600.0));
  cmd->callback([o] {
    CheckLinkOptions(o->link_options, std::cerr);
    const link::EStopSendResult r = link::SendEStopAndConfirm(o->link_options, o->timeout_s);
    if (r.confirmed) {
      std::cout << "estop: the follower reports ESTOP (reset to leave)\n";
      return;
    }
    throw std::runtime_error(r.follower_heard ? std::string("estop: the follower still reports ") +
                                                    teleop::ToString(r.last_state) + " after --timeout-s"
                                              : "estop: no follower heard within --timeout-s (the E-stop was "
                                                "offered to any follower while this waited)");
  });
}

void RegisterReplay(CLI::App& app, const AppContext& context) {
  struct ReplayOptions {
    std::string log;
    std::string follower_log;
    std::string out;
    bool no_plots = false;
    bool json = false;
  };
  auto r = std::make_shared<ReplayOptions>();
  CLI::App* replay = app.add_subcommand("replay", "A session log (robossis teleop) back into CSV, summary and figures");
  // No CLI11 file check: the log's reader refuses a missing or non-regular file in the project's words.
  replay->add_option("LOG", r->log, "Session log (DIR/session.rlog)")->required();
  replay->add_option("--follower-log", r->follower_log,
                     "With LOG a leader's log (`robossis leader`): the follower's log of the same run (`robossis "
                     "follower`), joined with it on the follower's clock into one summary");
  replay->add_option("--out", r->out, "Output folder (written atomically)")->required();
  replay->add_flag("--no-plots", r->no_plots, "Skip the figure");
  replay->add_flag("--json", r->json, "Print summary.json to stdout");
  replay->callback([r, &context] {
    const OutputPolicy output = context.Output({{"LOG", r->log}, {"--follower-log", r->follower_log}});
    output.CheckFolder("--out", r->out);
    const teleop::TeleopOutputs outputs = r->follower_log.empty()
                                              ? teleop::ReplaySessionLog(r->log)
                                              : teleop::ReplaySplitSession(r->log, r->follower_log);
    for (const std::string& w : outputs.warnings) std::cerr << "robossis: warning: " << w << "\n";
    StagedOutputDir out(r->out, output);
    const std::string units = outputs.summary["units"];
    CommitTeleopOutputs(out, outputs,
                        units == "leader" ? TeleopUnits::kLeader
                                          : units == "follower" ? TeleopUnits::kFollower : TeleopUnits::kBoth,
                        !r->no_plots);
    if (r->json) PrintJson(outputs.summary);
    else std::cout << "replay: " << r->log << " → " << r->out << "\n";
  });
}

void RegisterBilateralMatrix(CLI::App& app) {
  struct Options {
    double duration_s = 60;
    std::vector<double> delays_ms{0, 10, 25, 50, 100, 200};
    double loss = 0.05;
    double release_s = 0;
    double reserve_j = teleop::FeedbackPassivityConfig{}.reserve_j;
    double rest_damping_n_s_per_m = teleop::FeedbackPassivityConfig{}.rest_damping_n_s_per_m;
    bool let_go_detector = false;
    double let_go_confirm_s = teleop::LetGoConfig{}.confirm_s;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "bilateral-matrix",
      "The feedback port's passivity on a simulated clock: every scenario (free, wall, spring, load517, release, "
      "let_go) x one-way delay x scheme (off, classic, network), one axis, 5 % loss and jitter "
      "(src/teleop/bilateral_harness.h). Example: robossis bilateral-matrix --duration-s 60 --json");
  cmd->add_option("--duration-s", o->duration_s, "Simulated time per run")->check(CLI::Range(10.0, 600.0))
      ->capture_default_str();
  cmd->add_option("--delays-ms", o->delays_ms, "One-way delays")->check(CLI::Range(0.0, 1000.0))->delimiter(',');
  cmd->add_option("--loss", o->loss, "Packet loss per direction (0-0.5)")->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  cmd->add_option("--release-s", o->release_s,
                  "The passivity controller's action released over this time (0: tick by tick; leader.yaml "
                  "feedback.release_s)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--reserve-j", o->reserve_j,
                  "The energy reserve over which the load fades as the budget empties (0: cut tick by tick; "
                  "src/teleop/feedback_passivity.h reserve_j)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--rest-damping-n-s-per-m", o->rest_damping_n_s_per_m,
                  "With --reserve-j: the load's faded share shown as a damper up to this much")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  cmd->add_flag("--let-go-detector", o->let_go_detector,
               "The leader drops the load and damps the device once it believes the operator let go "
               "(src/teleop/let_go_detector.h)");
  cmd->add_option("--let-go-confirm-s", o->let_go_confirm_s,
                  "With --let-go-detector: how long the device must move as its own mass before the let-go is believed")
      ->check(CLI::Range(0.001, 1.0))
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the rows as JSON");
  cmd->callback([o] {
    teleop::HarnessParams base;
    base.let_go.confirm_s = o->let_go_confirm_s;
    base.passivity.release_s = o->release_s;
    base.passivity.reserve_j = o->reserve_j;
    base.passivity.rest_damping_n_s_per_m = o->rest_damping_n_s_per_m;
    base.detect_let_go = o->let_go_detector;
    base.duration_s = o->duration_s;
    base.loss = o->loss;
    std::vector<double> delays_s;
    for (double d : o->delays_ms) delays_s.push_back(1e-3 * d);
    const auto results = teleop::RunHarnessMatrix(
        base, delays_s,
        {teleop::FeedbackPassivityScheme::kOff, teleop::FeedbackPassivityScheme::kClassic,
         teleop::FeedbackPassivityScheme::kNetwork});
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (const auto& r : results) rows.push_back(teleop::ToJson(r));
    if (o->json) {
      PrintJson(rows);
      return;
    }
    std::printf("%-8s %6s %-8s %10s %10s %9s %8s %8s %7s %7s %6s %6s %9s %6s %8s\n", "scenario", "delay", "scheme",
                "E_fb_J", "E_fb_max", "obs_min", "dissip", "f_rms_N", "x_rms", "drift", "hf", "rest_s", "E_F_exc",
                "active", "let_go_s");
    for (const auto& r : results) {
      std::printf("%-8s %6.0f %-8s %10.4f %10.4f %9.4f %8.3f %8.3f %7.2f %7.3f %6.3f %6.2f %9.4f %6.3f %8.3f\n",
                  teleop::ToString(r.params.scenario), 1e3 * r.params.one_way_delay_s,
                  teleop::ToString(r.params.scheme), r.feedback_energy_j, r.max_feedback_energy_j, r.min_observer_j,
                  r.dissipated_share, r.force_error_n_rms, r.position_error_mm_rms, r.drift_mm, r.force_hf_share,
                  r.rest_after_event_s, r.max_follower_excess_j, r.active_fraction, r.let_go_detected_s);
    }
  });
}

}  // namespace

void RegisterTeleopCommands(CLI::App& app, const AppContext& context) {
  RegisterTeleop(app, context);
  RegisterLeader(app, context);
  RegisterFollower(app, context);
  RegisterEStop(app);
  RegisterReplay(app, context);
  RegisterBilateralMatrix(app);
}

}  // namespace robossis::apps
