#pragma once
// The TRUE workspace boundary, probed with the RSR inverse kinematics: bisection on IsPoseFeasible and the gradient
// of the tightest joint-limit margin. Used by the proxy method (to keep its god-object on the boundary) and by the
// comparison metrics (penetration and true normal), independently of every rendering method.
//
// Orientation perturbations are world-frame rotation vectors: R(e) = exp(e) · R, so a gradient with respect to e is
// directly a torque direction in F. Allocation-free and noexcept throughout.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "robot/rsr_kinematics.h"

namespace robossis::haptics {

struct LimitMargin {
  int index = 0;       // into RsrIkResult::checks (arm-major: stroke, rotary, spherical cone)
  double margin = 0;   // m for strokes, rad for angles; >= 0 inside
};

LimitMargin TightestLimit(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM) noexcept;
double LimitMarginAt(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, int index) noexcept;

// Central-difference gradients of one limit's margin: with respect to the position (per m) and to a world-frame
// rotation vector (per rad). The margin grows inwards, so the normalised gradient is the inward normal.
Eigen::Vector3d MarginGradientTranslation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, int index,
                                          double step_m = 1e-6) noexcept;
Eigen::Vector3d MarginGradientRotation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, int index,
                                       double step_rad = 1e-6) noexcept;

// Gradients of all nine limit margins at once (columns in RsrIkResult::checks order), by central differences:
// six IK evaluations.
using MarginGradients = Eigen::Matrix<double, 3, 3 * robot::kNumArms>;
void AllMarginGradientsTranslation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, MarginGradients& g,
                                   double step_m = 1e-6) noexcept;
void AllMarginGradientsRotation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, MarginGradients& g,
                                double step_rad = 1e-6) noexcept;

// Unit inward normal of the true boundary near X (zero if undefined). Each limit i gives a first-order signed
// distance s_i = margin_i / |∇margin_i| and a unit normal ĝ_i; the normal is Σ w_i ĝ_i normalised, with
// w_i = exp(−(s_i − min_j s_j)/blend): the gradient of a soft minimum of the limits' distance functions. Away from
// edges it is the tightest limit's normal; on an edge or corner where several limits are equally tight (the RSR's
// ±x, ±y edges at home orientation meet all three spherical cones at once) it is their bisector instead of an
// arbitrary one of them. blend: 1 mm in translation, 0.5° in rotation [assumed].
Eigen::Vector3d InwardNormalTranslation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                                        double blend_m = 1e-3) noexcept;
Eigen::Vector3d InwardNormalRotation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                                     double blend_rad = 0.5 * 3.14159265358979323846 / 180) noexcept;

// Largest s in [0, 1] found by `steps` bisections such that the pose with position p_from + s·(p_to − p_from) and
// orientation R is feasible; (p_from, R) must be feasible. Returns 1 when p_to itself is feasible.
double BisectTranslation(const robot::RsrModel& model, const Eigen::Matrix3d& R, const Eigen::Vector3d& p_from,
                         const Eigen::Vector3d& p_to, int steps) noexcept;
// Same in orientation: R(s) = exp(s · rotvec) · R_from at position p.
double BisectRotation(const robot::RsrModel& model, const Eigen::Vector3d& p, const Eigen::Matrix3d& R_from,
                      const Eigen::Vector3d& rotvec, int steps) noexcept;

// The reference's range: how far the penetration search below looks. In translation 0.2 m [assumed]: far beyond the
// tens of mm a hand on the device pushes through a wall, and not longer because the search's fallback (26 rays, 20
// steps each of range/20) would then step over thin parts of the region. In rotation the whole space, at the same
// cost: a rotation vector of norm pi reaches every orientation, so nothing found within it means no feasible
// orientation exists at that position (up to the fallback's 9° steps).
inline constexpr double kPenetrationRangeM = 0.2;
inline constexpr double kPenetrationRangeRad = 3.14159265358979323846;

// Penetration beyond the true boundary, for the metrics: the distance from X to the nearest feasible position at
// X's orientation (m), and the angle to the nearest feasible orientation at X's position (rad). 0 when X is
// feasible. Found by Newton projection on the violated limits (each step moves along the violated limit's gradient
// to its zero, exact to first order for one active limit), with a directional bisection search as the fallback.
// Returns exactly `cap` when nothing feasible is found within it (every found value is below it): the penetration is
// then beyond the reference's range, and only known to be at least `cap` (or undefined: beyond the twist limit no
// position is feasible, far from the workspace no orientation is).
double TranslationalPenetration(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                                double cap_m = kPenetrationRangeM) noexcept;
double RotationalPenetration(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM,
                             double cap_rad = kPenetrationRangeRad) noexcept;

// Whether the inward normal is unique at X: false on an edge or corner of the region, where a second limit's
// first-order distance s_i = margin_i / |grad margin_i| is within `edge_margin` of the tightest limit's and its
// normal is more than `crease_rad` away from the tightest's. There the boundary has a cone of normals (the soft-min
// normal above is only one of them, set by its blend), so no single direction is the truth. Six IK evaluations.
bool IsNormalUniqueTranslation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, double edge_margin_m,
                               double crease_rad) noexcept;
bool IsNormalUniqueRotation(const robot::RsrModel& model, const Eigen::Isometry3d& X_FM, double edge_margin_rad,
                            double crease_rad) noexcept;

}  // namespace robossis::haptics
