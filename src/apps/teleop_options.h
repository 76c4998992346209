#pragma once
// The options that `robossis teleop`, `robossis leader` and `robossis follower` share, parsed into the runtime's
// request and setup in one place, so the three commands check them identically.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "src/apps/app_context.h"
#include "src/core/files.h"
#include "src/teleop/teleop_session.h"

namespace robossis::apps {

struct TeleopCliOptions {
  std::string device = "sim";
  std::optional<std::string> method;  // absent: haptics.yaml hardware_default_method (given empty: an error)
  std::string follower = "sim";
  double rate_hz = 1000;
  double duration_s = 10;
  std::string out;
  std::string atlas;
  std::optional<double> max_speed_mm_s;
  std::optional<double> max_angular_speed_deg_s;
  bool no_plots = false;
  bool json = false;
  // The follower's start commands (teleop::TeleopRequest::home_at_start, enable_at_start).
  bool home = false;
  bool enable = false;
  bool no_enable = false;
  // Bilateral feedback (leader): walls | bilateral, and its gain (leader.yaml `feedback` unless given).
  std::optional<std::string> feedback;
  std::optional<double> feedback_gain;
  std::optional<std::string> feedback_passivity;
  bool let_go_detector = false;
  // The Bullet follower's muscle traction (N along the femur axis, N·m about it).
  double sim_load_n = 0;
  double sim_load_nm = 0;
};

// The leader's and the follower's bilateral options as arguments for their own processes (`teleop --link dds`).
std::vector<std::string> FeedbackArgs(const TeleopCliOptions& options);
std::vector<std::string> SimLoadArgs(const TeleopCliOptions& options);

// Which unit's options a command takes.
enum class TeleopUnits { kBoth, kLeader, kFollower };

// Adds the options of `units` to `command` (--out is required).
void AddTeleopOptions(CLI::App& command, TeleopCliOptions& options, TeleopUnits units);

// The models, the configs (with the caps of the command line) and the request of one run. Not movable: the setup
// points at the models.
class TeleopInputs {
 public:
  TeleopInputs(const AppContext& context, const TeleopCliOptions& options, bool real_clock);
  TeleopInputs(const TeleopInputs&) = delete;
  TeleopInputs& operator=(const TeleopInputs&) = delete;

  // Builds the mesh methods' atlas (the coarse one under `scratch/atlas` unless --atlas names one).
  void LoadAtlasIfNeeded(const TeleopCliOptions& options, const std::filesystem::path& scratch);

  const robot::RsrModel rsr;
  const robot::Sigma7Model sigma7;
  teleop::TeleopSetup setup;
  teleop::TeleopRequest request;
};

// summary.json, loop_periods.csv and the units' CSVs (leader.csv, follower.csv; those a run streamed into the staging
// folder, request.csv_dir, are there already) into `out`, teleop.png when both units ran and `plots` is true, and
// commits. A run whose recording failed: what was recorded is committed, then std::runtime_error names the cause.
void CommitTeleopOutputs(StagedOutputDir& out, const teleop::TeleopOutputs& outputs, TeleopUnits units, bool plots);

}  // namespace robossis::apps
