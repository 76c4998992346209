#pragma once
// `robossis demo`: one simulated session whose report reproduces the paper's figures. Each capability adds a
// section: a function that computes, writes its data (CSV/JSON) and figures into the report folder, and appends
// Markdown to the report.

#include <sstream>
#include <string>
#include <vector>

#include "src/apps/app_context.h"
#include "src/core/files.h"

namespace robossis::apps {

struct DemoContext {
  const AppContext& app;
  const StagedOutputDir& out;
  bool fast = false;       // --fast: smaller grids and shorter runs, for the test suite
  std::ostringstream report;  // Markdown of the report body

  void Progress(const std::string& message) const;
  // Renders a figure with scripts/plots/<script> (matplotlib). On success appends the image link; otherwise
  // appends a note saying which figure is missing and why (the data files stay in the report).
  void Figure(const std::string& script, const std::vector<std::string>& args, const std::string& png,
              const std::string& caption);
};

// The sections, in report order.
void WriteRobotSection(DemoContext& demo);
void WriteWorkspaceSection(DemoContext& demo);
void WriteSimSection(DemoContext& demo);
void WriteTrackingSection(DemoContext& demo);  // ## 6. Tracking accuracy (calibration/)
void WriteRenderingSection(DemoContext& demo);
void WriteTransferSection(DemoContext& demo);

}  // namespace robossis::apps
