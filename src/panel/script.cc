#include "src/panel/script.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "src/core/files.h"
#include "src/teleop/link_messages.h"

namespace robossis::panel {
namespace {

[[noreturn]] void Fail(const std::string& source, int line, const std::string& what) {
  throw std::invalid_argument(source + ":" + std::to_string(line) + ": " + what);
}

// The follower's states by the names the panel shows (teleop::ToString).
bool IsStateName(const std::string& name) {
  for (int s = 0; s <= static_cast<int>(teleop::OperatingState::kEStop); ++s)
    if (name == teleop::ToString(static_cast<teleop::OperatingState>(s))) return true;
  return false;
}

std::string StateNames() {
  std::string names;
  for (int s = 0; s <= static_cast<int>(teleop::OperatingState::kEStop); ++s)
    names += (s > 0 ? ", " : "") + std::string(teleop::ToString(static_cast<teleop::OperatingState>(s)));
  return names;
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
    if (!(words >> verb)) Fail(source, line_number, "expected an action (click, set, screenshot, quit, wait)");
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
    } else if (verb == "wait") {
      action.verb = ScriptVerb::kWait;
      if (!(words >> action.target)) Fail(source, line_number, "wait: expected a condition (state NAME, jog.done)");
      if (action.target == "state") {
        if (!(words >> action.value)) Fail(source, line_number, "wait state: expected a state's name");
        if (!IsStateName(action.value))
          Fail(source, line_number, "wait state: '" + action.value + "' is not one of " + StateNames());
      } else if (action.target != "jog.done") {
        Fail(source, line_number, "wait: '" + action.target + "' is not one of state, jog.done");
      }
      std::string timeout_text;
      if (words >> timeout_text) {
        std::size_t used = 0;
        try {
          action.timeout_s = std::stod(timeout_text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != timeout_text.size() || !std::isfinite(action.timeout_s) || action.timeout_s <= 0)
          Fail(source, line_number, "wait: timeout: expected a positive number of seconds, got '" + timeout_text + "'");
      }
    } else {
      Fail(source, line_number, "action: '" + verb + "' is not one of click, set, screenshot, quit, wait");
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
