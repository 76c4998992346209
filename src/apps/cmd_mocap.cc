// `robossis mocap inspect|simulate` and `robossis track-eval`: OptiTrack Motive recordings and tracking accuracy
// (paper §VII-A, Fig. 14).

#include <iostream>
#include <memory>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "calibration/mocap_track.h"
#include "calibration/synthetic_tracker.h"
#include "calibration/tracking_eval.h"
#include "calibration/tracking_report.h"
#include "src/apps/app_context.h"
#include "src/apps/plotting.h"
#include "src/apps/tracking_outputs.h"
#include "src/core/files.h"
#include "src/core/parse.h"
#include "src/core/units.h"

namespace robossis::apps {

namespace {

using json = nlohmann::ordered_json;

void PrintInspectText(const json& doc) {
  std::cout << "format " << doc["format_version"].get<std::string>() << ", "
            << doc["export_rate_hz"].get<double>() << " Hz, " << doc["frames"].get<long long>() << " frames ("
            << doc["duration_s"].get<double>() << " s), " << doc["length_units"].get<std::string>() << ", rotation "
            << doc["rotation_type"].get<std::string>() << "\n";
  for (const auto& rb : doc["rigid_bodies"]) {
    std::cout << "rigid body '" << rb["name"].get<std::string>() << "': present in "
              << rb["frames_present"].get<long long>() << " frames, " << rb["gaps"].get<long long>()
              << " gaps (longest " << rb["longest_gap_frames"].get<long long>() << " frames), "
              << rb["rigid_body_markers"].get<int>() << " rigid-body markers\n";
  }
  std::cout << "markers: " << doc["markers"].get<int>() << ", frame-number jumps: " << doc["frame_jumps"].get<long long>()
            << "\n";
  if (!doc["complete"].get<bool>()) {
    std::cout << "excerpt: " << doc["frames"].get<long long>() << " frames read of the header's "
              << doc["frames_in_header"].get<long long>() << " ('Total Exported Frames'); read as it is\n";
  }
}

}  // namespace

void RegisterMocapCommands(CLI::App& app, const AppContext& context) {
  CLI::App* mocap = app.add_subcommand("mocap", "OptiTrack Motive recordings: inspect, simulate");
  mocap->require_subcommand(1);

  CLI::App* inspect = mocap->add_subcommand(
      "inspect", "Summarize a Motive CSV export (format 1.2x): rate, frames, rigid bodies, gaps, markers\n"
                 "Example: robossis mocap inspect take.csv --json");
  auto inspect_file = std::make_shared<std::string>();
  auto inspect_json = std::make_shared<bool>(false);
  inspect->add_option("FILE", *inspect_file, "Motive CSV export")->required();
  inspect->add_flag("--json", *inspect_json, "Machine-readable output");
  inspect->callback([inspect_file, inspect_json] {
    const json doc = calibration::TakeSummaryJson(calibration::InspectMotiveTake(*inspect_file));
    if (*inspect_json) {
      PrintJson(doc);
    } else {
      PrintInspectText(doc);
    }
  });

  struct SimulateOptions {
    std::string reference, out, rigid_body = "MovingRing", units = "m", rotation = "Quaternion";
    double rate_hz = 120, offset_s = 0, drift_ppm = 0;
    int gaps = 0;
    unsigned seed = 42;
    std::string tracker_pose = "400,-300,1500,180,0,30", marker_offset = "0,0,25,0,0,0";
  };
  auto sim = std::make_shared<SimulateOptions>();
  CLI::App* simulate = mocap->add_subcommand(
      "simulate", "Write a genuine Motive CSV export of a simulated OptiTrack session following a trajectory\n"
                  "Example: robossis mocap simulate --reference commanded.csv --out take.csv --offset-s 2.5 --gaps 3");
  simulate->add_option("--reference", sim->reference, "Trajectory the ring follows (project CSV or TUM)")->required();
  simulate->add_option("--out", sim->out,
                       "Motive CSV to write (atomically; not a folder, not --reference)")->required();
  simulate->add_option("--rigid-body", sim->rigid_body,
                       "Rigid body name: 1 to 64 bytes, no comma, double quote, control character or edge space")
      ->capture_default_str();
  simulate->add_option("--rate-hz", sim->rate_hz, "Frame rate")->capture_default_str();
  simulate->add_option("--offset-s", sim->offset_s, "Clock offset: t_reference = t_mocap + offset")->capture_default_str();
  simulate->add_option("--drift-ppm", sim->drift_ppm, "Clock drift")->capture_default_str();
  simulate->add_option("--gaps", sim->gaps,
                       "Number of occlusion gaps (0.02-0.3 s each, separate; the error says how many fit)")
      ->capture_default_str();
  simulate->add_option("--units", sim->units, "Length units in the file: m or mm")->capture_default_str();
  simulate->add_option("--rotation-type", sim->rotation, "Quaternion, XYZ, XZY, YXZ, YZX, ZXY or ZYX")
      ->capture_default_str();
  simulate->add_option("--tracker-pose", sim->tracker_pose,
                       "Robot base in the tracker frame X_MM,Y_MM,Z_MM,ROLL_DEG,PITCH_DEG,YAW_DEG")
      ->capture_default_str();
  simulate->add_option("--marker-offset", sim->marker_offset, "Marker body in the ring frame (same format)")
      ->capture_default_str();
  simulate->add_option("--seed", sim->seed, "Random seed")->capture_default_str();
  simulate->callback([&context, sim] {
    const OutputPolicy output = context.Output({{"--reference", sim->reference}});
    output.CheckFile("--out", sim->out);
    calibration::SyntheticTrackerOptions o;
    OptionInRange(sim->rate_hz, 1, 10000, "--rate-hz", "Hz");
    // Bounds, checked before any work (a simulated take is at most kMaxSimulatedFrames rows, ~1 GB).
    constexpr int kMaxGaps = 10000;
    constexpr double kMaxSimulatedFrames = 1e7;
    if (sim->gaps < 0 || sim->gaps > kMaxGaps) {
      throw std::invalid_argument("--gaps: expected 0 to " + std::to_string(kMaxGaps) + ", got " + std::to_string(sim->gaps));
    }
    OptionInRange(sim->offset_s, -1e6, 1e6, "--offset-s", "s");
    OptionInRange(sim->drift_ppm, -1e5, 1e5, "--drift-ppm", "ppm");
    if (const std::string problem = calibration::MotiveAssetNameProblem(sim->rigid_body); !problem.empty()) {
      throw std::invalid_argument("--rigid-body '" + sim->rigid_body + "': the name " + problem);
    }
    if (sim->units != "m" && sim->units != "mm") throw std::invalid_argument("--units: expected m or mm, got '" + sim->units + "'");
    o.rate_hz = sim->rate_hz;
    o.clock_offset_s = sim->offset_s;
    o.clock_drift = sim->drift_ppm * 1e-6;
    o.occlusion_gaps = sim->gaps;
    o.millimetres = sim->units == "mm";
    o.seed = sim->seed;
    o.rigid_body_name = sim->rigid_body;
    bool known = false;
    for (auto t : {calibration::MotiveRotationType::kQuaternion, calibration::MotiveRotationType::kXYZ,
                   calibration::MotiveRotationType::kXZY, calibration::MotiveRotationType::kYXZ,
                   calibration::MotiveRotationType::kYZX, calibration::MotiveRotationType::kZXY,
                   calibration::MotiveRotationType::kZYX}) {
      if (calibration::RotationTypeName(t) == sim->rotation) {
        o.rotation_type = t;
        known = true;
      }
    }
    if (!known) throw std::invalid_argument("--rotation-type: expected Quaternion, XYZ, XZY, YXZ, YZX, ZXY or ZYX");
    o.X_TF = ParsePoseMmDeg(sim->tracker_pose, "--tracker-pose", FieldBounds::kFinite);
    o.X_MB = ParsePoseMmDeg(sim->marker_offset, "--marker-offset");
    const calibration::PoseTrajectory reference = calibration::ReadReferenceTrajectory(sim->reference);
    if (reference.duration_s() * sim->rate_hz > kMaxSimulatedFrames) {
      throw std::invalid_argument("--reference: " + sim->reference + " spans " + std::to_string(reference.duration_s()) +
                                  " s, " + std::to_string(reference.duration_s() * sim->rate_hz) + " frames at --rate-hz; "
                                  "expected at most " + std::to_string(static_cast<long>(kMaxSimulatedFrames)) + " frames");
    }
    if (const int max_gaps = calibration::MaxOcclusionGaps(reference, o); sim->gaps > max_gaps) {
      std::ostringstream why;
      why << "--gaps " << sim->gaps << ": at most " << max_gaps << " separate gaps of up to " << o.gap_max_s
          << " s fit in the " << calibration::SyntheticFrameCount(reference, o) << " frames of this take of "
          << sim->reference << " (each gap takes its own slot of the middle 90 %)";
      throw std::invalid_argument(why.str());
    }
    std::ostringstream csv;
    const calibration::SyntheticRecording rec = calibration::WriteSyntheticMotiveCsv(reference, o, csv);
    WriteOutputFile(output, sim->out, csv.str());
    std::cerr << "wrote " << sim->out << ": " << rec.frames << " frames, " << rec.gaps << " gaps ("
              << rec.frames_occluded << " frames occluded)\n";
  });
}

void RegisterTrackEvalCommand(CLI::App& app, const AppContext& context) {
  struct Options {
    std::string mocap, rigid_body, reference, out;
    bool json = false, no_drift = false, no_plot = false;
    double offset_s = 0, offset_window_s = 2.0;
    double flip_threshold_deg = 10;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "track-eval",
      "Tracking accuracy (paper Fig. 14): register and time-align a Motive rigid body to a command log, then\n"
      "report translational (mm) and rotational (deg) errors, data quality and the Fig. 14 figure\n"
      "Example: robossis track-eval --mocap take.csv --rigid-body MovingRing --reference commanded.csv --out eval");
  cmd->add_option("--mocap", o->mocap, "Motive CSV export (format 1.2x)")->required();
  cmd->add_option("--rigid-body", o->rigid_body, "Rigid body (or marker-set) name in the export")->required();
  cmd->add_option("--reference", o->reference,
                  "Commanded trajectory: project CSV (t_s, x_m|x_mm.., qw..|roll_deg..) or TUM")
      ->required();
  cmd->add_option("--out", o->out, "Output folder (written atomically: complete or untouched)")->required();
  cmd->add_flag("--json", o->json, "Print summary.json to stdout");
  auto offset_opt = cmd->add_option("--offset-s", o->offset_s,
                                    "Approximate clock offset (t_reference = t_mocap + offset): search only within "
                                    "±--offset-window-s of it (for motions that repeat themselves)");
  auto window_opt = cmd->add_option("--offset-window-s", o->offset_window_s,
                                    "Half-width of the search around --offset-s (only with --offset-s)")
                        ->capture_default_str();
  cmd->add_flag("--no-drift", o->no_drift, "Estimate the clock offset only, not the drift");
  cmd->add_option("--flip-threshold-deg", o->flip_threshold_deg,
                  "Frames whose orientation error exceeds this are excluded as orientation flips")
      ->capture_default_str();
  cmd->add_flag("--no-plot", o->no_plot, "Skip the Fig. 14 PNG");
  cmd->callback([&context, o, offset_opt, window_opt] {
    // Every option is checked whether or not it is used, before any input is read.
    const OutputPolicy output = context.Output({{"--mocap", o->mocap}, {"--reference", o->reference}});
    output.CheckFolder("--out", o->out);
    OptionInRange(o->flip_threshold_deg, 1e-3, 180, "--flip-threshold-deg", "deg");
    OptionInRange(o->offset_s, -1e6, 1e6, "--offset-s", "s");
    OptionInRange(o->offset_window_s, 1e-3, 1e6, "--offset-window-s", "s");
    if (window_opt->count() > 0 && offset_opt->count() == 0) {
      throw std::invalid_argument("--offset-window-s: only meaningful with --offset-s (without it the whole range of "
                                  "offsets is searched)");
    }
    // Read and evaluate everything before creating the output folder, so bad input leaves nothing behind.
    const calibration::RigidBodyTrack track = calibration::ReadRigidBodyTrack(o->mocap, o->rigid_body);
    const calibration::PoseTrajectory reference = calibration::ReadReferenceTrajectory(o->reference);
    calibration::TrackingEvalOptions options;
    options.clock_fit.allow_drift = !o->no_drift;
    options.flip_threshold_rad = DegToRad(o->flip_threshold_deg);
    if (offset_opt->count() > 0) {
      options.offset_given = true;
      options.offset_s = o->offset_s;
      options.offset_window_s = o->offset_window_s;
    }
    const calibration::TrackingEvalResult result = calibration::EvaluateTracking(track, reference, options);
    if (!track.complete) {
      std::cerr << "robossis: " << o->mocap << " is an excerpt: " << track.size() << " frames read of the header's "
                << track.frames_in_header << "\n";
    }
    if (!result.clock_fit.warning.empty()) std::cerr << "robossis: warning: " << result.clock_fit.warning << "\n";
    StagedOutputDir out(o->out, output);
    const json inputs{{"mocap", o->mocap}, {"rigid_body", o->rigid_body}, {"reference", o->reference}};
    WriteTrackingOutputs(result, inputs, out, "");
    if (!o->no_plot) {
      std::vector<std::string> args = TrackingFigureArgs(out, "", "Tracking accuracy: " + o->rigid_body);
      args.push_back("--out");
      args.push_back(out.Path("fig14_tracking.png").string());
      const PlotResult plot = RunPlotScript("tracking_fig14.py", args);
      if (!plot.ok) std::cerr << "robossis: warning: figure not drawn: " << plot.message << "\n";
    }
    out.Commit();
    if (o->json) {
      json summary = calibration::TrackingSummaryJson(result);
      summary["inputs"] = inputs;
      PrintJson(summary);
    } else {
      const json s = calibration::TrackingSummaryJson(result);
      std::cout << "translation error (mm): mean " << s["translation_error_mm"]["mean"].get<double>() << ", max "
                << s["translation_error_mm"]["max"].get<double>() << "; rotation error (deg): mean "
                << s["rotation_error_deg"]["mean"].get<double>() << ", max "
                << s["rotation_error_deg"]["max"].get<double>() << "\n"
                << calibration::ClockReportText(result.clock_fit) << "registration RMS "
                << s["registration_rms_mm"].get<double>() << " mm, frames used "
                << s["frames_used"].get<long long>() << ", excluded " << s["frames_excluded"].get<long long>()
                << "\nwritten to " << o->out << "\n";
    }
  });
}

}  // namespace robossis::apps
