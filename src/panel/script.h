#pragma once
// Scripted panel sessions (`robossis panel --script FILE`): a timed list of UI actions, so that every part of the
// panel can be exercised without a person.
//
// File format, one action per line, `#` starts a comment, times in seconds since the panel opened, non-decreasing:
//   0.5  set jog.axis z           # a field and its value (see PanelController::Set for the fields)
//   0.5  set jog.amount_mm 5
//   0.6  click jog.go             # a button (see PanelController::Click)
//   0.6  wait jog.done 60         # hold the script until the condition holds (at most 60 s, else an error)
//   3.0  screenshot out/jog.png   # the framebuffer as PNG
//   3.5  quit
//
// `wait` makes a script independent of the machine's speed: `wait state NAME [TIMEOUT_S]` (the follower's state, as
// the panel shows it: disabled, homing, ready, enabled, clutched, fault, estop) and `wait jog.done [TIMEOUT_S]` (the
// last jog played to its end and the robot there, still: PanelController::ScriptConditionHolds). The script's clock
// stops while it waits: the times of the actions after a wait count from the moment it was satisfied.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace robossis::panel {

enum class ScriptVerb { kClick, kSet, kScreenshot, kQuit, kWait };

// Long enough for a loaded machine or a sanitized build; a wait that does not end is an error, never a hang.
inline constexpr double kDefaultWaitTimeoutS = 60;

struct ScriptAction {
  double time_s = 0;
  ScriptVerb verb = ScriptVerb::kQuit;
  std::string target;  // button, field, screenshot path or wait condition ("state", "jog.done")
  std::string value;   // for kSet; for a wait on "state", the state's name
  double timeout_s = kDefaultWaitTimeoutS;  // for kWait
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
  // The next action due at `now_s` (seconds since the panel opened), or nullptr; call until nullptr each frame. A
  // wait is returned, and the actions after it held back, until Satisfied() is called for it: the caller checks its
  // condition once per frame and stops asking for actions in that frame while it does not hold.
  const ScriptAction* NextDue(double now_s) noexcept {
    if (next_ >= actions_.size() || actions_[next_].time_s + waited_s_ > now_s) return nullptr;
    const ScriptAction* action = &actions_[next_];
    if (action->verb != ScriptVerb::kWait) ++next_;
    return action;
  }
  // Seconds the wait NextDue returned has been due at `now_s`.
  double WaitingS(double now_s) const noexcept {
    return next_ < actions_.size() ? now_s - (actions_[next_].time_s + waited_s_) : 0;
  }
  // The wait NextDue returned holds at `now_s`: the script goes on, its later times shifted by the time waited.
  void Satisfied(double now_s) noexcept {
    waited_s_ += std::max(0.0, WaitingS(now_s));
    ++next_;
  }
  bool finished() const { return next_ >= actions_.size(); }

 private:
  std::vector<ScriptAction> actions_;
  std::size_t next_ = 0;
  double waited_s_ = 0;  // total time the script's clock stood still in waits
};

}  // namespace robossis::panel
