#include "src/panel/panel_controller.h"

#include <cmath>
#include <stdexcept>

#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::panel {
namespace {

double ParseValue(const std::string& field, const std::string& value) {
  try {
    std::size_t used = 0;
    const double number = std::stod(value, &used);
    if (used == value.size() && std::isfinite(number)) return number;
  } catch (const std::exception&) {
  }
  throw std::invalid_argument(field + ": expected a number, got '" + value + "'");
}

}  // namespace

PanelController::PanelController(PanelBackend& backend, const robot::RsrModel& model, const PanelConfig& config,
                                 HapticModeModel haptic)
    : backend_(backend),
      model_(model),
      haptic_(std::move(haptic)),
      plot_window_s_(config.plot_window_s),
      pose_plot_(static_cast<std::size_t>(config.plot_capacity_samples)),
      wrench_plot_(static_cast<std::size_t>(config.plot_capacity_samples)) {}

void PanelController::Update(double now_s) {
  teleop::FollowerStatusMessage status;
  if (backend_.ReadStatus(status)) {
    view_ = BuildViewModel(model_, status);
    if (!view_.fault_text.empty()) last_fault_ = view_.fault_text;
    if (message_.empty()) message_ = view_.refusal_text;  // the follower's own refusal, while its status carries it
    // Moved: by more than 1 um or 1 urad, far below a motor step (5 um, 0.3 mrad), above a simulation's noise.
    bool moved = false;
    for (std::size_t i = 0; i < status.joints.size(); ++i)
      moved |= std::abs(status.joints[i] - still_joints_[i]) > 1e-6;
    if (moved) {
      still_joints_ = status.joints;
      still_since_ns_ = status.stamp_ns;
    }
    status_stamp_ns_ = status.stamp_ns;
  }
  backend_.ReadHealth(health_);
  backend_.ReadHandWrench(wrench_);
  if (!backend_.ReadCommandedPose(X_FM_commanded_)) X_FM_commanded_ = view_.X_FM;
  if (!view_.has_status) return;
  const Vector6d commanded = MmDegFromPose(X_FM_commanded_);
  PlotBuffer<12>::Values pose{};
  for (int i = 0; i < 6; ++i) {
    pose[i] = static_cast<float>(commanded[i]);
    pose[6 + i] = static_cast<float>(view_.pose_mm_deg[i]);
  }
  pose_plot_.Push(now_s, pose);
  pose_plot_.TrimOlderThan(plot_window_s_);
  PlotBuffer<6>::Values wrench{};
  for (int i = 0; i < 3; ++i) {
    wrench[i] = static_cast<float>(wrench_.force_n[i]);
    wrench[3 + i] = static_cast<float>(wrench_.torque_nm[i]);
  }
  wrench_plot_.Push(now_s, wrench);
  wrench_plot_.TrimOlderThan(plot_window_s_);
}

JogRequest PanelController::CurrentJogRequest() const {
  JogRequest request;
  request.axis = jog_form_.axis;
  const double scale = IsRotational(jog_form_.axis) ? kDegToRad : kMmToM;
  request.amount = jog_form_.amount * scale;
  request.timing = jog_form_.timing;
  request.duration_s = jog_form_.duration_s;
  request.peak_speed = jog_form_.speed * scale;
  return request;
}

void PanelController::PreviewJog() {
  last_verdict_ = backend_.PreviewJog(CurrentJogRequest());
  message_ = last_verdict_->accepted ? "" : "refused: " + last_verdict_->reason;
}

void PanelController::GoJog() {
  last_verdict_ = backend_.StartJog(CurrentJogRequest());  // previewed again by the backend before it starts
  last_started_jog_ = last_verdict_;
  message_ = last_verdict_->accepted ? "" : "refused: " + last_verdict_->reason;
}

bool PanelController::ScriptConditionHolds(const ScriptAction& wait) const {
  if (wait.target == "state") return view_.has_status && view_.state_name == wait.value;
  if (wait.target != "jog.done") throw std::invalid_argument("wait: unknown condition '" + wait.target + "'");
  if (!view_.has_status || !last_started_jog_ || !last_started_jog_->accepted) return false;
  const Eigen::Isometry3d& end = last_started_jog_->X_FM_end;
  const auto apart = [&](const Eigen::Isometry3d& X, double position_m, double angle_rad) {
    return (X.translation() - end.translation()).norm() > position_m ||
           Eigen::AngleAxisd(end.linear().transpose() * X.linear()).angle() > angle_rad;
  };
  // The player's last set-point is the end pose itself (eq. 9 at its duration); 1 um, 1 urad for rounding.
  if (apart(X_FM_commanded_, 1e-6, 1e-6)) return false;
  if (apart(view_.X_FM, kJogDonePositionM, kJogDoneAngleRad)) return false;
  return 1e-9 * static_cast<double>(status_stamp_ns_ - still_since_ns_) >= kJogDoneStillS;
}

