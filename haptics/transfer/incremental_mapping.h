#pragma once
// Incremental HC→RSR mapping with dynamic scaling (paper eq. 10–11), the clutch, and the hygiene of a "broken" USB
// stream (Fig. 8): dropped samples (gaps), repeated samples (a frozen driver returning the same pose), late samples
// (older than one already used) and invalid ones (NaN).
//
// eq. 10: x_RSR(t) = x_RSR(t-1) + (x_HC(t) - x_HC(t-1)) · S
// eq. 11: S = [Max_v, Max_w] / [|v_HC|, |w_HC|]
// We read eq. 11 as a cap, S = min(1, Max / |v_HC|) separately for the linear and the angular part: below the cap the
// hand's motion passes unchanged (Fig. 8b: the scaling acts "once the user speed is above the desired limits").
// |v_HC| is the speed over the time since the last *new* sample, so a gap or a freeze followed by a jump is a
// displacement over the whole gap, not a spike.

#include <cstdint>

#include <Eigen/Geometry>

#include "haptics/transfer/transfer_config.h"
#include "src/core/pose.h"

namespace robossis::transfer {

// One HC reading: the handle pose in the HC base frame O, stamped by the device clock.
struct HcSample {
  double time_s = 0;
  Eigen::Vector3d p_OH = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_OH = Eigen::Matrix3d::Identity();
};

enum class SampleVerdict : std::uint8_t {
  kAnchored,    // first sample after the clutch engaged: the reference, no motion
  kAccepted,    // a new sample: an increment was produced
  kRepeated,    // same pose as the last sample (frozen driver): ignored, the gap keeps growing
  kLate,        // not newer than the last sample used: ignored
  kInvalid,     // non-finite values: ignored
  kClutchOpen,  // clutch released: ignored
};
const char* ToString(SampleVerdict verdict);

struct MappingIncrement {
  Vector6d delta_F = Vector6d::Zero();  // RSR increment [m; rad] in F, after scaling
  double hc_speed_m_s = 0;              // |v_HC| over the gap
  double hc_angular_speed_rad_s = 0;    // |w_HC|
  double scale_linear = 1;              // S of eq. 11 (<= 1)
  double scale_angular = 1;
};

class IncrementalMapper {
 public:
  IncrementalMapper(const MappingConfig& mapping, const SpeedCaps& caps);

  // Engaging re-anchors on the next sample; releasing ignores samples until re-engaged. Neither moves the RSR.
  void SetClutch(bool engaged) noexcept;
  bool clutch_engaged() const { return engaged_; }

  // Processes one sample; on kAccepted, `increment` holds the RSR increment of eq. 10. Allocation-free.
  SampleVerdict Push(const HcSample& sample, MappingIncrement& increment) noexcept;

 private:
  MappingConfig mapping_;
  double max_v_;
  double max_w_;
  bool engaged_ = true;
  bool anchored_ = false;
  HcSample last_{};
};

}  // namespace robossis::transfer
