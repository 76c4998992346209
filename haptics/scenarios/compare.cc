#include "haptics/scenarios/compare.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "haptics/device/device_sim.h"
#include "haptics/rendering/boundary_probe.h"
#include "haptics/rendering/mesh_proxy_renderer.h"
#include "haptics/rendering/renderer_factory.h"
#include "robot/rsr_kinematics.h"
#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::haptics {

namespace {

constexpr double kDirectionForceThresholdN = 1.0;     // [assumed] below this the direction is noise
constexpr double kDirectionTorqueThresholdNm = 0.02;  // [assumed]
constexpr double kOnsetForceN = 2.0;                  // [assumed] a force the hand clearly feels
constexpr double kOnsetTorqueNm = 0.05;               // [assumed]

double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const double pos = q * (values.size() - 1);
  const std::size_t i = static_cast<std::size_t>(pos);
  const double frac = pos - i;
  return i + 1 < values.size() ? values[i] * (1 - frac) + values[i + 1] * frac : values[i];
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double na = a.norm(), nb = b.norm();
  if (na == 0 || nb == 0) return -1;
  return RadToDeg(std::acos(std::clamp(a.dot(b) / (na * nb), -1.0, 1.0)));
}

HandTarget TargetAt(const Episode& e, const HcToRsrMap& map, double t) {
  const double h = 1e-4;
  HandTarget target;
  target.X_OH = map.ToHc(e.target_FM(t));
  const Eigen::Isometry3d before = map.ToHc(e.target_FM(std::max(0.0, t - h)));
  const Eigen::Isometry3d after = map.ToHc(e.target_FM(t + h));
  const double span = (t + h) - std::max(0.0, t - h);
  target.v_O = (after.translation() - before.translation()) / span;
  target.w_O = RotationVector(after.linear() * before.linear().transpose()) / span;
  return target;
}

// Beyond the true boundary by at most the shallow-contact thresholds, in the unit the penetration is counted in.
bool IsShallow(const TickRecord& r) {
  switch (r.penetration_counted) {
    case PenetrationCount::kTranslation: return r.penetration_mm <= kShallowPenetrationMm;
    case PenetrationCount::kRotation: return r.penetration_deg <= kShallowPenetrationDeg;
    default: return false;
  }
}

}  // namespace

const char* ToString(PenetrationCount c) {
  switch (c) {
    case PenetrationCount::kFree: return "free";
    case PenetrationCount::kTranslation: return "mm";
    case PenetrationCount::kRotation: return "deg";
    case PenetrationCount::kBeyondReference: return "beyond_reference";
  }
  return "?";
}

