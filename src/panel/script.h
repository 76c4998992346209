#pragma once
// Scripted panel sessions (`robossis panel --script FILE`): a timed list of UI actions, so that every part of the
// panel can be exercised without a person.
//
// File format, one action per line, `#` starts a comment, times in seconds since the panel opened, non-decreasing:
//   0.5  set jog.axis z           # a field and its value (see PanelController::Set for the fields)
//   0.5  set jog.amount_mm 5
//   0.6  click jog.go             # a button (see PanelController::Click)
//   3.0  screenshot out/jog.png   # the framebuffer as PNG
//   3.5  quit

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace robossis::panel {

enum class ScriptVerb { kClick, kSet, kScreenshot, kQuit };

struct ScriptAction {
  double time_s = 0;
  ScriptVerb verb = ScriptVerb::kQuit;
  std::string target;  // button, field or screenshot path
  std::string value;   // for kSet
  int line = 0;        // 1-based line in the file, for messages
};

// Parses a script's text; `source` names it in errors. Throws std::invalid_argument naming the source, the line and
// what was expected.
std::vector<ScriptAction> ParseScript(const std::string& text, const std::string& source);
// A script is a few hundred lines; the bound keeps a wrong file (a video, /dev/zero) from being read at all.
inline constexpr std::uintmax_t kMaxScriptFileBytes = std::uintmax_t{1} << 20;  // 1 MiB
// Reads `file` through ReadBoundedFile (a regular file within kMaxScriptFileBytes), then ParseScript. Throws
// std::invalid_argument starting "--script: " when it cannot be read.
std::vector<ScriptAction> LoadScript(const std::filesystem::path& file);

class ScriptPlayer {
 public:
  explicit ScriptPlayer(std::vector<ScriptAction> actions) : actions_(std::move(actions)) {}
  // The next action due at `now_s`, or nullptr; call until nullptr each frame.
  const ScriptAction* NextDue(double now_s) noexcept {
    if (next_ >= actions_.size() || actions_[next_].time_s > now_s) return nullptr;
    return &actions_[next_++];
  }
  bool finished() const { return next_ >= actions_.size(); }

 private:
  std::vector<ScriptAction> actions_;
  std::size_t next_ = 0;
};

}  // namespace robossis::panel
