#pragma once
// A reference signed distance to the TRUE boundary of a slice, computed from the feasibility test alone
// (independent of any mesh): dense ray casting from the query point (Fibonacci-sphere directions; each ray marched
// at a fixed step and its first feasibility change bisected), then local minimisation of the boundary distance over
// the ray direction (a pattern search on the sphere of directions). Slow (milliseconds): for validation only.

#include <Eigen/Core>

#include "geometry/boundary_mesher.h"

namespace robossis::geometry {

struct ReferenceDistanceOptions {
  int directions = 1000;           // Fibonacci-sphere rays
  double max_distance = 0.03;      // search radius (slice units); beyond it the distance is reported as not found
  double march_step = 2.5e-4;      // ray marching step (slice units); features thinner than it can be missed
  double tolerance = 1e-7;         // bisection bracket and final direction step
};

struct ReferenceDistanceResult {
  bool found = false;              // a boundary point lies within max_distance
  bool inside = false;             // feasibility of q
  double signed_distance = 0;      // > 0 inside, < 0 outside (slice units)
  Eigen::Vector3d nearest = Eigen::Vector3d::Zero();
};

ReferenceDistanceResult ComputeReferenceSignedDistance(const FeasibilityFn& feasible, const Eigen::Vector3d& q,
                                                       const ReferenceDistanceOptions& options = {});

}  // namespace robossis::geometry