MethodRun RunMethod(const Scenario& scenario, const std::string& method, const HapticsConfig& config,
                    const robot::RsrModel& rsr, const robot::Sigma7Model& sigma7, const CompareSettings& settings,
                    std::shared_ptr<const geometry::BoundaryAtlas> atlas,
                    const std::function<void(double)>& progress) {
  MethodRun run;
  run.method = method;
  const double dt = 1.0 / settings.rate_hz;
  HcToRsrMap map;
  map.frame = settings.frame;
  map.X_OH_anchor = Eigen::Isometry3d::Identity();
  map.X_OH_anchor.translation() = sigma7.p_center_O();
  std::unique_ptr<HapticRenderer> renderer = MakeRenderer(method, config, rsr, map, settings.rate_hz, std::move(atlas));
  SimulatedSigma7 device(sigma7, config.device, config.hand);

  std::vector<double> tick_us, direction_errors, force_errors, torque_errors;
  long free_ticks = 0, shallow_ticks = 0, deep_ticks = 0;
  const double total_s = std::max(1e-9, scenario.duration_s());
  double elapsed_s = 0, energy_cumulative = 0;
  double energy_generated = 0;
  MethodMetrics& m = run.metrics;
  for (std::size_t ei = 0; ei < scenario.episodes.size(); ++ei) {
    const Episode& e = scenario.episodes[ei];
    map.X_FM_anchor = e.X_FM_anchor;
    renderer->SetMap(map);
    device.set_hand(e.hand);
    device.Reset(map.ToHc(e.X_FM_start));
    renderer->Reset(device.pose());
    Eigen::Isometry3d X_prev = device.pose();
    Eigen::Vector3d f_prev = Eigen::Vector3d::Zero(), tau_prev = Eigen::Vector3d::Zero();
    bool in_contact = false;
    bool onset_seen = false;
    double contact_energy = 0, contact_energy_max = 0;
    const long ticks = static_cast<long>(std::floor(e.duration_s * settings.rate_hz));
    for (long k = 0; k < ticks; ++k) {
      const double t = k * dt;
      // The device reports its pose and a backward-difference velocity, as a real sigma.7 driver does.
      HapticInput input;
      input.X_OH = device.pose();
      if (k > 0) {
        input.v_O = (device.pose().translation() - X_prev.translation()) / dt;
        input.w_O = RotationVector(device.pose().linear() * X_prev.linear().transpose()) / dt;
      }
      X_prev = device.pose();
      renderer->StepSimulatedBackground(elapsed_s + t);  // between ticks, outside the timed tick
      HapticOutput output;
      const auto t0 = std::chrono::steady_clock::now();
      renderer->Tick(input, output);
      const auto t1 = std::chrono::steady_clock::now();
      const double us = std::chrono::duration<double, std::micro>(t1 - t0).count();
      tick_us.push_back(us);

      // Metrics against the true boundary, at the RSR pose the HC commands.
      const Eigen::Isometry3d X_FM = map.ToRsr(input.X_OH);
      TickRecord rec;
      rec.t_s = elapsed_s + t;
      rec.episode = static_cast<int>(ei);
      rec.target_mm_deg = MmDegFromPose(e.target_FM(t));
      rec.pose_mm_deg = MmDegFromPose(X_FM);
      rec.force_n = output.f_O;
      rec.torque_nm = output.tau_O;
      rec.status = static_cast<int>(output.status);
      rec.saturated = output.saturated;
      rec.tick_us = us;
      const double t_pen = TranslationalPenetration(rsr, X_FM, kPenetrationRangeM);
      const double r_pen = RotationalPenetration(rsr, X_FM, kPenetrationRangeRad);
      rec.penetration_mm = MToMm(t_pen);
      rec.penetration_deg = RadToDeg(r_pen);
      rec.penetration_mm_beyond_reference = t_pen >= kPenetrationRangeM;
      rec.penetration_deg_beyond_reference = r_pen >= kPenetrationRangeRad;
      // The workspace is coupled: a pose beyond a translational edge can also be escaped by turning, and one beyond
      // a rotational edge by moving (or not at all: beyond the twist limit no position is feasible). Each tick's
      // penetration is therefore attributed to its cheaper escape, with 15 mm ≡ 5° (the paper's cloud radii,
      // [assumed] as the exchange rate): translation counts toward max_penetration_mm, rotation toward
      // max_penetration_deg. An escape beyond the reference's range is not known, so the other one counts; with
      // neither known the tick counts as beyond the reference, in no maximum. The traces keep both raw values.
      if (t_pen > 0 || r_pen > 0) {
        const double t_cost =
            rec.penetration_mm_beyond_reference ? HUGE_VAL : t_pen / config.cloud.translation_radius_m;
        const double r_cost =
            rec.penetration_deg_beyond_reference ? HUGE_VAL : r_pen / config.cloud.rotation_radius_rad;
        if (t_cost == HUGE_VAL && r_cost == HUGE_VAL) {
          rec.penetration_counted = PenetrationCount::kBeyondReference;
          ++m.penetration_beyond_reference_ticks;
        } else if (t_cost <= r_cost) {
          rec.penetration_counted = PenetrationCount::kTranslation;
          m.max_penetration_mm = std::max(m.max_penetration_mm, rec.penetration_mm);
        } else {
          rec.penetration_counted = PenetrationCount::kRotation;
          m.max_penetration_deg = std::max(m.max_penetration_deg, rec.penetration_deg);
        }
      }
      m.translation_beyond_reference_ticks += rec.penetration_mm_beyond_reference;
      m.rotation_beyond_reference_ticks += rec.penetration_deg_beyond_reference;
      ++m.ticks;
      ++(IsShallow(rec) ? shallow_ticks : rec.penetration_counted == PenetrationCount::kFree ? free_ticks : deep_ticks);
      if (rec.penetration_counted == PenetrationCount::kFree) {
        m.max_free_space_force_n = std::max(m.max_free_space_force_n, output.f_O.norm());
        m.max_free_space_torque_nm = std::max(m.max_free_space_torque_nm, output.tau_O.norm());
      }
      const bool contact = output.status != HapticStatus::kFree;
      if (contact && output.status != HapticStatus::kFault) {
        // The direction of the WALL: the rendered wrench minus the viscous term −c·v that every method applies
        // everywhere, in free space too (eq. 18–19, Algorithm 1 lines 19–20; the paper's c_f and c_τ, which the
        // device-safe preset keeps). Otherwise a hand withdrawing fast while some cloud still touches a limit is
        // scored by its damper, which then points toward the wall (the strike: 405 of the point cloud's 2133 force
        // samples, all pure damper, at 156°; haptics/README.md).
        // mesh-proxy fades its damper in with the depth (MeshProxyParams::damping_fade_m): remove what it applied.
        double w_f = 1, w_tau = 1;
        if (const auto* mesh_proxy = dynamic_cast<const MeshProxyRenderer*>(renderer.get())) {
          w_f = mesh_proxy->last_force_damping_weight();
          w_tau = mesh_proxy->last_torque_damping_weight();
        }
        // In F, where the walls and their normals are: the displayed wrench rotated back, the damper on the
        // hand's velocity mapped as the renderer maps it.
        const Eigen::Vector3d f_wall = map.frame.WrenchToRsr(output.f_O) +
                                       w_f * config.wall.c_f_ns_per_m * map.frame.LinearToRsr(input.v_O);
        const Eigen::Vector3d tau_wall = map.frame.WrenchToRsr(output.tau_O) +
                                         w_tau * config.wall.c_tau_nms_per_rad * map.frame.AngularToRsr(input.w_O);
        // Scored only where the reference's normal is defined: within its range and off its edges.
        if (f_wall.norm() > kDirectionForceThresholdN) {
          if (rec.penetration_mm_beyond_reference ||
              !IsNormalUniqueTranslation(rsr, X_FM, kNormalEdgeMarginM, DegToRad(kNormalCreaseDeg))) {
            rec.force_direction_left_out = true;
          } else {
            rec.force_direction_error_deg = AngleDeg(f_wall, InwardNormalTranslation(rsr, X_FM));
          }
          if (rec.force_direction_error_deg >= 0) {
            force_errors.push_back(rec.force_direction_error_deg);
            direction_errors.push_back(rec.force_direction_error_deg);
          }
        }
        if (tau_wall.norm() > kDirectionTorqueThresholdNm) {
          if (rec.penetration_deg_beyond_reference ||
              !IsNormalUniqueRotation(rsr, X_FM, DegToRad(kNormalEdgeMarginDeg), DegToRad(kNormalCreaseDeg))) {
            rec.torque_direction_left_out = true;
          } else {
            rec.torque_direction_error_deg = AngleDeg(tau_wall, InwardNormalRotation(rsr, X_FM));
          }
          if (rec.torque_direction_error_deg >= 0) {
            torque_errors.push_back(rec.torque_direction_error_deg);
            direction_errors.push_back(rec.torque_direction_error_deg);
          }
        }
        m.direction_error_scored_ticks += rec.force_direction_error_deg >= 0 || rec.torque_direction_error_deg >= 0;
        m.direction_error_left_out_ticks += rec.force_direction_left_out || rec.torque_direction_left_out;
      }
      if (k > 0) {
        m.max_force_step_n = std::max(m.max_force_step_n, (output.f_O - f_prev).norm());
        m.max_torque_step_nm = std::max(m.max_torque_step_nm, (output.tau_O - tau_prev).norm());
      }
      f_prev = output.f_O;
      tau_prev = output.tau_O;
      if (output.saturated) m.saturation_time_s += dt;
      if (output.status == HapticStatus::kDeepPenetration) ++m.deep_penetration_ticks;
      if (output.status == HapticStatus::kFault) ++m.fault_ticks;
      // What only the trace's rows and the wall onset use is computed for those ticks alone (a bisection and an IK
      // per tick otherwise; the trace keeps every trace_decimation-th tick).
      const bool kept = settings.keep_trace && k % settings.trace_decimation == 0;
      if (e.is_push) {
        rec.is_push = true;
        rec.push_rotational = e.rotational;
        const bool strong = e.rotational ? output.tau_O.norm() >= kOnsetTorqueNm : output.f_O.norm() >= kOnsetForceN;
        // The onset only while pushing in (the first crossing of the threshold), not on the way back.
        const bool onset = strong && !onset_seen;
        if (onset || kept) {
          const double s = SignedDistanceAlongPush(rsr, e, X_FM);
          rec.push_signed = e.rotational ? RadToDeg(s) : MToMm(s);
        }
        if (onset) {
          onset_seen = true;
          double& wall_onset = e.rotational ? m.wall_onset_deg : m.wall_onset_mm;
          wall_onset = std::min(wall_onset, rec.push_signed);
        }
      }
      if (kept) {
        const robot::RsrIkResult ik = robot::CalcInverseKinematics(rsr, X_FM);
        rec.stroke_mm = ik.joints.d_m * kMToMm;
        rec.cone_deg = ik.joints.cone_rad * kRadToDeg;
      }

      // Physics over the tick with the displayed wrench held.
      const HandTarget target = TargetAt(e, map, t);
      const DeviceStepResult step = device.Step(dt, output.f_O, output.tau_O, target);
      energy_cumulative += step.energy_into_hand_j;
      rec.energy_into_hand_j = energy_cumulative;
      // Energy generated per contact episode (passivity): the running maximum of the work done on the hand.
      if (contact) {
        if (!in_contact) contact_energy = contact_energy_max = 0;
        contact_energy += step.energy_into_hand_j;
        contact_energy_max = std::max(contact_energy_max, contact_energy);
      } else if (in_contact) {
        energy_generated += contact_energy_max;
      }
      in_contact = contact;
      if (kept) run.trace.push_back(rec);
      if (progress && k % 2000 == 0) progress((elapsed_s + t) / total_s);
    }
    if (in_contact) energy_generated += contact_energy_max;
    elapsed_s += ticks * dt;
  }
  m.energy_generated_j = energy_generated;
  if (m.ticks > 0) {
    m.free_share = static_cast<double>(free_ticks) / m.ticks;
    m.shallow_share = static_cast<double>(shallow_ticks) / m.ticks;
    m.deep_share = static_cast<double>(deep_ticks) / m.ticks;
  }
  m.direction_error_deg_p95 = Percentile(direction_errors, 0.95);
  m.force_direction_error_deg_p95 = Percentile(force_errors, 0.95);
  m.torque_direction_error_deg_p95 = Percentile(torque_errors, 0.95);
  m.tick_us_p50 = Percentile(tick_us, 0.50);
  m.tick_us_p99 = Percentile(tick_us, 0.99);
  m.tick_us_max = tick_us.empty() ? 0 : *std::max_element(tick_us.begin(), tick_us.end());
  if (progress) progress(1.0);
  return run;
}

