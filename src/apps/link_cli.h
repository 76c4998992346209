#pragma once
// The options every DDS link participant takes (`robossis leader`, `robossis follower`, the panel): credentials,
// --insecure, network interface, peers, domain. One place, so the participants agree.

#include <iosfwd>

#include "src/link/link_options.h"

// CLI11 is included only by the units that add options (it costs seconds per unit to compile).
namespace CLI {
class App;
}  // namespace CLI

namespace robossis::apps {

// Adds --keys DIR, --insecure, --domain N, --interface ADDR|NAME, --peer ADDR (repeatable) to `command`.
void AddLinkOptions(CLI::App& command, link::LinkOptions& options);

// Checks the options after parsing (credentials given unless --insecure; throws std::invalid_argument naming the
// option) and prints the loud warning of --insecure to `err`.
void CheckLinkOptions(const link::LinkOptions& options, std::ostream& err);

}  // namespace robossis::apps
