#include "calibration/tracking_report.h"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "src/core/pose.h"
#include "src/core/units.h"

namespace robossis::calibration {

namespace {

using json = nlohmann::ordered_json;

json StatsJson(const ErrorStats& s, double scale) {
  return json{{"mean", s.mean * scale}, {"median", s.median * scale}, {"rmse", s.rmse * scale},
              {"std", s.std * scale},   {"p95", s.p95 * scale},       {"max", s.max * scale}};
}

json ErrorJson(const ErrorStats& norm, const ErrorStats* axes, double scale) {
  json j = StatsJson(norm, scale);
  j["per_axis"] = json{{"x", StatsJson(axes[0], scale)}, {"y", StatsJson(axes[1], scale)},
                       {"z", StatsJson(axes[2], scale)}};
  return j;
}

json PoseJson(const Eigen::Isometry3d& X) {
  const Vector6d v = MmDegFromPose(X);
  return json{{"position_mm", {v[0], v[1], v[2]}}, {"rpy_deg", {v[3], v[4], v[5]}}};
}

std::string Tum(const std::vector<double>& t, const std::vector<Eigen::Isometry3d>& X) {
  PoseTrajectory traj;
  for (std::size_t i = 0; i < t.size(); ++i) traj.Add(t[i], X[i].translation(), Eigen::Quaterniond(X[i].linear()));
  return FormatTum(traj);
}

}  // namespace

std::string ClockModelName(const ClockFitResult& c) {
  if (!c.drift_considered) return "offset only (drift not estimated)";
  return c.drift_selected ? "offset + drift (BIC)" : "offset only (BIC: no drift)";
}

json ClockJson(const ClockFitResult& c) {
  // The interval of one standard uncertainty alone (ms, same k), shown beside the combined one.
  const double k = c.coverage_factor;
  const auto Around = [k](double x_s, double u_s) { return json{(x_s - k * u_s) * 1e3, (x_s + k * u_s) * 1e3}; };
  json budget = json::array();
  for (const UncertaintySource& u : c.budget) {
    budget.push_back(json{{"source", u.name}, {"type", u.evaluation}, {"standard_uncertainty_ms",
                          u.standard_uncertainty_s * 1e3}, {"note", u.note}});
  }
  return json{{"measurand",
               "t_reference - t_mocap at the take's middle (t_mocap = t_mid_s), through the ring's motion"},
              {"t_mid_s", c.t_mid_s},
              {"offset_ms", c.offset_mid_s * 1e3},
              {"expanded_uncertainty_ms", c.expanded_uncertainty_s * 1e3},
              {"coverage_factor", c.coverage_factor},
              {"interval_ms", {c.offset_ci_s[0] * 1e3, c.offset_ci_s[1] * 1e3}},
              {"sigma_bootstrap_ms", c.offset_sigma_bootstrap_s * 1e3},
              {"sigma_curvature_ms", c.offset_sigma_curvature_s * 1e3},
              {"interval_bootstrap_ms", Around(c.offset_mid_s, c.offset_sigma_bootstrap_s)},
              {"interval_curvature_ms", Around(c.offset_mid_s, c.offset_sigma_curvature_s)},
              {"crb_ms", c.crb_s * 1e3},
              {"crb_position_only_ms", c.crb_position_only_s * 1e3},
              {"budget", budget},
              {"drift_selected", c.drift_selected},
              {"drift_ppm_if_fitted", c.drift * 1e6},
              {"drift_interval_ppm", {c.drift_ci[0] * 1e6, c.drift_ci[1] * 1e6}},
              {"delta_bic", c.delta_bic},
              {"identifiable", c.identifiable},
              {"offset_information_share", c.offset_information_share},
              {"warning", c.warning.empty() ? json(nullptr) : json(c.warning)},
              {"frames", c.frames},
              {"bootstrap_blocks", c.blocks},
              {"block_s", c.block_s},
              {"sigma_position_mm", c.sigma_position_m * 1e3},
              {"sigma_rotation_deg", c.sigma_rotation_rad * kRadToDeg}};
}

std::string ClockReportText(const ClockFitResult& c) {
  char buf[1024];
  std::string out;
  std::snprintf(buf, sizeof buf,
                "clock offset at mid-take (t_mocap = %.3f s): %.4f ms, 95 %% interval [%.4f, %.4f] ms "
                "(U = %.4f ms, k = %g; bootstrap sigma %.4f ms, curvature sigma %.4f ms; bound sigma_tau %.4f ms)\n",
                c.t_mid_s, c.offset_mid_s * 1e3, c.offset_ci_s[0] * 1e3, c.offset_ci_s[1] * 1e3,
                c.expanded_uncertainty_s * 1e3, c.coverage_factor, c.offset_sigma_bootstrap_s * 1e3,
                c.offset_sigma_curvature_s * 1e3, c.crb_s * 1e3);
  out += buf;
  if (!c.drift_considered) {
    std::snprintf(buf, sizeof buf, "clock drift: not estimated (the offset-only model was asked for)\n");
  } else if (c.drift_selected) {
    std::snprintf(buf, sizeof buf, "clock drift: %.2f ppm [%.2f, %.2f] (selected by BIC, dBIC %.1f)\n", c.drift * 1e6,
                  c.drift_ci[0] * 1e6, c.drift_ci[1] * 1e6, c.delta_bic);
  } else {
    std::snprintf(buf, sizeof buf, "clock drift: no drift (BIC, dBIC %.1f); |drift| <= %.2f ppm\n", c.delta_bic,
                  c.drift_bound * 1e6);
  }
  out += buf;
  if (!c.warning.empty()) out += "warning: " + c.warning + "\n";
  return out;
}

json TrackingSummaryJson(const TrackingEvalResult& r) {
  json j;
  j["translation_error_mm"] = ErrorJson(r.translation, r.translation_axis, kMToMm);
  j["rotation_error_deg"] = ErrorJson(r.rotation, r.rotation_axis, kRadToDeg);
  j["time_offset_s"] = r.clock.offset_s;
  const ClockFitResult& c = r.clock_fit;
  j["clock_offset_ms"] = c.offset_mid_s * 1e3;
  j["clock_offset_ci_ms"] = {c.offset_ci_s[0] * 1e3, c.offset_ci_s[1] * 1e3};
  j["clock_offset_crb_ms"] = c.crb_s * 1e3;
  j["clock_drift_ppm"] = c.drift_selected ? json(c.drift * 1e6) : json(nullptr);
  j["clock_drift_bound_ppm"] = c.drift_considered ? json(c.drift_bound * 1e6) : json(nullptr);
  j["clock_model"] = ClockModelName(c);
  j["clock"] = ClockJson(c);
  j["speed_correlation"] = r.speed_correlation;
  j["registration_rms_mm"] = r.registration.rms_position_m * kMToMm;
  j["registration_rms_deg"] = r.registration.rms_rotation_rad * kRadToDeg;
  j["registration"] = json{{"method", r.registration.method},
                           {"pairs", r.registration.pairs},
                           {"max_mm", r.registration.max_position_m * kMToMm},
                           {"max_deg", r.registration.max_rotation_rad * kRadToDeg},
                           {"rotation_spread_deg", r.registration.rotation_spread_rad * kRadToDeg},
                           {"tracker_in_robot_base_X_FT", PoseJson(r.registration.X_FT)},
                           {"marker_body_in_ring_X_MB", PoseJson(r.registration.X_MB)}};
  j["frames_used"] = r.translation.count;
  j["frames_excluded"] = r.excluded.total();
  j["frames_total"] = r.frames_total;
  j["frames_excluded_by_reason"] = json{{"missing", r.excluded.missing},
                                        {"outside_reference", r.excluded.outside_reference},
                                        {"orientation_flip", r.excluded.orientation_flip}};
  json quality{{"pose_source", r.pose_source},
               {"frames_present", r.gaps.frames_present},
               {"gaps", r.gaps.gaps},
               {"longest_gap_frames", r.gaps.longest_gap_frames},
               {"frame_jumps", r.frame_jumps},
               {"complete", r.complete},
               {"frames_in_header", r.frames_in_header >= 0 ? json(r.frames_in_header) : json(nullptr)},
               {"quaternion_sign_flips", r.quaternion_sign_flips},
               {"orientation_flips", r.excluded.orientation_flip}};
  quality["mean_marker_error_mm"] =
      r.mean_marker_error.count > 0 ? StatsJson(r.mean_marker_error, kMToMm) : json(nullptr);
  j["data_quality"] = quality;
  return j;
}

std::string TrackingErrorsCsv(const TrackingEvalResult& r) {
  std::string out =
      "t_s,ref_x_mm,ref_y_mm,ref_z_mm,ref_roll_deg,ref_pitch_deg,ref_yaw_deg,"
      "trk_x_mm,trk_y_mm,trk_z_mm,trk_roll_deg,trk_pitch_deg,trk_yaw_deg,"
      "ex_mm,ey_mm,ez_mm,e_mm,rx_deg,ry_deg,rz_deg,r_deg\n";
  out.reserve(out.size() + r.t_reference_s.size() * 200);
  char buf[512];
  for (std::size_t i = 0; i < r.t_reference_s.size(); ++i) {
    const Vector6d a = MmDegFromPose(r.X_FM_reference[i]);
    const Vector6d b = MmDegFromPose(r.X_FM_tracked[i]);
    const Eigen::Vector3d e = r.translation_error_m[i] * kMToMm;
    const Eigen::Vector3d w = r.rotation_error_rad[i] * kRadToDeg;
    std::snprintf(buf, sizeof buf,
                  "%.6f,%.4f,%.4f,%.4f,%.5f,%.5f,%.5f,%.4f,%.4f,%.4f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.6f,%.6f,"
                  "%.6f,%.6f\n",
                  r.t_reference_s[i], a[0], a[1], a[2], a[3], a[4], a[5], b[0], b[1], b[2], b[3], b[4], b[5], e.x(),
                  e.y(), e.z(), e.norm(), w.x(), w.y(), w.z(), w.norm());
    out += buf;
  }
  return out;
}

std::string ReferenceTum(const TrackingEvalResult& r) { return Tum(r.t_reference_s, r.X_FM_reference); }
std::string TrackedTum(const TrackingEvalResult& r) { return Tum(r.t_reference_s, r.X_FM_tracked); }

json TakeSummaryJson(const MotiveTakeSummary& s) {
  json j;
  j["format_version"] = s.header.format_version;
  j["export_rate_hz"] = s.header.export_rate_hz;
  j["frames"] = s.frames;
  j["length_units"] = s.header.length_units;
  j["rotation_type"] = std::string(RotationTypeName(s.header.rotation_type));
  json bodies = json::array();
  for (const MotiveTakeSummary::RigidBody& rb : s.rigid_bodies) {
    bodies.push_back(json{{"name", rb.name},
                          {"frames_present", rb.gaps.frames_present},
                          {"gaps", rb.gaps.gaps},
                          {"longest_gap_frames", rb.gaps.longest_gap_frames},
                          {"rigid_body_markers", rb.rigid_body_markers},
                          {"mean_marker_error_mm", std::isnan(rb.mean_marker_error_mean_m)
                                                       ? json(nullptr)
                                                       : json(rb.mean_marker_error_mean_m * kMToMm)}});
  }
  j["rigid_bodies"] = bodies;
  j["markers"] = s.markers;
  j["rigid_body_markers"] = s.rigid_body_markers;
  j["take_name"] = s.header.take_name;
  j["first_frame"] = s.first_frame;
  j["last_frame"] = s.last_frame;
  j["frame_jumps"] = s.frame_jumps;
  j["complete"] = s.complete;
  j["frames_in_header"] = s.frames_in_header >= 0 ? json(s.frames_in_header) : json(nullptr);
  j["duration_s"] = s.frames > 0 ? static_cast<double>(s.last_frame - s.first_frame) / s.header.export_rate_hz : 0.0;
  return j;
}

}  // namespace robossis::calibration
