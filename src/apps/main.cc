// robossis: the workbench's command line. Thin: parse, build, run, catch.

#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <string>

#include <CLI/CLI.hpp>

#include "src/apps/app_context.h"
#include "src/apps/cmd_teleop.h"
#include "src/core/config.h"
#include "robossis_version.h"  // generated: ROBOSSIS_VERSION, ROBOSSIS_GIT_REVISION

namespace {

// "unknown command 'bogus' for 'robossis robot'; expected one of: info, ik, ...", where CLI11 would only say "A
// subcommand is required": the deepest command the parse reached, and the word it did not know. Empty if the
// parse left no such word.
std::string UnknownCommandMessage(CLI::App& app) {
  CLI::App* reached = &app;
  std::string path = app.get_name();
  while (!reached->get_subcommands().empty()) {
    reached = reached->get_subcommands().front();
    path += " " + reached->get_name();
  }
  std::string word;
  for (CLI::App* a = reached; a != nullptr && word.empty(); a = a->get_parent()) {
    for (const std::string& r : a->remaining()) {
      if (!r.empty() && r.front() != '-') {
        word = r;
        break;
      }
    }
  }
  if (word.empty()) return "";
  std::string known;
  for (const CLI::App* sub : reached->get_subcommands({})) known += (known.empty() ? "" : ", ") + sub->get_name();
  return "unknown command '" + word + "' for '" + path + "'; expected one of: " + known;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace robossis;
  CLI::App app{"Robossis haptic workbench: sigma.7 leader, 3-arm parallel surgical robot (RSR) follower.\n"
               "Units at the command line: mm, degrees, Hz; inside: SI.",
               "robossis"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Show the help of every subcommand");
  apps::AppContext context;
  context.data_dir = DefaultDataDir();
  app.add_option("--data-dir", context.data_dir, "Folder with config/ and reference data (default: built-in data/)")
      ->check(CLI::ExistingDirectory);
  app.add_flag("--force", context.force,
               "Let --out replace a non-empty folder that is not an earlier robossis output (it is replaced whole)");
  app.set_version_flag("--version", std::string("robossis ") + ROBOSSIS_VERSION + " (git " + ROBOSSIS_GIT_REVISION + ")");
  app.fallthrough();  // --data-dir and --force may also follow the subcommand
  apps::RegisterRobotCommands(app, context);
  apps::RegisterHcCommands(app, context);
  apps::RegisterDemoCommand(app, context);
  apps::RegisterRenderCompareCommand(app, context);
  apps::RegisterWorkspaceCommands(app, context);
  apps::RegisterSimCommands(app, context);
  apps::RegisterMocapCommands(app, context);
  apps::RegisterTrackEvalCommand(app, context);
  apps::RegisterTransferCommands(app, context);
  apps::RegisterHalCommands(app, context);
  apps::RegisterKeysCommands(app, context);
  apps::RegisterPanelCommand(app, context);
  apps::RegisterTeleopCommands(app, context);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help, --help-all and --version end the parse with "success": CLI11 prints them.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    // A bad option is an input error like any other: one line naming the option and what was expected
    // ("--days: Value 0 not in range 1 to 36500"), exit 1, not CLI11's own exit codes (105, 106, 109...).
    std::string message = e.what();
    if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr) {
      if (const std::string unknown = UnknownCommandMessage(app); !unknown.empty()) message = unknown;
    }
    for (char& c : message) {
      if (c == '\n') c = ' ';
    }
    std::cerr << "robossis: error: " << message << "\n";
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    // Not the library's raw "filesystem error: ..." text: the path and the reason.
    std::cerr << "robossis: error: " << e.path1().string() << ": " << e.code().message() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "robossis: error: out of memory (an input larger than this machine can hold?)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "robossis: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