std::vector<MethodRun> RunMethods(const Scenario& scenario, const std::vector<std::string>& methods,
                                  const HapticsConfig& config, const robot::RsrModel& rsr,
                                  const robot::Sigma7Model& sigma7, const CompareSettings& settings,
                                  std::shared_ptr<const geometry::BoundaryAtlas> atlas, int jobs,
                                  const MethodRunEvents& events) {
  if (jobs < 1) throw std::invalid_argument("jobs: expected at least 1 run at a time, got " + std::to_string(jobs));
  std::vector<MethodRun> runs(methods.size());
  std::mutex mutex;  // serialises the events and guards `error`
  std::exception_ptr error;
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i = next.fetch_add(1); i < methods.size(); i = next.fetch_add(1)) {
      try {
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (error) return;
          if (events.started) events.started(i);
        }
        const auto t0 = std::chrono::steady_clock::now();
        MethodRun run = RunMethod(scenario, methods[i], config, rsr, sigma7, settings, atlas);
        const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::lock_guard<std::mutex> lock(mutex);
        if (events.done) events.done(i, run, wall_s);
        runs[i] = std::move(run);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        return;
      }
    }
  };
  const std::size_t threads = std::min(static_cast<std::size_t>(jobs), methods.size());
  if (threads <= 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    for (std::size_t t = 0; t < threads; ++t) pool.emplace_back(work);
    for (std::thread& t : pool) t.join();
  }
  if (error) std::rethrow_exception(error);
  return runs;
}

