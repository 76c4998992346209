#include "src/teleop/bilateral_harness.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace robossis::teleop {

const char* ToString(HarnessScenario scenario) {
  switch (scenario) {
    case HarnessScenario::kFree: return "free";
    case HarnessScenario::kWall: return "wall";
    case HarnessScenario::kSpring: return "spring";
    case HarnessScenario::kLoad517: return "load517";
    case HarnessScenario::kRelease: return "release";
    case HarnessScenario::kLetGo: return "let_go";
  }
  return "unknown";
}

std::vector<HarnessScenario> AllHarnessScenarios() {
  return {HarnessScenario::kFree,    HarnessScenario::kWall,    HarnessScenario::kSpring,
          HarnessScenario::kLoad517, HarnessScenario::kRelease, HarnessScenario::kLetGo};
}

namespace {

constexpr double kPi = 3.14159265358979323846;
// [assumed] The device alone once the operator let go: the sigma.7's translational mass and its friction.
constexpr double kDeviceMassKg = 0.2;
constexpr double kDeviceDampingNSPerM = 0.5;
// [assumed] The operator holds still this long before the release or the let-go, so that the rest is judged.
constexpr double kStillBeforeEventS = 5;
constexpr double kRestSpeedMS = 0.001;   // [assumed] "at rest": below 1 mm/s
constexpr double kHighFrequencyHz = 25;  // [assumed] the chatter band: above 25 Hz
// [assumed] The follower's speed cap, the teleop runs' --max-speed-mm-s 100: a set-point farther away than one
// tick's travel (the network form's follower making up a held-back step) is approached at this speed; the other
// schemes' follower is the ideal position source of the first matrix.
constexpr double kFollowerMaxSpeedMS = 0.1;

// A packet in flight, latest-value semantics: one arriving after a newer one is dropped.
template <typename T>
struct Channel {
  struct Packet {
    T value;
    double due_s;
    std::uint64_t seq;
  };
  std::vector<Packet> in_flight;
  std::uint64_t next_seq = 0, last_delivered = 0;
  bool Deliver(double now_s, T& out) {
    bool got = false;
    for (std::size_t i = 0; i < in_flight.size();) {
      if (in_flight[i].due_s <= now_s) {
        if (in_flight[i].seq > last_delivered) {
          last_delivered = in_flight[i].seq;
          out = in_flight[i].value;
          got = true;
        }
        in_flight[i] = in_flight.back();
        in_flight.pop_back();
      } else {
        ++i;
      }
    }
    return got;
  }
};

struct StatusPacket {
  double wrench_n = 0;
  double energy_in_j = 0;
};
struct SetPointPacket {
  double position_m = 0;
  double energy_in_j = 0;  // what the hand put into the leader's port
};

// The environment's force on the follower at x, v (1-D, + = pushing toward +x).
double EnvironmentForce(const HarnessParams& p, double t, double x, double v) {
  switch (p.scenario) {
    case HarnessScenario::kFree: return 0;
    case HarnessScenario::kWall: return x > p.wall_at_m ? -p.wall_stiffness_n_per_m * (x - p.wall_at_m) : 0.0;
    case HarnessScenario::kRelease:
      if (t >= p.release_at_s) return 0;
      [[fallthrough]];
    case HarnessScenario::kSpring:
    case HarnessScenario::kLoad517:
    case HarnessScenario::kLetGo: {
      const double preload = p.scenario == HarnessScenario::kSpring ? p.spring_preload_n : p.load_preload_n;
      // Muscles only pull (toward −x): slack lines give nothing.
      return -std::max(0.0, preload + p.spring_stiffness_n_per_m * x + p.spring_damping_n_s_per_m * v);
    }
  }
  return 0;
}

// Variance share above `fc` of a signal sampled at fs: a 2nd-order Butterworth high-pass (bilinear), run forward.
double HighFrequencyShare(const std::vector<double>& f, double fs, double fc) {
  if (f.size() < 4) return 0;
  double mean = 0;
  for (double v : f) mean += v;
  mean /= static_cast<double>(f.size());
  const double K = std::tan(kPi * fc / fs), q = std::sqrt(2.0);
  const double norm = 1 / (1 + K * q + K * K);
  const double b0 = norm, b1 = -2 * norm, b2 = norm;
  const double a1 = 2 * (K * K - 1) * norm, a2 = (1 - K * q + K * K) * norm;
  double x1 = 0, x2 = 0, y1 = 0, y2 = 0, hp = 0, total = 0;
  for (double raw : f) {
    const double x = raw - mean;
    const double y = b0 * x + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
    x2 = x1, x1 = x, y2 = y1, y1 = y;
    hp += y * y;
    total += x * x;
  }
  return total > 0 ? hp / total : 0;
}

}  // namespace