void PanelController::StopJog() { backend_.StopJog(); }

void PanelController::SendCommand(teleop::StateCommand command) {
  if (command == teleop::StateCommand::kEStop) ++estops_sent_;
  if (!backend_.SendCommand(command))
    Refused(std::string("command ") + teleop::ToString(command) + ": the link refused it");
  else
    message_.clear();
}

void PanelController::SetHapticEnabled(bool enabled) {
  std::string reason;
  HapticModeModel next = haptic_;
  if (!next.SetEnabled(enabled, reason)) return Refused(reason);
  if (!backend_.RequestHapticMode(next.request(), reason)) return Refused(reason);
  haptic_ = std::move(next);
  message_.clear();
}

void PanelController::SetClutched(bool clutched) {
  std::string reason;
  HapticModeModel next = haptic_;
  if (!next.SetClutched(clutched, reason)) return Refused(reason);
  if (!backend_.RequestHapticMode(next.request(), reason)) return Refused(reason);
  haptic_ = std::move(next);
  message_.clear();
}

void PanelController::SetMethod(const std::string& method) {
  std::string reason;
  HapticModeModel next = haptic_;
  if (!next.SetMethod(method, reason)) return Refused(reason);
  if (!backend_.RequestHapticMode(next.request(), reason)) return Refused(reason);
  haptic_ = std::move(next);
  message_.clear();
}

void PanelController::SetCapPreset(SpeedCapPreset preset) {
  std::string reason;
  HapticModeModel next = haptic_;
  if (!next.SetCapPreset(preset, reason)) return Refused(reason);
  if (!backend_.RequestHapticMode(next.request(), reason)) return Refused(reason);
  haptic_ = std::move(next);
  message_.clear();
}

void PanelController::Click(const std::string& button) {
  using teleop::StateCommand;
  if (button == "jog.preview") return PreviewJog();
  if (button == "jog.go") return GoJog();
  if (button == "jog.stop") return StopJog();
  if (button == "estop") return SendCommand(StateCommand::kEStop);
  if (button == "reset") return SendCommand(StateCommand::kReset);
  if (button == "home") {
    // Disabled in the window unless it makes sense (view_model.h); a script's click is refused the same way.
    if (view_.has_status && !view_.home_allowed)
      return Refused("home: only a disabled follower is homed (it is " + view_.state_name + ")");
    return SendCommand(StateCommand::kHome);
  }
  if (button == "enable") return SendCommand(StateCommand::kEnable);
  if (button == "disable") return SendCommand(StateCommand::kDisable);
  if (button == "haptic.on") return SetHapticEnabled(true);
  if (button == "haptic.off") return SetHapticEnabled(false);
  if (button == "haptic.clutch") return SetClutched(true);
  if (button == "haptic.unclutch") return SetClutched(false);
  throw std::invalid_argument("button: '" + button + "' is not a panel button");
}

void PanelController::Set(const std::string& field, const std::string& value) {
  if (field == "jog.axis") {
    jog_form_.axis = JogAxisFromString(value);
  } else if (field == "jog.amount") {
    jog_form_.amount = ParseValue(field, value);
  } else if (field == "jog.timing") {
    if (value == "duration")
      jog_form_.timing = JogTiming::kDuration;
    else if (value == "speed")
      jog_form_.timing = JogTiming::kSpeed;
    else
      throw std::invalid_argument("jog.timing: expected duration or speed, got '" + value + "'");
  } else if (field == "jog.duration_s") {
    jog_form_.duration_s = ParseValue(field, value);
  } else if (field == "jog.speed") {
    jog_form_.speed = ParseValue(field, value);
  } else if (field == "haptic.method") {
    SetMethod(value);
  } else if (field == "haptic.caps") {
    SetCapPreset(SpeedCapPresetFromString(value));
  } else if (field == "view.azimuth_deg") {
    camera_.azimuth_deg = ParseValue(field, value);
  } else if (field == "view.elevation_deg") {
    camera_.elevation_deg = ParseValue(field, value);
  } else if (field == "view.distance_mm") {
    const double distance = ParseValue(field, value);
    if (!(distance > 0)) throw std::invalid_argument("view.distance_mm: expected a positive distance");
    camera_.distance_mm = distance;
  } else {
    throw std::invalid_argument("field: '" + field + "' is not a panel field");
  }
}

}  // namespace robossis::panel
