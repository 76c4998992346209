#pragma once
// What every subcommand shares: where the configuration lives, and the loaders for it.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robot/rsr_model.h"
#include "robot/sigma7_model.h"
#include "src/core/files.h"
#include "src/core/parse.h"
#include "src/core/pose.h"

// CLI11 is included only by the units that add options (it costs seconds per unit to compile).
namespace CLI {
class App;
}  // namespace CLI

namespace robossis::apps {

struct AppContext {
  std::filesystem::path data_dir;  // --data-dir, else $ROBOSSIS_DATA_DIR, else the source tree's data/
  bool force = false;              // --force: --out may replace a non-empty folder that is not an earlier output

  std::filesystem::path ConfigPath(const std::string& name) const { return data_dir / "config" / name; }
  robot::RsrModel LoadRsr() const { return robot::RsrModel::FromYaml(ConfigPath("rsr.yaml")); }
  robot::Sigma7Model LoadSigma7() const { return robot::Sigma7Model::FromYaml(ConfigPath("sigma7.yaml")); }

  // The one output policy of every command: --force, the command's own inputs (option and path; an empty path is
  // an input not given) and the folders of --data-dir the commands read (kDataDirInputs). Hand it to
  // StagedOutputDir or WriteOutputFile; call its CheckFolder/CheckFile before any work.
  OutputPolicy Output(std::vector<OutputPolicy::Input> inputs = {}) const;
};

// The folders of the data dir that commands read (configs, the femur mesh, the recorded hand, the DDS profile). An
// output may lie elsewhere in the data dir (`hal config --out data/hal/...`), never over one of these.
inline constexpr const char* kDataDirInputs[] = {"config", "femur", "teleop", "dds"};

// Each family of subcommands registers itself on the top-level app.
void RegisterRobotCommands(CLI::App& app, const AppContext& context);
void RegisterHcCommands(CLI::App& app, const AppContext& context);
void RegisterDemoCommand(CLI::App& app, const AppContext& context);
void RegisterRenderCompareCommand(CLI::App& app, const AppContext& context);
void RegisterWorkspaceCommands(CLI::App& app, const AppContext& context);
void RegisterSimCommands(CLI::App& app, const AppContext& context);
void RegisterMocapCommands(CLI::App& app, const AppContext& context);
void RegisterTrackEvalCommand(CLI::App& app, const AppContext& context);
void RegisterTransferCommands(CLI::App& app, const AppContext& context);
void RegisterHalCommands(CLI::App& app, const AppContext& context);
void RegisterKeysCommands(CLI::App& app, const AppContext& context);
void RegisterPanelCommand(CLI::App& app, const AppContext& context);

// "--pose X_MM,Y_MM,Z_MM,ROLL_DEG,PITCH_DEG,YAW_DEG" → pose in SI, a pose in the system's workspaces unless
// `bounds` says otherwise (a tracker's pose in its room). Throws std::invalid_argument naming the option.
Eigen::Isometry3d ParsePoseMmDeg(const std::string& text, const std::string& option_name,
                                 FieldBounds bounds = FieldBounds::kWorkspace);

// A numeric option checked before any work: finite and within [lo, hi] (0 is a value like any other, never "not
// given"). Throws std::invalid_argument "--rate-hz: expected a finite number in [1, 10000] Hz, got inf".
double OptionInRange(double value, double lo, double hi, const std::string& option_name, const std::string& unit);

// The input paths a `--device` value names ("replay:FILE.csv" → FILE.csv; "sim", "dhd..." → none).
std::filesystem::path DeviceInputPath(const std::string& device);
// The --help text of the speed-cap options (--max-speed-mm-s, --max-angular-speed-deg-s): the range the caps'
// one checker accepts (haptics/transfer/transfer_config.h) and the default.
std::string LinearSpeedCapHelp();
std::string AngularSpeedCapHelp();

// Prints a JSON document (pretty, one trailing newline) to stdout.
void PrintJson(const nlohmann::ordered_json& document);

}  // namespace robossis::apps
