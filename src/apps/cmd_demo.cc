// `robossis demo`: a complete simulated session and its report.

#include <malloc.h>

#include <chrono>
#include <iterator>
#include <cstdio>
#include <iostream>
#include <memory>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "src/apps/demo.h"
#include "src/apps/demo_teleop_section.h"
#include "src/apps/plotting.h"

namespace robossis::apps {

void DemoContext::Progress(const std::string& message) const { std::cerr << "[demo] " << message << std::endl; }

void DemoContext::Figure(const std::string& script, const std::vector<std::string>& args, const std::string& png,
                         const std::string& caption) {
  std::vector<std::string> full = args;
  full.push_back("--out");
  full.push_back(out.Path(png).string());
  const PlotResult result = RunPlotScript(script, full);
  if (result.ok) {
    report << "![" << caption << "](" << png << ")\n\n*" << caption << "*\n\n";
  } else {
    report << "> Figure `" << png << "` was not rendered: " << result.message
           << ". The data behind it is in this folder.\n\n";
    Progress("warning: " + result.message);
  }
}

void RegisterDemoCommand(CLI::App& app, const AppContext& context) {
  struct Options {
    std::string out = "demo-report";
    bool fast = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* demo = app.add_subcommand(
      "demo", "Run a complete simulated session and write a report that reproduces the paper's figures\n"
              "Example: robossis demo --out demo-report");
  demo->add_option("--out", options->out, "Report folder (written atomically: complete or untouched)")
      ->capture_default_str();
  demo->add_flag("--fast", options->fast, "Smaller grids and shorter runs (used by the test suite)");
  demo->callback([&context, options] {
    const auto start = std::chrono::steady_clock::now();
    StagedOutputDir out(options->out, context.Output());
    DemoContext demo{context, out, options->fast, {}, {}};
    demo.report << "# Robossis workbench: simulated session report\n\n"
                << "Produced by `robossis demo" << (options->fast ? " --fast" : "")
                << "` on the configuration in `" << context.data_dir.string() << "/config`. "
                << "Every number below is computed by this run; the data behind each table and figure is in this "
                   "folder.\n\n";
    struct Section {
      const char* name;
      void (*write)(DemoContext&);
    };
    const Section sections[] = {{"robots", &WriteRobotSection},     {"workspaces", &WriteWorkspaceSection},
                                {"rendering", &WriteRenderingSection}, {"transfer", &WriteTransferSection},
                                {"simulation", &WriteSimSection},      {"tracking", &WriteTrackingSection},
                                {"chain", &WriteChainSection},         {"teleop", &WriteTeleopSection},
                                {"link", &WriteLinkSection}};
    const auto seconds_since = [](std::chrono::steady_clock::time_point t) {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    const int count = static_cast<int>(std::size(sections));
    for (int i = 0; i < count; ++i) {
      const auto section_start = std::chrono::steady_clock::now();
      sections[i].write(demo);
      // What a section freed goes back to the system before the next one: without it glibc keeps the boundary
      // atlas of sections 2 and 3 (about 650 MB, freed) resident for the rest of the run.
      malloc_trim(0);
      // What a newcomer watching a run of several minutes wants to see: how far along it is.
      demo.Progress("section " + std::to_string(i + 1) + " of " + std::to_string(count) + " (" +
                    sections[i].name + ") took " + FormatFixed(seconds_since(section_start), 0) + " s; " +
                    FormatFixed(seconds_since(start), 0) + " s so far");
    }
    const double seconds = seconds_since(start);
    demo.report << "---\nRun time: " << seconds << " s.\n";
    out.Write("report.md", demo.report.str());
    out.Commit();
    demo.Progress("report written to " + (out.target() / "report.md").string());
    if (!demo.faults.empty()) {
      std::string all;
      for (const std::string& f : demo.faults) all += (all.empty() ? "" : "; ") + f;
      throw std::runtime_error("the report (" + (out.target() / "report.md").string() + ") shows " +
                               std::to_string(demo.faults.size()) + " fault(s): " + all);
    }
  });
}

std::string FormatFixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

}  // namespace robossis::apps