std::string TraceCsv(const MethodRun& run) {
  std::ostringstream out;
  out << "t_s,episode,target_x_mm,target_y_mm,target_z_mm,target_roll_deg,target_pitch_deg,target_yaw_deg,"
         "x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,fx_n,fy_n,fz_n,tx_nm,ty_nm,tz_nm,status,saturated,tick_us,"
         "penetration_mm,penetration_deg,force_dir_err_deg,torque_dir_err_deg,is_push,push_rotational,push_signed,"
         "d1_mm,d2_mm,d3_mm,cone1_deg,cone2_deg,cone3_deg,energy_into_hand_j,penetration_mm_beyond_reference,"
         "penetration_deg_beyond_reference,penetration_counted_as,force_dir_left_out,torque_dir_left_out\n";
  char buf[64];
  auto num = [&](double v) {
    std::snprintf(buf, sizeof buf, "%.6g", v);
    out << buf;
  };
  for (const TickRecord& r : run.trace) {
    num(r.t_s);
    out << ',' << r.episode;
    for (int i = 0; i < 6; ++i) out << ',', num(r.target_mm_deg[i]);
    for (int i = 0; i < 6; ++i) out << ',', num(r.pose_mm_deg[i]);
    for (int i = 0; i < 3; ++i) out << ',', num(r.force_n[i]);
    for (int i = 0; i < 3; ++i) out << ',', num(r.torque_nm[i]);
    out << ',' << ToString(static_cast<HapticStatus>(r.status)) << ',' << (r.saturated ? 1 : 0) << ',';
    num(r.tick_us);
    out << ',', num(r.penetration_mm);
    out << ',', num(r.penetration_deg);
    out << ',', num(r.force_direction_error_deg);
    out << ',', num(r.torque_direction_error_deg);
    out << ',' << (r.is_push ? 1 : 0) << ',' << (r.push_rotational ? 1 : 0) << ',';
    num(r.push_signed);
    for (int i = 0; i < 3; ++i) out << ',', num(r.stroke_mm[i]);
    for (int i = 0; i < 3; ++i) out << ',', num(r.cone_deg[i]);
    out << ',', num(r.energy_into_hand_j);
    out << ',' << r.penetration_mm_beyond_reference << ',' << r.penetration_deg_beyond_reference << ','
        << ToString(r.penetration_counted) << ',' << r.force_direction_left_out << ',' << r.torque_direction_left_out;
    out << '\n';
  }
  return out.str();
}

