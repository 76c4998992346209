#include "haptics/transfer/incremental_mapping.h"

#include <algorithm>
#include <cmath>

namespace robossis::transfer {

const char* ToString(SampleVerdict verdict) {
  switch (verdict) {
    case SampleVerdict::kAnchored: return "anchored";
    case SampleVerdict::kAccepted: return "accepted";
    case SampleVerdict::kRepeated: return "repeated";
    case SampleVerdict::kLate: return "late";
    case SampleVerdict::kInvalid: return "invalid";
    case SampleVerdict::kClutchOpen: return "clutch_open";
  }
  return "unknown";
}

IncrementalMapper::IncrementalMapper(const MappingConfig& mapping, const SpeedCaps& caps)
    : mapping_(mapping),
      max_v_(caps.max_linear_speed_m_s * mapping.cap_headroom),
      max_w_(caps.max_angular_speed_rad_s * mapping.cap_headroom) {}

void IncrementalMapper::SetClutch(bool engaged) noexcept {
  if (engaged && !engaged_) anchored_ = false;  // the next sample becomes the new reference: no jump
  engaged_ = engaged;
}

SampleVerdict IncrementalMapper::Push(const HcSample& sample, MappingIncrement& increment) noexcept {
  increment = MappingIncrement{};
  if (!std::isfinite(sample.time_s) || !sample.p_OH.allFinite() || !sample.R_OH.allFinite()) {
    return SampleVerdict::kInvalid;
  }
  if (!engaged_) return SampleVerdict::kClutchOpen;
  if (!anchored_) {
    last_ = sample;
    anchored_ = true;
    return SampleVerdict::kAnchored;
  }
  if (sample.time_s <= last_.time_s) return SampleVerdict::kLate;
  if (sample.p_OH == last_.p_OH && sample.R_OH == last_.R_OH) return SampleVerdict::kRepeated;

  const double gap_s = sample.time_s - last_.time_s;
  // HC increments in the HC base frame O: translation, and the fixed-frame rotation increment R_new R_old^T.
  const Eigen::Vector3d dp_O = sample.p_OH - last_.p_OH;
  const Eigen::Matrix3d dR_O = sample.R_OH * last_.R_OH.transpose();
  const Eigen::Vector3d dphi_O = RotationVector(dR_O);
  last_ = sample;

  // Frame mapping O → F and the nominal scaling: the one HC → RSR frame map the walls use too.
  const Eigen::Vector3d dp_F = mapping_.frame().LinearToRsr(dp_O);
  const Eigen::Vector3d dphi_F = mapping_.frame().AngularToRsr(dphi_O);

  // eq. 11, as a cap: S = min(1, Max / |v|), on the norm of the (mapped) hand velocity.
  increment.hc_speed_m_s = dp_F.norm() / gap_s;
  increment.hc_angular_speed_rad_s = dphi_F.norm() / gap_s;
  increment.scale_linear = increment.hc_speed_m_s > max_v_ ? max_v_ / increment.hc_speed_m_s : 1.0;
  increment.scale_angular =
      increment.hc_angular_speed_rad_s > max_w_ ? max_w_ / increment.hc_angular_speed_rad_s : 1.0;
  // eq. 10: the RSR increment.
  increment.delta_F << increment.scale_linear * dp_F, increment.scale_angular * dphi_F;
  return SampleVerdict::kAccepted;
}

}  // namespace robossis::transfer
