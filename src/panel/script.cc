#include "src/panel/script.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "src/core/files.h"

namespace robossis::panel {
namespace {

[[noreturn]] void Fail(const std::string& source, int line, const std::string& what) {
  throw std::invalid_argument(source + ":" + std::to_string(line) + ": " + what);
}

}  // namespace

std::vector<ScriptAction> ParseScript(const std::string& text, const std::string& source) {
  std::vector<ScriptAction> actions;
  std::istringstream lines(text);
  std::string raw;
  int line_number = 0;
  double last_time_s = 0;
  while (std::getline(lines, raw)) {
    ++line_number;
    const std::size_t hash = raw.find('#');
    if (hash != std::string::npos) raw.resize(hash);
    std::istringstream words(raw);
    std::string time_text, verb;
    if (!(words >> time_text)) continue;  // blank or comment
    ScriptAction action;
    action.line = line_number;
    try {
      std::size_t used = 0;
      action.time_s = std::stod(time_text, &used);
      if (used != time_text.size()) throw std::invalid_argument("trailing characters");
    } catch (const std::exception&) {
      Fail(source, line_number, "time: expected seconds, got '" + time_text + "'");
    }
    if (!std::isfinite(action.time_s) || action.time_s < 0)
      Fail(source, line_number, "time: expected a non-negative number of seconds");
    if (action.time_s < last_time_s) Fail(source, line_number, "time: expected times in non-decreasing order");
    last_time_s = action.time_s;
    if (!(words >> verb)) Fail(source, line_number, "expected an action (click, set, screenshot, quit)");
    if (verb == "click") {
      action.verb = ScriptVerb::kClick;
      if (!(words >> action.target)) Fail(source, line_number, "click: expected a button name");
    } else if (verb == "set") {
      action.verb = ScriptVerb::kSet;
      if (!(words >> action.target >> action.value)) Fail(source, line_number, "set: expected a field and a value");
    } else if (verb == "screenshot") {
      action.verb = ScriptVerb::kScreenshot;
      if (!(words >> action.target)) Fail(source, line_number, "screenshot: expected a PNG path");
    } else if (verb == "quit") {
      action.verb = ScriptVerb::kQuit;
    } else {
      Fail(source, line_number, "action: '" + verb + "' is not one of click, set, screenshot, quit");
    }
    std::string extra;
    if (words >> extra) Fail(source, line_number, "unexpected '" + extra + "' after the action");
    actions.push_back(std::move(action));
  }
  return actions;
}

std::vector<ScriptAction> LoadScript(const std::filesystem::path& file) {
  std::string text;
  try {
    text = ReadBoundedFile(file, kMaxScriptFileBytes, "panel script");
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(std::string("--script: ") + e.what());
  }
  return ParseScript(text, file.string());
}

}  // namespace robossis::panel
