#pragma once
// The files of a tracking evaluation: summary.json (its keys are a stable interface), errors.csv (one row per used
// frame), and TUM trajectories of the reference and the registered tracked ring, so other tools (e.g. evo) can
// check them.

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "calibration/mocap_track.h"
#include "calibration/tracking_eval.h"

namespace robossis::calibration {

// translation_error_mm / rotation_error_deg: {mean, median, rmse, std, p95, max, per_axis: {x, y, z}} where each
// per-axis entry holds the same statistics of |component|; plus time_offset_s, the clock (clock_offset_ms at
// mid-take, clock_offset_ci_ms, clock_offset_crb_ms, clock_drift_ppm or null, clock_drift_bound_ppm, clock_model,
// clock: {...}), registration_rms_mm, frames_used, frames_excluded and the data-quality section.
nlohmann::ordered_json TrackingSummaryJson(const TrackingEvalResult& result);

// The clock's measurand, interval (k = 2), bound, budget, drift choice and identifiability: summary.json's "clock",
// and the report's lines.
nlohmann::ordered_json ClockJson(const ClockFitResult& clock);
std::string ClockModelName(const ClockFitResult& clock);
std::string ClockReportText(const ClockFitResult& clock);

// t_s (reference clock), reference and tracked pose (mm, deg RPY), errors per axis and norms (mm, deg).
std::string TrackingErrorsCsv(const TrackingEvalResult& result);

// Reference and tracked ring poses at the used frames, TUM format, reference clock, robot base frame.
std::string ReferenceTum(const TrackingEvalResult& result);
std::string TrackedTum(const TrackingEvalResult& result);

// `robossis mocap inspect --json`.
nlohmann::ordered_json TakeSummaryJson(const MotiveTakeSummary& summary);

}  // namespace robossis::calibration