HarnessResult RunHarness(const HarnessParams& p) {
  HarnessResult r;
  r.params = p;
  const double dt = 1.0 / p.rate_hz;
  const auto n = static_cast<std::size_t>(std::llround(p.duration_s * p.rate_hz));
  const auto lag = static_cast<std::size_t>(std::llround(p.one_way_delay_s * p.rate_hz));
  std::mt19937 gen(p.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const bool has_event = p.scenario == HarnessScenario::kRelease || p.scenario == HarnessScenario::kLetGo;

  FeedbackPassivityConfig pc = p.passivity;
  pc.scheme = p.scheme;
  FeedbackPassivity port(pc);
  LetGoDetector detector(p.let_go);
  bool let_go_seen = false;
  FollowerPassivity follower_port;
  Channel<SetPointPacket> setpoints;  // leader → follower: the hand's position and its port's input energy
  Channel<StatusPacket> statuses;     // follower → leader: the wrench and the follower port's input energy
  StatusPacket received;
  SetPointPacket command;

  double x_h = 0, v_h = 0, x_f = 0, v_f = 0, w = 0, dissipated = 0;
  std::vector<double> hand_x(n), env_f(n), shown_f(n), follower_x(n);
  std::uint64_t active = 0, taper_active = 0;
  double force_err2 = 0, pos_err2 = 0;
  std::size_t compared = 0;
  double last_moving_s = -1;

  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt;
    // Leader: the newest status, the port.
    statuses.Deliver(t, received);
    Vector6d wanted = Vector6d::Zero(), twist = Vector6d::Zero();
    // Once the operator let go (detected): no load, the device damped to rest.
    wanted[0] = let_go_seen ? -p.let_go.rest_damping_n_s_per_m * v_h : p.gain * received.wrench_n;
    twist[0] = v_h;
    const CappedWrench c =
        port.Apply(Vector6d::Zero(), wanted, twist, dt, p.max_force_n, 1.0, p.gain * received.energy_in_j);
    port.Observe(c.feedback, twist, dt, p.gain * received.energy_in_j);  // the model device shows what it is given
    const double f_shown = c.displayed[0];
    const double f_uncontrolled = CapWrench(Vector6d::Zero(), wanted, p.max_force_n, 1.0).displayed[0];
    dissipated += std::max(0.0, (f_uncontrolled - f_shown) * v_h * dt);
    if (port.active()) ++active;
    if (port.taper_active()) ++taper_active;
    r.max_force_n = std::max(r.max_force_n, std::abs(f_shown));

    // The hand: the operator's grasp tracking the intent (held still before an event; gone after a let-go).
    const double t_intent = has_event ? std::min(t, p.release_at_s - kStillBeforeEventS) : t;
    const double w1 = 2 * kPi * p.intent_frequency_hz, w2 = 2 * kPi * p.intent_fast_frequency_hz;
    const double x_i = p.intent_amplitude_m * std::sin(w1 * t_intent) + p.intent_fast_amplitude_m * std::sin(w2 * t_intent);
    const double v_i = t_intent < t ? 0.0
                                    : p.intent_amplitude_m * w1 * std::cos(w1 * t) +
                                          p.intent_fast_amplitude_m * w2 * std::cos(w2 * t);
    const bool let_go = p.scenario == HarnessScenario::kLetGo && t >= p.release_at_s;
    const double mass = let_go ? kDeviceMassKg : p.hand_mass_kg;
    const double grasp = let_go ? -kDeviceDampingNSPerM * v_h
                                : p.hand_stiffness_n_per_m * (x_i - x_h) + p.hand_damping_n_s_per_m * (v_i - v_h);
    const double v_before = v_h;
    v_h += (grasp + f_shown) / mass * dt;
    x_h += v_h * dt;
    if (p.detect_let_go && !let_go_seen) {
      let_go_seen = detector.Update(Eigen::Vector3d(f_shown, 0, 0), Eigen::Vector3d(v_before, 0, 0),
                                    Eigen::Vector3d(v_h, 0, 0), dt, port.damping());
      if (let_go_seen) r.let_go_detected_s = t;
    }
    if (uniform(gen) >= p.loss) {
      setpoints.in_flight.push_back({{x_h, port.energies().in_j}, t + p.one_way_delay_s + p.jitter_s * uniform(gen),
                                     ++setpoints.next_seq});
    }

    // Follower: position-controlled toward the newest set-point (kNetwork: as far as its port's budget allows);
    // the environment's force on it.
    setpoints.Deliver(t, command);
    Vector6d step = Vector6d::Zero(), wrench = Vector6d::Zero();
    step[0] = command.position_m - x_f;
    wrench[0] = w;
    if (p.scheme == FeedbackPassivityScheme::kNetwork) {
      step[0] = std::clamp(step[0], -kFollowerMaxSpeedMS * dt, kFollowerMaxSpeedMS * dt);
      step *= follower_port.StepShare(step, wrench, command.energy_in_j / p.gain);
    }
    v_f = step[0] / dt;
    x_f = p.scheme == FeedbackPassivityScheme::kNetwork ? x_f + step[0] : command.position_m;
    w = EnvironmentForce(p, t, x_f, v_f);
    wrench[0] = w;
    follower_port.Book(wrench, step);
    r.max_follower_excess_j =
        std::max(r.max_follower_excess_j, follower_port.energies().out_j - command.energy_in_j / p.gain);
    if (uniform(gen) >= p.loss) {
      statuses.in_flight.push_back({{w, follower_port.energies().in_j},
                                    t + p.one_way_delay_s + p.jitter_s * uniform(gen), ++statuses.next_seq});
    }

    hand_x[k] = x_h;
    follower_x[k] = x_f;
    env_f[k] = w;
    shown_f[k] = f_shown;
    if (k >= lag) {
      // The delay removed: the force shown now against the environment's one delay ago; the follower now against
      // the hand one delay ago.
      force_err2 += std::pow(f_shown - p.gain * env_f[k - lag], 2);
      pos_err2 += std::pow(x_f - hand_x[k - lag], 2);
      ++compared;
    }
    const double out_minus_in = port.energies().out_j - port.energies().in_j;
    r.max_feedback_energy_j = std::max(r.max_feedback_energy_j, out_minus_in);
    r.min_observer_j = std::min(r.min_observer_j, port.observed_j());
    if (has_event && t >= p.release_at_s && std::abs(v_h) >= kRestSpeedMS) last_moving_s = t;
  }
  r.feedback_energy_j = port.energies().out_j - port.energies().in_j;
  r.hand_energy_in_j = port.energies().in_j;
  r.dissipated_share = r.hand_energy_in_j > 0 ? dissipated / r.hand_energy_in_j : 0;
  r.force_error_n_rms = compared ? std::sqrt(force_err2 / static_cast<double>(compared)) : 0;
  r.position_error_mm_rms = compared ? 1e3 * std::sqrt(pos_err2 / static_cast<double>(compared)) : 0;
  auto mean_gap = [&](double from_s, double to_s) {
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t k = lag; k < n; ++k) {
      const double t = static_cast<double>(k) * dt;
      if (t < from_s || t >= to_s) continue;
      sum += std::abs(follower_x[k] - hand_x[k - lag]);
      ++count;
    }
    return count ? 1e3 * sum / static_cast<double>(count) : 0.0;
  };
  r.drift_mm = mean_gap(p.duration_s - 1, p.duration_s);
  r.drift_growth_mm = r.drift_mm - mean_gap(5, 6);
  r.force_hf_share = HighFrequencyShare(shown_f, p.rate_hz, kHighFrequencyHz);
  if (has_event) {
    const double end = static_cast<double>(n) * dt;
    r.rest_after_event_s = last_moving_s < 0 ? 0.0 : last_moving_s < end - 2 * dt ? last_moving_s - p.release_at_s : -1.0;
  }
  r.active_fraction = n ? static_cast<double>(active) / static_cast<double>(n) : 0;
  r.taper_active_fraction = n ? static_cast<double>(taper_active) / static_cast<double>(n) : 0;
  return r;
}

