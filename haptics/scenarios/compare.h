#pragma once
// Side-by-side comparison of rendering methods on the same scripted hand motion, in closed loop with the simulated
// sigma.7, and these metrics, all measured against the TRUE boundary (IK feasibility with bisection,
// haptics/rendering/boundary_probe.h), independently of the method:
//   max_penetration_mm / _deg   how far the commanded RSR pose went beyond the true boundary: distance to the nearest
//                               feasible position at the same orientation / angle to the nearest feasible orientation
//                               at the same position; each tick counts toward the cheaper of the two escapes
//                               (15 mm ≡ 5°), since the coupled workspace can often be re-entered either way
//   direction_error_deg_p95     angle between the rendered wall force (torque) — the output minus the viscous −c·v
//                               every method applies in free space too — and the true inward normal of the tightest
//                               joint limit at the commanded pose, over ticks in contact with |F| > 1 N (|τ| > 0.02 N·m)
//   max_force_step_n            largest change of the force vector from one tick to the next (continuity)
//   saturation_time_s           time with the force or torque at its cap
//   energy_generated_j          energy the wall put into the hand: over each contact episode, the largest value of the
//                               running integral of F·v + τ·ω (0 for a passive wall), summed over episodes
//   tick_us_p50/p99/max         wall-clock time of HapticRenderer::Tick
//   max_free_space_force_n      largest |F| (|τ|: _torque_nm) displayed while the commanded pose is inside the true
//                               region: a phantom wall (the damper included)
//   wall_onset_mm / _deg        push scenarios: signed distance to the true boundary where the wall first reached
//                               2 N (0.05 N·m) — the workspace a method gives up before the true boundary
//
// The reference has a range (kPenetrationRangeM / _Rad, boundary_probe.h) and a normal that is not defined
// everywhere; the metrics say where it ends instead of using its capped or arbitrary values:
//   penetration_beyond_reference_ticks  ticks where neither escape was found within the range: the penetration is
//                               unknown (at least the range), so it is counted here and left out of the maxima; a tick
//                               with one escape in range counts that one (beyond the twist limit no position is
//                               feasible, far from the workspace no orientation is)
//   direction_error_left_out_ticks      ticks whose wall force (torque) would have been scored but the reference's
//                               normal is not defined there: the penetration in that space is beyond the range, or
//                               the pose is on an edge (IsNormalUnique*: a second limit within kNormalEdgeMargin* of
//                               the tightest, with a normal more than kNormalCreaseDeg away)
//   free_share / shallow_share / deep_share  share of ticks with the commanded pose inside the true region, beyond it
//                               by at most kShallowPenetration* (in the counted unit), and deeper (or beyond the
//                               reference)

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "geometry/boundary_atlas.h"
#include "haptics/haptics_config.h"
#include "haptics/scenarios/scenario.h"

