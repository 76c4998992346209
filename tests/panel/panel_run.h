#pragma once
// Runs the `robossis panel` binary (ROBOSSIS_BINARY) under Xvfb over a script, as a person would drive it:
// `xvfb-run -a` starts a private X server and always stops it when the panel exits; `timeout` bounds a hung run.
// Under AddressSanitizer the window's process runs without leak detection (its other checks stay on): a library
// that GLFW and Mesa load for the window and unload at exit leaves 128 bytes that LeakSanitizer can name no module
// or function of, so no suppression can match them. The panel's session logic (panel_test) and its line images
// (panel_draw_test) are leak-checked in their own processes.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/robossis_cli.h"

namespace robossis::testing {

struct PanelRun {
  int exit_code = -1;
  std::string output;
  nlohmann::json json;
};

inline std::filesystem::path TestDir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("robossis_panel_test_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Writes the script and runs the panel over it with --json. stderr is kept apart so stdout parses.
inline PanelRun RunPanel(const std::filesystem::path& dir, const std::string& script, const std::string& extra = "") {
  const std::filesystem::path script_file = dir / "script.txt";
  std::ofstream(script_file) << script;
  // The X authority file in the test's folder (-f): without it xvfb-run makes a temporary folder of its own and,
  // now and then when the program exits at once, fails to remove it and exits 5 whatever the program returned.
  const std::string command = "ASAN_OPTIONS=detect_leaks=0 timeout 300 xvfb-run -a -f " + (dir / "Xauthority").string() +
                              " -s '-screen 0 1920x1080x24' " +
                              std::string(ROBOSSIS_BINARY) +
                              " panel --script " + script_file.string() + " --json " + extra + " 2>" +
                              (dir / "stderr.txt").string();
  const CommandRun shell = RunShell(command);
  PanelRun run;
  run.exit_code = shell.exit_code;
  run.output = shell.output;
  if (run.exit_code == 0) run.json = nlohmann::json::parse(run.output, nullptr, false);
  if (run.exit_code != 0) {
    std::ifstream err(dir / "stderr.txt");
    run.output += std::string(std::istreambuf_iterator<char>(err), {});
  }
  return run;
}

}  // namespace robossis::testing