std::vector<HarnessResult> RunHarnessMatrix(const HarnessParams& base, const std::vector<double>& delays_s,
                                            const std::vector<FeedbackPassivityScheme>& schemes) {
  std::vector<HarnessResult> results;
  for (const HarnessScenario scenario : AllHarnessScenarios()) {
    for (const double delay : delays_s) {
      for (const FeedbackPassivityScheme scheme : schemes) {
        HarnessParams p = base;
        p.scenario = scenario;
        p.one_way_delay_s = delay;
        p.scheme = scheme;
        results.push_back(RunHarness(p));
      }
    }
  }
  return results;
}

nlohmann::ordered_json ToJson(const HarnessResult& r) {
  nlohmann::ordered_json j;
  j["scenario"] = ToString(r.params.scenario);
  j["delay_ms"] = 1e3 * r.params.one_way_delay_s;
  j["scheme"] = ToString(r.params.scheme);
  j["feedback_energy_j"] = r.feedback_energy_j;
  j["feedback_energy_max_j"] = r.max_feedback_energy_j;
  j["observer_min_j"] = r.min_observer_j;
  j["hand_energy_in_j"] = r.hand_energy_in_j;
  j["dissipated_share"] = r.dissipated_share;
  j["force_error_n_rms"] = r.force_error_n_rms;
  j["position_error_mm_rms"] = r.position_error_mm_rms;
  j["drift_mm"] = r.drift_mm;
  j["drift_growth_mm"] = r.drift_growth_mm;
  j["force_hf_share"] = r.force_hf_share;
  j["rest_after_event_s"] = r.rest_after_event_s;
  j["follower_excess_max_j"] = r.max_follower_excess_j;
  j["let_go_detected_s"] = r.let_go_detected_s;
  j["active_fraction"] = r.active_fraction;
  j["taper_active_fraction"] = r.taper_active_fraction;
  j["max_force_n"] = r.max_force_n;
  return j;
}

}  // namespace robossis::teleop
