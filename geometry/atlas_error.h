#pragma once
// The error the atlas grid spacing introduces: at random off-grid poses near the boundary, the atlas' signed
// distance (nearest-node slice) against the reference signed distance to the TRUE slice of the actual pose
// (reference_distance.h; independent of every mesh). The same measure at on-grid poses isolates the mesh error.

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/boundary_atlas.h"
#include "geometry/live_boundary.h"
#include "geometry/reference_distance.h"

namespace robossis::geometry {

// The most error samples one measurement takes (per family and case). Each sample runs the reference search (400
// directions of IK marching, ~1 ms), so 100 000 samples are already minutes; more is a typo or a hostile input.
inline constexpr int kMaxErrorSamples = 100000;
// The count as an int; throws std::invalid_argument "OPTION: expected an integer from 0 to 100000 samples, got N"
// unless `samples` is a whole number in [0, kMaxErrorSamples] (a double, so 1e12 or -5 at the command line reaches
// this check instead of overflowing).
int RequireErrorSamples(double samples, const std::string& option);

struct ErrorStats {
  int samples = 0;
  int not_found = 0;  // reference found no boundary within its search radius (counted, excluded from the stats)
  int sign_disagreements = 0;
  double mean = 0, p50 = 0, p95 = 0, max = 0;  // |atlas - reference|, slice units (m or rad)
};
ErrorStats SummariseErrors(std::vector<double> errors, int not_found, int sign_disagreements);

struct AtlasErrorReport {
  ErrorStats dexterous_off_grid, dexterous_on_grid;    // m
  ErrorStats rotational_off_grid, rotational_on_grid;  // rad
};

struct AtlasErrorOptions {
  int samples = 40;                    // per family and per on/off-grid case
  double position_offset_m = 0.003;    // query points: a random mesh vertex + uniform offset in +/- this
  double angle_offset_rad = 0.0175;    // (1 deg)
  std::uint32_t seed = 42;
};

AtlasErrorReport MeasureAtlasError(const robot::RsrModel& rsr, const robot::Sigma7Model& hc,
                                   const BoundaryAtlas& atlas, const AtlasErrorOptions& options = {});

// The error of the LIVE slices (live_boundary.h): a slice made at a pose that is `staleness` away from the actual
// pose (the motion during one refresh, plus the refresh tolerance), against the reference at the actual pose. Poses
// are drawn uniformly over the atlas spec's grid ranges; the stale pose is offset in a random direction.
struct LiveErrorOptions {
  int samples = 20;                       // per family
  double orientation_staleness_rad = 0;   // dexterous slices: |rpy_slice - rpy_actual|
  double position_staleness_m = 0;        // rotational slices: |p_slice - p_actual|
  double position_offset_m = 0.003;       // query points: a random mesh vertex + uniform offset in +/- this
  double angle_offset_rad = 0.0175;
  std::uint32_t seed = 42;
};
struct LiveErrorReport {
  ErrorStats dexterous;   // m
  ErrorStats rotational;  // rad
  double dexterous_seconds_max = 0, rotational_seconds_max = 0;  // slowest slice generation seen (wall clock)
};
LiveErrorReport MeasureLiveError(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const AtlasSpec& range,
                                 const LiveBoundaryOptions& live, const LiveErrorOptions& options);

// The live-slice error at the clinical speeds (kClinical*): the refresh time measured at the home pose, the
// worst-case staleness it implies (WorstCaseStaleness), and the error of slices that stale.
struct ClinicalLiveError {
  RefreshTiming timing;
  LiveStaleness staleness;
  LiveErrorReport error;
};
ClinicalLiveError MeasureClinicalLiveError(const robot::RsrModel& rsr, const robot::Sigma7Model& hc,
                                           const AtlasSpec& range, const LiveBoundaryOptions& live, int samples,
                                           std::uint32_t seed = 42);

// Mesh-versus-true-boundary error of one slice: signed distance from the mesh (FCL query) against the reference at
// random points near the boundary.
ErrorStats MeasureSliceError(const robot::RsrModel& rsr, const robot::Sigma7Model& hc, const WorkspaceSlice& slice,
                             int samples, std::uint32_t seed);

}  // namespace robossis::geometry
