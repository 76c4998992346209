#pragma once
// The follower back end for real step/direction drives through LinuxCNC HAL (`--follower hal`).
//
// The follower process is a HAL userspace component (hal.yaml's component_name, default "robossis"). A user-space
// loop cannot time steps at 10 kHz; LinuxCNC's stepgen does, on its base thread or in a Mesa card's FPGA. The
// component exports per joint (eq. 13 order) the position and velocity commands, the position feedback and the
// enable, plus an external fault input and a watchdog output (hal_names.h). On start it links each pin to the
// signal of the same role that the HAL files of data/hal/ create, so halrun can be running before the follower.
//
// Units on the pins are the joints' SI units (rad, m), as displacements from the homing reference; stepgen's
// position-scale (the steps per unit of actuation.yaml, written into the HAL file) turns them into steps, so the
// counts stepgen emits are eq. 17's count.
//
// Life cycle: the follower starts unhomed after every start (stepgen's feedback counts steps sent, not a position
// measured: a restarted follower cannot know where the robot stands). Home() is the operator's declaration that the
// robot stands at its home pose now, and references the present motor position to it; Enable() needs a homed,
// fault-free follower with live feedback. HAL's watchdog re-arms only on a rising edge of the enabled pin that its
// servo-thread function sees, so Enable() raises the joint enables at once but the enabled pin only once the servo
// thread has run a whole period since the pin was last written low (kRearmHandshakes, seen through the echo);
// until then the drives stay cut by the watchdog rather than missing the edge and staying cut for good;
// Service() exchanges the heartbeat with the servo thread, reads feedback and the fault pin, and latches FollowerFault::kExternal when the
// fault pin is raised (seen at the first Service() after it rises: within one servo period) and
// FollowerFault::kFeedbackLost when the servo thread has not echoed the watchdog for feedback_timeout_s. A fault
// disables every drive and holds the command at the feedback. The destructor disables and leaves HAL (hal_exit).

#include <cstdint>
#include <filesystem>
#include <memory>

#include "robot/drivers/hal_config.h"
#include "robot/follower.h"
#include "robot/rsr_model.h"

namespace robossis::drivers {

class HalFollower final : public robot::Follower {
 public:
  // Joins HAL as `config.component_name`, creates and links the pins. Throws std::runtime_error naming the pin,
  // the signal or the HAL call that failed (HAL not running, a component of that name already loaded, a HAL file
  // without the follower's signals); nothing is left in HAL then.
  HalFollower(const robot::RsrModel& model, const HalConfig& config);
  ~HalFollower() override;
  HalFollower(const HalFollower&) = delete;
  HalFollower& operator=(const HalFollower&) = delete;

  bool Enable() noexcept override;
  void Disable() noexcept override;
  bool Home() noexcept override;
  // stepgen's position feedback counts the steps it sent, which an open-loop drive may have lost or a push may
  // have undone: not a measurement (an encoder or index input on the HAL side would be one; not supported yet).
  bool MeasuresJoints() const noexcept override { return false; }
  bool ResetFault() noexcept override;
  void Command(const robot::RsrJointCommand& command) noexcept override;
  void Service(double now_s) noexcept override;
  robot::RsrFollowerState State() const noexcept override { return state_; }

  const HalConfig& config() const { return config_; }
  const robot::RsrJointVector& q_home() const { return q_home_; }

 private:
  struct Pins;  // pin pointers, in HAL's shared memory

  bool FeedbackAlive() const noexcept;
  void HoldAtFeedback() noexcept;
  void WriteEnables(bool on) noexcept;
  void Latch(robot::FollowerFault fault) noexcept;
  void RearmWhenSeenLow() noexcept;

  // Echo handshakes after the enabled pin went low before it may rise: the first may echo a level written before
  // the low one; the second shows an echo after it, but the watchdog function runs before the echo in the servo
  // thread (data/hal: addf order), so it may have preceded the write; the third is in a later period, whose watchdog
  // function ran wholly after the low write.
  static constexpr std::uint64_t kRearmHandshakes = 3;

  const robot::RsrModel& model_;
  HalConfig config_;
  int comp_id_ = -1;
  Pins* pins_ = nullptr;
  robot::RsrJointVector q_home_;                                    // joints at the home pose (IK)
  robot::RsrJointVector fb_home_ = robot::RsrJointVector::Zero();  // feedback when homed
  bool watchdog_ = false;
  double now_s_ = 0;
  double last_alive_s_ = 0;
  bool serviced_ = false;   // Service() has run once (a watchdog level was written)
  bool echo_seen_ = false;  // the echo has changed at least once: the servo thread is known to run
  std::uint64_t handshakes_ = 0;  // echoes seen
  std::uint64_t low_at_ = 0;      // handshakes_ when the enabled pin was last written low
  bool rearm_pending_ = false;    // enabled, but the enabled pin not yet raised
  robot::RsrFollowerState state_;
};

// The `--follower hal` back end: hal.yaml from `config_dir`. Throws std::runtime_error (also when the program was
// built without LinuxCNC's headers).
std::unique_ptr<robot::Follower> MakeHalFollower(const robot::RsrModel& model,
                                                 const std::filesystem::path& config_dir);

}  // namespace robossis::drivers
