#include "src/apps/plotting.h"

#include <spawn.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>

extern char** environ;

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
  std::vector<std::string> argv_strings = {python, path.string()};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& s : argv_strings) argv.push_back(s.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
    return {false, "cannot start " + python + " (install python3-matplotlib: scripts/install-deps.sh)"};
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    return {false, python + " " + script + " failed (is python3-matplotlib installed?)"};
  }
  return {true, ""};
}

}  // namespace robossis::apps