nlohmann::ordered_json SummaryJson(const Scenario& scenario, const CompareSettings& settings,
                                   const std::vector<MethodRun>& runs) {
  nlohmann::ordered_json j;
  j["scenario"] = scenario.name;
  j["rate_hz"] = settings.rate_hz;
  j["duration_s"] = scenario.duration_s();
  // Where the reference ends and what the direction error and the contact shares take as defined.
  nlohmann::ordered_json ref;
  ref["translation_range_mm"] = MToMm(kPenetrationRangeM);
  ref["rotation_range_deg"] = RadToDeg(kPenetrationRangeRad);
  ref["normal_edge_margin_mm"] = MToMm(kNormalEdgeMarginM);
  ref["normal_edge_margin_deg"] = kNormalEdgeMarginDeg;
  ref["normal_crease_deg"] = kNormalCreaseDeg;
  ref["shallow_penetration_mm"] = kShallowPenetrationMm;
  ref["shallow_penetration_deg"] = kShallowPenetrationDeg;
  j["reference"] = ref;
  nlohmann::ordered_json methods = nlohmann::ordered_json::object();
  for (const MethodRun& r : runs) {
    const MethodMetrics& m = r.metrics;
    nlohmann::ordered_json x;
    x["max_penetration_mm"] = m.max_penetration_mm;
    x["max_penetration_deg"] = m.max_penetration_deg;
    x["direction_error_deg_p95"] = m.direction_error_deg_p95;
    x["max_force_step_n"] = m.max_force_step_n;
    x["energy_generated_j"] = m.energy_generated_j;
    x["tick_us_p50"] = m.tick_us_p50;
    x["tick_us_p99"] = m.tick_us_p99;
    x["tick_us_max"] = m.tick_us_max;
    // Details beyond the headline keys:
    x["force_direction_error_deg_p95"] = m.force_direction_error_deg_p95;
    x["torque_direction_error_deg_p95"] = m.torque_direction_error_deg_p95;
    x["max_torque_step_nm"] = m.max_torque_step_nm;
    x["saturation_time_s"] = m.saturation_time_s;
    x["wall_onset_mm"] = m.wall_onset_mm;
    x["wall_onset_deg"] = m.wall_onset_deg;
    x["max_free_space_force_n"] = m.max_free_space_force_n;
    x["max_free_space_torque_nm"] = m.max_free_space_torque_nm;
    x["deep_penetration_ticks"] = m.deep_penetration_ticks;
    x["fault_ticks"] = m.fault_ticks;
    x["ticks"] = m.ticks;
    x["penetration_beyond_reference_ticks"] = m.penetration_beyond_reference_ticks;
    x["translation_beyond_reference_ticks"] = m.translation_beyond_reference_ticks;
    x["rotation_beyond_reference_ticks"] = m.rotation_beyond_reference_ticks;
    x["direction_error_scored_ticks"] = m.direction_error_scored_ticks;
    x["direction_error_left_out_ticks"] = m.direction_error_left_out_ticks;
    x["free_share"] = m.free_share;
    x["shallow_share"] = m.shallow_share;
    x["deep_share"] = m.deep_share;
    methods[r.method] = x;
  }
  j["methods"] = methods;
  return j;
}

