#pragma once
// Figures are drawn by matplotlib scripts (scripts/plots/) from the CSV/JSON the C++ code writes, so a user can
// re-plot every figure. The interpreter is $ROBOSSIS_PYTHON, else Debian's /usr/bin/python3.

#include <string>
#include <vector>

namespace robossis::apps {

struct PlotResult {
  bool ok = false;
  std::string message;  // why it failed
};

// Runs `python3 scripts/plots/<script> args...` without a shell; returns its success.
PlotResult RunPlotScript(const std::string& script, const std::vector<std::string>& args);

}  // namespace robossis::apps
