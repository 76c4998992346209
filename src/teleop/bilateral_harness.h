#pragma once
// The bilateral feedback port on a simulated clock, one axis, for the delay × scenario matrix: an operator's hand
// (a mass-spring-damper tracking an intended motion), the device displaying the follower's load through the
// passivity observer/controller of the leader unit (FeedbackPassivity, the same code), a link delaying, jittering and
// losing packets in both directions, and a position-controlled follower against an environment (free motion, a
// hard wall, a preloaded traction spring, the 517 N muscle load, a sudden release, the operator letting go).
//
// Why one axis and not the Bullet follower: the matrix is 6 delays × 6 scenarios × 3 schemes × 60 s; the energy
// argument of time-domain passivity is per port and per axis, and the same class observes and controls it. The
// full runtime (`robossis teleop --feedback bilateral --link-delay-ms D`) runs the same port with the real units.
//
// Every constant of the operator and the environments is an [assumed] named value here (HarnessParams).

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "src/teleop/feedback_passivity.h"
#include "src/teleop/follower_passivity.h"
#include "src/teleop/let_go_detector.h"

namespace robossis::teleop {

enum class HarnessScenario : std::uint8_t { kFree, kWall, kSpring, kLoad517, kRelease, kLetGo };
const char* ToString(HarnessScenario scenario);
std::vector<HarnessScenario> AllHarnessScenarios();

struct HarnessParams {
  HarnessScenario scenario = HarnessScenario::kFree;
  FeedbackPassivityScheme scheme = FeedbackPassivityScheme::kNetwork;
  double one_way_delay_s = 0.1;
  double jitter_s = 0.002;      // [assumed] uniform extra delay per packet, 0..jitter_s (packets keep latest-only order)
  double loss = 0.05;           // packet loss, each direction
  double duration_s = 60;
  double rate_hz = 1000;        // both units' ticks
  double gain = 0.025;          // leader.yaml feedback.gain
  double max_force_n = 15;      // the rendering caps
  std::uint32_t seed = 42;
  // [assumed] The operator: hand + device mass, grasp stiffness and damping (a light grasp, within the 100–1000 N/m
  // of the haptics literature), tracking an intended motion of two sines (20 mm at 0.3 Hz, 5 mm at 1.1 Hz).
  double hand_mass_kg = 0.7;
  double hand_stiffness_n_per_m = 400;
  double hand_damping_n_s_per_m = 15;
  double intent_amplitude_m = 0.02;
  double intent_frequency_hz = 0.3;
  double intent_fast_amplitude_m = 0.005;
  double intent_fast_frequency_hz = 1.1;
  // [assumed] Environments: a bone-contact wall 10 mm out, stiffness 20 kN/m (scaled by the gain: 500 N/m at the
  // hand); the traction spring of sim.yaml's muscles (20 680 N/m, 300 N·s/m) preloaded with 200 N (kSpring) or the
  // paper's 517 N (kLoad517, kRelease, kLetGo); the release or let-go at release_at_s.
  double wall_at_m = 0.01;
  double wall_stiffness_n_per_m = 20000;
  double spring_stiffness_n_per_m = 20680;
  double spring_damping_n_s_per_m = 300;
  double spring_preload_n = 200;
  double load_preload_n = 517;
  double release_at_s = 30;
  FeedbackPassivityConfig passivity;  // its damper caps
  bool detect_let_go = false;         // the leader's let-go detector on (let_go_detector.h)
  LetGoConfig let_go;
};

struct HarnessResult {
  HarnessParams params;
  double feedback_energy_j = 0;       // the port gave the hand minus what it took, at the end (<= 0: passive)
  double max_feedback_energy_j = 0;   // its largest value at any sample
  double min_observer_j = 0;          // the scheme's observer (kOff: the one-port E_in − E_out)
  double hand_energy_in_j = 0;        // what the hand gave the port
  double dissipated_share = 0;        // the controller's dissipation / what the hand gave
  double force_error_n_rms = 0;       // displayed − gain × true environment force, delay removed
  double position_error_mm_rms = 0;   // follower − hand, delay removed
  double drift_mm = 0;                // |follower − hand (delay removed)| over the last second, mean
  double drift_growth_mm = 0;         // that, minus the same over the first second after 5 s
  double force_hf_share = 0;          // share of the displayed force's power above 25 Hz
  double rest_after_event_s = -1;     // kRelease/kLetGo: time until the hand stays below 1 mm/s (-1: never, or no event)
  // The network gave the environment minus what the hand put in as received (divided by the gain), largest at any
  // sample (<= 0: the follower's port passive in the network form's sense; meaningful for kNetwork only).
  double max_follower_excess_j = 0;
  double let_go_detected_s = -1;      // when the detector believed the operator let go (-1: never)
  double active_fraction = 0;         // samples the controller changed the force beyond its tolerance in
  double taper_active_fraction = 0;   // samples its taper alone did
  double max_force_n = 0;
};

HarnessResult RunHarness(const HarnessParams& params);

// Every scenario × delay × scheme from `base` (its other values kept), in that order.
std::vector<HarnessResult> RunHarnessMatrix(const HarnessParams& base, const std::vector<double>& delays_s,
                                            const std::vector<FeedbackPassivityScheme>& schemes);
// One row per run (SI, with the units in the keys).
nlohmann::ordered_json ToJson(const HarnessResult& result);

}  // namespace robossis::teleop
