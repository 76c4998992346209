#pragma once
// `robossis demo`: one simulated session whose report reproduces the paper's figures. Each capability adds a
// section: a function that computes, writes its data (CSV/JSON) and figures into the report folder, and appends
// Markdown to the report.

#include <sstream>
#include <string>
#include <vector>

#include "src/apps/app_context.h"
#include "src/core/files.h"
#include "src/core/parse.h"

namespace robossis::apps {

struct DemoContext {
  const AppContext& app;
  const StagedOutputDir& out;
  bool fast = false;       // --fast: smaller grids and shorter runs, for the test suite
  std::ostringstream report;  // Markdown of the report body
  // What a section found wrong (one line each, naming the section): the report is written, then the demo exits 1.
  std::vector<std::string> faults;

  void Progress(const std::string& message) const;
  // Renders a figure with scripts/plots/<script> (matplotlib). On success appends the image link; otherwise
  // appends a note saying which figure is missing and why (the data files stay in the report).
  void Figure(const std::string& script, const std::vector<std::string>& args, const std::string& png,
              const std::string& caption);
};

// The sections, in report order.
// Numbers in the report: fixed decimals (FormatFixed), or a printf format for one double (FormatNumber of
// src/core/parse.h, "%.3g").
std::string FormatFixed(double v, int decimals);

void WriteRobotSection(DemoContext& demo);      // ## 1. The robots (robot/)
void WriteWorkspaceSection(DemoContext& demo);  // ## 2. Workspaces (geometry/)
void WriteRenderingSection(DemoContext& demo);  // ## 3. Haptic rendering (haptics/)
void WriteTransferSection(DemoContext& demo);   // ## 4. Motion transfer and actuation (haptics/transfer, robot/actuation)
void WriteSimSection(DemoContext& demo);        // ## 5. Simulation (robot/sim)
void WriteTrackingSection(DemoContext& demo);   // ## 6. Tracking accuracy (calibration/)
void WriteLinkSection(DemoContext& demo);       // ## 9. The link: two processes over secured DDS (src/link)
void WriteChainSection(DemoContext& demo);      // ## 7. The whole follower chain: transfer -> actuation -> Bullet

}  // namespace robossis::apps
