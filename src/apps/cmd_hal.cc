// `robossis hal config`: the HAL files of the follower's LinuxCNC back end, generated from actuation.yaml and
// hal.yaml (robot/drivers/README.md).

#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "robot/drivers/hal_file.h"
#include "src/apps/app_context.h"
#include "src/core/files.h"

namespace robossis::apps {

void RegisterHalCommands(CLI::App& app, const AppContext& context) {
  CLI::App* hal = app.add_subcommand("hal", "LinuxCNC HAL files for step/direction drives (--follower hal)");
  hal->require_subcommand(1);
  struct Options {
    std::string target = "stepgen";
    std::string out;
  };
  auto options = std::make_shared<Options>();
  CLI::App* config = hal->add_subcommand(
      "config", "Write the HAL file for the software stepgen or a Mesa 7i76E.\n"
                "Example: robossis hal config --target stepgen --out data/hal/robossis-stepgen.hal");
  config->add_option("--target", options->target, "stepgen (software, base thread) or 7i76e (Mesa, hm2_eth)")
      ->check(CLI::IsMember({"stepgen", "7i76e"}));
  config->add_option("--out", options->out,
                     "HAL file to write (atomically; not a folder, not under --data-dir's config/); default: stdout");
  config->callback([options, &context] {
    const OutputPolicy output = context.Output();
    if (!options->out.empty()) output.CheckFile("--out", options->out);
    const std::string text = drivers::GenerateHalFile(
        drivers::HalConfig::FromYaml(context.ConfigPath("hal.yaml")),
        actuation::ActuationConfig::FromYaml(context.ConfigPath("actuation.yaml")),
        drivers::ParseHalTarget(options->target));
    if (options->out.empty()) {
      std::cout << text;
    } else {
      WriteOutputFile(output, options->out, text);
    }
  });
}

}  // namespace robossis::apps
