#pragma once
// The panel's logic, without a window: the form fields, the buttons and what they do through the PanelBackend, the
// view model of the latest snapshot, the plot histories, the camera. The window draws this state and forwards the
// user's clicks here; a script (script.h) sets the same fields and presses the same buttons by name, so a scripted
// test exercises exactly what a person does.
//
// Buttons (Click): jog.preview, jog.go, jog.stop, estop, reset, home, enable, disable,
//                  haptic.on, haptic.off, haptic.clutch, haptic.unclutch.
// Fields (Set):    jog.axis (x|y|z|roll|pitch|yaw), jog.amount (mm or deg, by axis), jog.timing (duration|speed),
//                  jog.duration_s, jog.speed (mm/s or deg/s, by axis), haptic.method (a rendering method),
//                  haptic.caps (clinical|demonstration), view.azimuth_deg, view.elevation_deg, view.distance_mm.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "robot/rsr_model.h"
#include "src/panel/haptic_mode.h"
#include "src/panel/jog.h"
#include "src/panel/panel_backend.h"
#include "src/panel/panel_config.h"
#include "src/panel/plot_buffer.h"
#include "src/panel/script.h"
#include "src/panel/view_model.h"

namespace robossis::panel {

// The jog form, in the units the operator types (mm, deg, s).
struct JogForm {
  JogAxis axis = JogAxis::kZ;
  double amount = 5;       // mm or deg
  JogTiming timing = JogTiming::kDuration;
  double duration_s = 2;
  double speed = 2;        // mm/s or deg/s (peak speed of eq. 9)
};

// Orbit camera around the ring (the window turns it into a projection).
struct Camera {
  double azimuth_deg = 35;
  double elevation_deg = 25;
  double distance_mm = 1100;
};

class PanelController {
 public:
  PanelController(PanelBackend& backend, const robot::RsrModel& model, const PanelConfig& config,
                  HapticModeModel haptic);

  // Reads the snapshots (never waits) and appends the plot samples. Call once per frame.
  void Update(double now_s);

  // By name, as the script does. Throw std::invalid_argument naming the button, field or value when unknown.
  void Click(const std::string& button);
  void Set(const std::string& field, const std::string& value);

  // A script's `wait` condition (script.h) on the view of the last Update(): "state" with a state's name, or
  // "jog.done": the last jog started with GoJog was accepted, its last set-point is commanded (the player reached
  // its end), the measured pose is within kJogDonePositionM and kJogDoneAngleRad of it, and the measured joints
  // have not changed for kJogDoneStillS of the follower's clock (drives near the end may still make their last
  // steps). Throws std::invalid_argument naming an unknown condition.
  bool ScriptConditionHolds(const ScriptAction& wait) const;
  // The robot is at a jog's end: a step of a stroke motor is 5 um (actuation.yaml), so the drives can get there.
  static constexpr double kJogDonePositionM = 1e-5;
  static constexpr double kJogDoneAngleRad = 0.01 * 3.14159265358979323846 / 180;
  // Still: longer than a stepgen's last steps are apart as it comes to rest (about 15 ms at its acceleration).
  static constexpr double kJogDoneStillS = 0.05;

  JogRequest CurrentJogRequest() const;  // the form in SI
  void PreviewJog();
  void GoJog();
  void StopJog();
  void SendCommand(teleop::StateCommand command);
  void SetHapticEnabled(bool enabled);
  void SetClutched(bool clutched);
  void SetMethod(const std::string& method);
  void SetCapPreset(SpeedCapPreset preset);

  JogForm& jog_form() { return jog_form_; }
  Camera& camera() { return camera_; }
  const HapticModeModel& haptic() const { return haptic_; }
  const PanelViewModel& view() const { return view_; }
  const LoopHealth& health() const { return health_; }
  const HandWrench& wrench() const { return wrench_; }
  const Eigen::Isometry3d& commanded_pose() const { return X_FM_commanded_; }
  const std::optional<JogVerdict>& last_verdict() const { return last_verdict_; }
  // The last message for the operator (a refusal, a latched fault's reason); "" when there is none.
  const std::string& message() const { return message_; }
  // The reason of the last fault or E-stop seen, kept after a reset.
  const std::string& last_fault() const { return last_fault_; }
  int estops_sent() const { return estops_sent_; }
  // Plots: commanded then measured pose (x, y, z mm; roll, pitch, yaw deg), and the hand force (N) and torque (N·m).
  const PlotBuffer<12>& pose_plot() const { return pose_plot_; }
  const PlotBuffer<6>& wrench_plot() const { return wrench_plot_; }
  double plot_window_s() const { return plot_window_s_; }
  const robot::RsrModel& model() const { return model_; }

 private:
  void Refused(const std::string& reason) { message_ = reason; }
  PanelBackend& backend_;
  robot::RsrModel model_;
  HapticModeModel haptic_;
  JogForm jog_form_;
  Camera camera_;
  PanelViewModel view_;
  LoopHealth health_;
  HandWrench wrench_;
  Eigen::Isometry3d X_FM_commanded_ = Eigen::Isometry3d::Identity();
  std::optional<JogVerdict> last_verdict_;
  std::optional<JogVerdict> last_started_jog_;  // GoJog's, not the preview's
  std::array<double, 6> still_joints_{};        // the measured joints, and the follower's time they were first seen
  std::int64_t still_since_ns_ = 0;
  std::int64_t status_stamp_ns_ = 0;
  std::string message_;
  std::string last_fault_;
  int estops_sent_ = 0;
  double plot_window_s_;
  PlotBuffer<12> pose_plot_;
  PlotBuffer<6> wrench_plot_;
};

}  // namespace robossis::panel
