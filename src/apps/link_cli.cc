#include "src/apps/link_cli.h"

#include <ostream>
#include <stdexcept>

#include <CLI/CLI.hpp>

namespace robossis::apps {

void AddLinkOptions(CLI::App& command, link::LinkOptions& options) {
  command.add_option("--keys", options.keys_dir, "This unit's credentials: DIR/<unit> of `robossis keys init DIR` (DIR/leader, DIR/follower, DIR/panel); "
                     "`teleop --link dds` takes DIR itself");
  command.add_flag("--insecure", options.insecure,
                   "Run WITHOUT DDS Security (lab bench only: anyone on the network can read and command the robot)");
  command.add_option("--domain", options.domain_id, "DDS domain on the wire (both units must agree)")
      ->check(CLI::Range(0, 230))
      ->capture_default_str();
  command.add_option("--interface", options.network_interface, "Network interface: address or name (e.g. eth1)")
      ->capture_default_str();
  command.add_option("--peer", options.peers, "The other unit's address (unicast discovery; repeatable)")
      ->capture_default_str();
}

void CheckLinkOptions(const link::LinkOptions& options, std::ostream& err) {
  if (options.insecure) {
    err << "robossis: WARNING: --insecure: DDS Security is OFF. Set-points, commands and state travel in clear and\n"
           "robossis: WARNING: any program on this network can read them or command the robot. Lab bench only.\n";
    return;
  }
  if (options.keys_dir.empty()) {
    throw std::invalid_argument("--keys: expected this unit's credentials folder made by `robossis keys init DIR` "
                                "(DIR/leader, DIR/follower or DIR/panel; or --insecure on a lab bench)");
  }
}

}  // namespace robossis::apps
