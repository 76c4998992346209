#include "src/apps/plotting.h"

#include <cstdlib>
#include <filesystem>
#include <optional>

#include "src/core/child_process.h"

namespace robossis::apps {

PlotResult RunPlotScript(const std::string& script, const std::vector<std::string>& args) {
  const char* env_python = std::getenv("ROBOSSIS_PYTHON");
  const std::string python = env_python != nullptr && *env_python != '\0' ? env_python : "/usr/bin/python3";
  const char* env_scripts = std::getenv("ROBOSSIS_PLOT_SCRIPTS_DIR");
  std::filesystem::path dir = env_scripts != nullptr && *env_scripts != '\0' ? env_scripts : ROBOSSIS_PLOT_SCRIPTS_DIR;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    // An installed program: PREFIX/bin/robossis beside PREFIX/share/robossis/plots.
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) dir = exe.parent_path().parent_path() / "share" / "robossis" / "plots";
  }
  const std::filesystem::path path = dir / script;
  if (!std::filesystem::exists(path)) return {false, "plot script " + path.string() + " not found"};
  std::vector<std::string> argv = {path.string()};
  argv.insert(argv.end(), args.begin(), args.end());
  std::optional<ChildProcess> plot;
  try {
    plot.emplace(python, argv);
  } catch (const std::runtime_error&) {
    return {false, "cannot start " + python + " (install python3-matplotlib: scripts/install-deps.sh)"};
  }
  if (const ChildExit exit = plot->Wait(); !exit.exited || exit.code != 0) {
    return {false, python + " " + script + " failed (is python3-matplotlib installed?)"};
  }
  return {true, ""};
}

}  // namespace robossis::apps
