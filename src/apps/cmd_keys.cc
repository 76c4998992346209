// `robossis keys init DIR`: the credentials of the secured leader-follower link (src/link/keys.h).

#include <filesystem>
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>

#include "src/apps/app_context.h"
#include "src/link/keys.h"

namespace robossis::apps {

void RegisterKeysCommands(CLI::App& app, const AppContext& /*context*/) {
  CLI::App* keys = app.add_subcommand("keys", "Credentials of the secured DDS link (DDS Security): init");
  keys->require_subcommand(1);
  CLI::App* init = keys->add_subcommand(
      "init", "Make a CA, identities for leader, follower, panel and observer (ROS 2 tools, read-only), signed "
              "governance and permissions (openssl):\n"
              "one folder per role (DIR/leader, DIR/follower, DIR/panel, DIR/observer) and the CA apart (DIR/ca)\n"
              "Example: robossis keys init ~/robossis-keys    (copy only DIR/leader to the leader PC, DIR/follower to "
              "the robot PC; store DIR/ca offline)");
  auto dir = std::make_shared<std::string>();
  auto options = std::make_shared<link::KeysInitOptions>();
  init->add_option("DIR", *dir, "New or empty folder for the credentials")->required();
  init->add_option("--days", options->validity_days, "Validity of the certificates and permissions (days)")
      ->check(CLI::Range(1, link::kMaxValidityDays))
      ->capture_default_str();
  init->callback([dir, options] {
    link::InitKeys(*dir, *options);
    const std::filesystem::path d = *dir;
    std::cout << "credentials written to " << d.string() << " (private keys mode 0600), one folder per unit:\n"
              << "  " << (d / "leader").string() << "    copy to the leader PC only: --keys DIR/leader\n"
              << "  " << (d / "follower").string() << "  copy to the robot PC only: --keys DIR/follower\n"
              << "  " << (d / "panel").string() << "     copy to the panel's machine only: --keys DIR/panel\n"
              << "  " << (d / "observer").string()
              << "  for ROS 2 tools (rviz, ros2 bag): reads the status, commands nothing (src/link/README.md)\n"
              << "  " << (d / link::kCaFolder).string()
              << "        the CA's key: move it OFFLINE now (never on a unit; needed only to sign new credentials)\n"
              << "valid for " << options->validity_days << " days\n";
  });
}

}  // namespace robossis::apps