namespace robossis::haptics {

// Direction errors need a unique reference normal: on an edge, a second limit within this first-order distance of
// the tightest one [assumed: the soft-min normal's blend, where the second limit's weight exceeds 1/e] ...
inline constexpr double kNormalEdgeMarginM = 1e-3;
inline constexpr double kNormalEdgeMarginDeg = 0.5;
// ... whose normal is more than this far from the tightest's [assumed: beyond it, the bisector the reference
// reports can be more than 15° from a limit's own normal, as large as the errors being compared].
inline constexpr double kNormalCreaseDeg = 30.0;
// Shallow contact: the commanded pose beyond the true boundary by at most this, in the unit its penetration is
// counted in [assumed: a third of the paper's point-cloud radii (15 mm, 5°): a hand resting on a wall; deeper it has
// pushed through].
inline constexpr double kShallowPenetrationMm = 5.0;
inline constexpr double kShallowPenetrationDeg = 5.0 / 3.0;

// Which of a tick's two penetrations counts toward the summary (see RunMethod).
enum class PenetrationCount { kFree, kTranslation, kRotation, kBeyondReference };
const char* ToString(PenetrationCount c);

struct TickRecord {
  double t_s = 0;
  int episode = 0;
  Vector6d target_mm_deg = Vector6d::Zero();  // hand target (RSR pose)
  Vector6d pose_mm_deg = Vector6d::Zero();    // RSR pose commanded by the HC
  Eigen::Vector3d force_n = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_nm = Eigen::Vector3d::Zero();
  int status = 0;
  bool saturated = false;
  double tick_us = 0;
  double penetration_mm = 0;
  double penetration_deg = 0;
  // The search found nothing within the reference's range: penetration_mm (_deg) is then the range, a lower bound.
  bool penetration_mm_beyond_reference = false;
  bool penetration_deg_beyond_reference = false;
  PenetrationCount penetration_counted = PenetrationCount::kFree;
  double force_direction_error_deg = -1;   // -1: not evaluated this tick
  double torque_direction_error_deg = -1;
  // Would have been scored (in contact, wall above the threshold) but the reference's normal is not defined here.
  bool force_direction_left_out = false;
  bool torque_direction_left_out = false;
  double push_signed = 0;  // push episodes: signed distance to the true boundary along the push (mm or deg)
  bool push_rotational = false;
  bool is_push = false;
  Eigen::Vector3d stroke_mm = Eigen::Vector3d::Zero();  // d_i at the commanded pose
  Eigen::Vector3d cone_deg = Eigen::Vector3d::Zero();   // spherical-joint angles
  double energy_into_hand_j = 0;  // cumulative over the run
};

struct MethodMetrics {
  double max_penetration_mm = 0;
  double max_penetration_deg = 0;
  double direction_error_deg_p95 = 0;
  double force_direction_error_deg_p95 = 0;
  double torque_direction_error_deg_p95 = 0;
  double max_force_step_n = 0;
  double max_torque_step_nm = 0;
  double saturation_time_s = 0;
  double energy_generated_j = 0;
  double tick_us_p50 = 0, tick_us_p99 = 0, tick_us_max = 0;
  // Where the wall starts: over push episodes, the most negative signed distance to the true boundary at which
  // |F| first reached 2 N (|τ| 0.05 N·m) — how much workspace the method gives up before the true boundary
  // (negative: before it). NaN-free: 0 if no push episode reached the threshold.
  double wall_onset_mm = 0;
  double wall_onset_deg = 0;
  // No phantom wall: the largest force (torque) displayed while the commanded RSR pose is inside the true region
  // (no penetration), the damper included — what the hand feels where there is no wall.
  double max_free_space_force_n = 0;
  double max_free_space_torque_nm = 0;
  int deep_penetration_ticks = 0;
  int fault_ticks = 0;
  // Where the reference ends (see the top of this file).
  int ticks = 0;
  int penetration_beyond_reference_ticks = 0;
  int translation_beyond_reference_ticks = 0;  // the translational search alone found nothing
  int rotation_beyond_reference_ticks = 0;
  int direction_error_scored_ticks = 0;  // ticks with a force or torque direction error scored
  int direction_error_left_out_ticks = 0;
  double free_share = 0, shallow_share = 0, deep_share = 0;
};

struct MethodRun {
  std::string method;
  MethodMetrics metrics;
  std::vector<TickRecord> trace;
};

struct CompareSettings {
  double rate_hz = 1000;
  // The one HC -> RSR frame map (transfer.yaml `mapping`): the hand is placed and the walls are seen through it.
  transfer::HcToRsrFrame frame;
  bool keep_trace = true;
  int trace_decimation = 1;  // keep every n-th tick in the trace (metrics always use every tick)
};

// Runs one method over every episode of the scenario in closed loop. `progress` (optional) gets a fraction in [0, 1].
MethodRun RunMethod(const Scenario& scenario, const std::string& method, const HapticsConfig& config,
                    const robot::RsrModel& rsr, const robot::Sigma7Model& sigma7, const CompareSettings& settings,
                    std::shared_ptr<const geometry::BoundaryAtlas> atlas = nullptr,
                    const std::function<void(double)>& progress = {});

// Several methods on one scenario, each run as RunMethod runs it, up to `jobs` at a time on threads of their own (1:
// one after the other on the calling thread). The runs share only const inputs and the atlas (read-only), so every
// metric and trace is the one RunMethod gives alone; only the tick times see the other runs. With `jobs` at most the
// number of cores each run's ticks have a core of their own on an otherwise idle machine; other load preempts them
// more often than a run alone (the tick p99 and max then measure the machine more than the method).
// The events (optional) are called one at a time, never concurrently: `started` when a run begins, `done` when it
// ended (with its wall time, e.g. to write its trace and free it). The runs are returned in the order of `methods`.
// Throws std::invalid_argument for jobs < 1; an exception of a run (an unknown method) or of an event is rethrown
// here once the runs in progress ended (no new run starts after it).
struct MethodRunEvents {
  std::function<void(std::size_t index)> started;
  std::function<void(std::size_t index, MethodRun& run, double wall_s)> done;
};
std::vector<MethodRun> RunMethods(const Scenario& scenario, const std::vector<std::string>& methods,
                                  const HapticsConfig& config, const robot::RsrModel& rsr,
                                  const robot::Sigma7Model& sigma7, const CompareSettings& settings,
                                  std::shared_ptr<const geometry::BoundaryAtlas> atlas, int jobs,
                                  const MethodRunEvents& events = {});

// Output formats.
std::string TraceCsv(const MethodRun& run);
nlohmann::ordered_json SummaryJson(const Scenario& scenario, const CompareSettings& settings,
                                   const std::vector<MethodRun>& runs);
// Markdown table: one row per method, one column per metric, the best value of each column in bold, and a last row
// naming the winner of each metric.
// Then, unranked, where the reference ends: ticks beyond its range, direction samples left out, contact shares.
std::string MarkdownTable(const std::vector<MethodRun>& runs);
// What the reference is and where it ends: its range, the edge rule of the direction error, the contact thresholds.
std::string MarkdownReferenceNotes();

}  // namespace robossis::haptics
