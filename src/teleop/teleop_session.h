#pragma once
// A whole teleoperation session on one machine (Fig. 2 in one process): the device back end, the leader unit, the
// in-process link, the follower unit and its back end, each unit on its own loop; the flight recorder writing the
// session log; the summary computed from the recorded ticks. `--clock real` runs the loops on threads on
// wall-clock deadlines; `--clock simulated` steps the same units deterministically on a SimulatedClock, as fast as
// the machine allows. `robossis teleop` and the demo only call this.
//
// The same session splits over two processes or machines (`robossis leader`, `robossis follower`): RunLeader and
// RunFollower each run one unit over a link given by the caller (the DDS link), on wall-clock deadlines, and write
// their half of the outputs (their own records in their own session log).

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/boundary_atlas.h"
#include "haptics/haptics_config.h"
#include "haptics/transfer/transfer_config.h"
#include "robot/actuation/actuation_config.h"
#include "robot/follower.h"
#include "robot/rsr_model.h"
#include "robot/sigma7_model.h"
#include "robot/sim/sim_config.h"
#include "src/core/rt/clock.h"
#include "src/teleop/follower_config.h"
#include "src/teleop/leader_config.h"
#include "src/teleop/link.h"

namespace robossis::teleop {

// Everything a session reads from data/: models and configs (loaded once by the caller).
struct TeleopSetup {
  const robot::RsrModel* rsr = nullptr;
  const robot::Sigma7Model* sigma7 = nullptr;
  haptics::HapticsConfig haptics;
  transfer::TransferConfig transfer;
  actuation::ActuationConfig actuation;
  FollowerConfig follower;
  LeaderConfig leader;
  sim::SimConfig sim;
  std::filesystem::path config_dir;  // data_dir/config: back ends with configs of their own (hal.yaml, dhd.yaml)
  // Loads every config from data_dir/config (throws std::runtime_error naming the file and key).
  static TeleopSetup Load(const std::filesystem::path& data_dir, const robot::RsrModel& rsr,
                          const robot::Sigma7Model& sigma7);
  // The setup refers to both models, so they must outlive it: temporaries are refused at compile time.
  static TeleopSetup Load(const std::filesystem::path&, robot::RsrModel&&, const robot::Sigma7Model&) = delete;
  static TeleopSetup Load(const std::filesystem::path&, const robot::RsrModel&, robot::Sigma7Model&&) = delete;
  static TeleopSetup Load(const std::filesystem::path&, robot::RsrModel&&, robot::Sigma7Model&&) = delete;
};

struct TeleopRequest {
  std::string device = "sim";          // haptics::MakeDevice: sim | replay:FILE.csv | dhd[:...]
  std::string method = "proxy-safe";   // haptics::KnownMethods()
  std::string follower = "sim";        // sim (Bullet) | recorder (pulse recorder) | hal (LinuxCNC HAL drives)
  double rate_hz = 1000;               // the leader's loop (a multiple of the 1 kHz transfer rate)
  double duration_s = 10;              // a replay stops earlier: 0.5 s after its end
  bool real_clock = false;
  // The operator's home when the session starts: the state machine never homes on enable, so a back end that does
  // not measure its joints (hal) is homed only by this (`--home`: the robot stands at its home pose now) or a later
  // home command. Sent before the enable.
  bool home_at_start = false;
  // The operator's enable when the session starts (the follower follows once the leader has presence; refused while
  // unhomed). Split: the follower enables itself at its start; the leader never sends a command (a follower that
  // disabled itself when its leader was lost is enabled again from the panel or the follower's console).
  bool enable_at_start = true;
  std::shared_ptr<const geometry::BoundaryAtlas> atlas;  // the mesh methods' atlas
  // Set: leader.csv and follower.csv (of the units run) are written into this folder as the run goes, and
  // TeleopOutputs' CSV strings stay empty, so that memory stays flat however long the run. Empty: returned whole.
  std::filesystem::path csv_dir;
  // Bilateral feedback (leader.yaml `feedback` unless set): --feedback walls|bilateral, --feedback-gain G.
  std::string feedback;      // empty: leader.yaml's mode
  double feedback_gain = -1; // < 0: leader.yaml's gain
  std::string feedback_passivity;  // --feedback-passivity off|classic|network; empty: leader.yaml's
  bool let_go_detector = false;    // --let-go-detector: on whatever leader.yaml says (feedback.detect_let_go)
  // The in-process link's one-way delay, both directions (--link-delay-ms; `teleop` on one process only).
  double link_delay_s = 0;
  // The Bullet follower's muscle traction (--sim-load-n, --sim-load-nm): the reduction scenario's muscles, calibrated
  // to pull with this load along the femur axis and twist with this torque about it at the home pose.
  double sim_load_n = 0;
  double sim_load_nm = 0;
};

struct TeleopOutputs {
  nlohmann::ordered_json summary;
  std::string leader_csv;
  std::string follower_csv;
  std::string periods_csv;
  std::vector<std::string> warnings;  // real-time setup refused (SCHED_FIFO, mlockall)
  // Not empty: recording failed (a write error, a full disk, the record queue full) and names the cause; the
  // follower held the robot at rest from then on and the session ended. The rest holds what was recorded; the
  // caller writes it and exits non-zero.
  std::string recorder_error;
};

std::vector<std::string> KnownFollowers();  // sim, recorder, hal

// Whether a follower unit of back end `kind` enables at its start unless told (--enable, --no-enable): the back ends
// that measure their joints (robot::Follower::MeasuresJoints: sim, recorder) are homed from their start and do; the
// HAL drives start unhomed after every start and stay disabled until the operator homes and enables them.
bool EnablesAtStartByDefault(const std::string& kind);

// The follower back end `kind` names (with the muscles' traction load_n, load_nm on the simulation) (KnownFollowers()), at the robot's home pose: the Bullet RSR without the bone
// fragments, the LinuxCNC HAL drives (hal.yaml in setup.config_dir), or the pulse recorder sized for
// `max_duration_s` of actuation ticks (at most 4e6 samples). The one factory of `robossis teleop`, `robossis
// follower` and `robossis panel`. Throws std::invalid_argument for an unknown kind, std::runtime_error when the back
// end cannot start (HAL not running, a bad hal.yaml).
std::unique_ptr<robot::Follower> MakeFollowerBackEnd(const std::string& kind, const TeleopSetup& setup,
                                                     double max_duration_s, double load_n = 0, double load_nm = 0);

// Runs a session, writing its log to `log_file`. Throws std::invalid_argument on a bad request (naming the option),
// std::runtime_error on a failure to write the log.
TeleopOutputs RunTeleop(const TeleopRequest& request, const TeleopSetup& setup, const std::filesystem::path& log_file);

// The leader unit alone, over `link`, in real time: request.follower is not used. Ends after duration_s, 0.5 s after
// a replay's end, or once `stop` (may be null; a signal handler sets it) is set. The outputs hold the leader's half
// (leader.csv, the leader's keys of the summary).
TeleopOutputs RunLeader(const TeleopRequest& request, const TeleopSetup& setup, LeaderLink& link,
                        const std::filesystem::path& log_file, const std::atomic<bool>* stop = nullptr);

// The follower unit alone, over `link`, in real time on `clock` (the one the link stamps arrivals with):
// request.device and request.method are not used. Ends after duration_s or once `stop` is set; the drives are
// disabled at the end. The outputs hold the follower's half (follower.csv, its keys of the summary, set-points
// accepted and rejected). `running` (may be empty) is called once, on the calling thread, when the loops run: a
// leader started after it finds the follower answering at once.
TeleopOutputs RunFollower(const TeleopRequest& request, const TeleopSetup& setup, FollowerLink& link,
                          const rt::MonotonicClock& clock, const std::filesystem::path& log_file,
                          const std::atomic<bool>* stop = nullptr, const std::function<void()>& running = {});

// The outputs of the run that wrote `log_file`, recomputed from its records. Throws std::runtime_error naming the
// file and the problem.
TeleopOutputs ReplaySessionLog(const std::filesystem::path& log_file);

}  // namespace robossis::teleop
