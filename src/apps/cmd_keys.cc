// `robossis keys init DIR`: the credentials of the secured leader-follower link (src/link/keys.h).

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
      "init", "Make a CA, identities for leader, follower and panel, signed governance and permissions (openssl)\n"
              "Example: robossis keys init ~/robossis-keys    (then copy it to both machines; keep ca_key.pem safe)");
  auto dir = std::make_shared<std::string>();
  auto options = std::make_shared<link::KeysInitOptions>();
  init->add_option("DIR", *dir, "New or empty folder for the credentials")->required();
  init->add_option("--days", options->validity_days, "Validity of the certificates and permissions (days)")
      ->check(CLI::Range(1, link::kMaxValidityDays))
      ->capture_default_str();
  init->callback([dir, options] {
    link::InitKeys(*dir, *options);
    std::cout << "credentials for leader, follower and panel written to " << *dir
              << " (private keys mode 0600; ca_key.pem signs new permissions: keep it off the robot)\n";
  });
}

}  // namespace robossis::apps