std::string MarkdownTable(const std::vector<MethodRun>& runs) {
  struct Column {
    const char* header;
    double MethodMetrics::*field;
    int decimals;
    bool higher_is_better = false;
  };
  const Column columns[] = {
      {"max penetration (mm)", &MethodMetrics::max_penetration_mm, 2},
      {"max penetration (deg)", &MethodMetrics::max_penetration_deg, 2},
      {"direction error p95 (deg)", &MethodMetrics::direction_error_deg_p95, 1},
      {"max force step (N)", &MethodMetrics::max_force_step_n, 3},
      {"max torque step (N·m)", &MethodMetrics::max_torque_step_nm, 4},
      {"time saturated (s)", &MethodMetrics::saturation_time_s, 2},
      {"wall onset (mm)", &MethodMetrics::wall_onset_mm, 1, true},
      {"wall onset (deg)", &MethodMetrics::wall_onset_deg, 2, true},
      {"energy generated (J)", &MethodMetrics::energy_generated_j, 5},
      {"tick p50 (µs)", &MethodMetrics::tick_us_p50, 1},
      {"tick p99 (µs)", &MethodMetrics::tick_us_p99, 1},
      {"tick max (µs)", &MethodMetrics::tick_us_max, 1},
  };
  std::ostringstream out;
  out << "| method |";
  for (const Column& c : columns) out << ' ' << c.header << " |";
  out << "\n|---|";
  for (std::size_t i = 0; i < std::size(columns); ++i) out << "---|";
  out << '\n';
  char buf[64];
  std::vector<std::string> winners;
  for (const Column& c : columns) {
    double best = c.higher_is_better ? -1e300 : 1e300;
    for (const MethodRun& r : runs) {
      best = c.higher_is_better ? std::max(best, r.metrics.*(c.field)) : std::min(best, r.metrics.*(c.field));
    }
    std::string names;
    for (const MethodRun& r : runs) {
      std::snprintf(buf, sizeof buf, "%.*f", c.decimals, r.metrics.*(c.field));
      char best_buf[64];
      std::snprintf(best_buf, sizeof best_buf, "%.*f", c.decimals, best);
      if (std::string(buf) == best_buf) names += (names.empty() ? "" : ", ") + r.method;
    }
    winners.push_back(names);
  }
  for (const MethodRun& r : runs) {
    out << "| " << r.method << " |";
    for (std::size_t i = 0; i < std::size(columns); ++i) {
      std::snprintf(buf, sizeof buf, "%.*f", columns[i].decimals, r.metrics.*(columns[i].field));
      const bool is_best = winners[i].find(r.method) != std::string::npos &&
                           (", " + winners[i] + ",").find(", " + r.method + ",") != std::string::npos;
      out << ' ' << (is_best ? "**" : "") << buf << (is_best ? "**" : "") << " |";
    }
    out << '\n';
  }
  out << "| *best* |";
  for (const std::string& w : winners) out << ' ' << w << " |";
  out << "\n\n";
  // Where the reference ends, unranked: these say how much of each row above was measured.
  out << "| method | beyond reference (ticks) | direction error scored / left out (ticks) | "
         "free / shallow / deep (%) |\n|---|---|---|---|\n";
  for (const MethodRun& r : runs) {
    const MethodMetrics& m = r.metrics;
    std::snprintf(buf, sizeof buf, "%.1f / %.1f / %.1f", 100 * m.free_share, 100 * m.shallow_share,
                  100 * m.deep_share);
    out << "| " << r.method << " | " << m.penetration_beyond_reference_ticks << " of " << m.ticks << " | "
        << m.direction_error_scored_ticks << " / " << m.direction_error_left_out_ticks << " | " << buf << " |\n";
  }
  return out.str();
}

std::string MarkdownReferenceNotes() {
  char buf[1024];
  std::snprintf(
      buf, sizeof buf,
      "Reference: the true boundary from the RSR IK. Its penetration search looks %.0f mm in translation and "
      "%.0f° in rotation (every orientation); a tick with no escape found within that range counts as *beyond "
      "reference* and in no maximum (its trace row flags it). Direction errors are scored only where the "
      "reference's normal is defined: the penetration in that space within the range, and off the region's edges "
      "(no second joint limit within %.1f mm / %.1f° of the tightest one with a normal more than %.0f° away from "
      "its normal); the rest are *left out*. Free: the commanded pose inside the true region; shallow: beyond it "
      "by at most %.0f mm / %.2f° (in the unit its penetration counts in, 15 mm ≡ 5°); deep: further, or beyond "
      "the reference.\n",
      MToMm(kPenetrationRangeM), RadToDeg(kPenetrationRangeRad), MToMm(kNormalEdgeMarginM), kNormalEdgeMarginDeg,
      kNormalCreaseDeg, kShallowPenetrationMm, kShallowPenetrationDeg);
  return buf;
}

}  // namespace robossis::haptics
