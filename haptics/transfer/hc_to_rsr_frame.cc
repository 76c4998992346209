#include "haptics/transfer/hc_to_rsr_frame.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "src/core/parse.h"
#include "src/core/pose.h"

namespace robossis::transfer {

Eigen::Matrix3d HcToRsrFrame::RotationToRsr(const Eigen::Matrix3d& dR_O) const noexcept {
  if (rotation_scale == 1.0) return R_FO * dR_O * R_FO.transpose();
  return RotationFromVector(AngularToRsr(RotationVector(dR_O)));
}

Eigen::Matrix3d HcToRsrFrame::RotationToHc(const Eigen::Matrix3d& dR_F) const noexcept {
  if (rotation_scale == 1.0) return R_FO.transpose() * dR_F * R_FO;
  return RotationFromVector(AngularToHc(RotationVector(dR_F)));
}

void HcToRsrFrame::Validate() const {
  const auto fail = [](const std::string& key, const std::string& expected, double value) {
    throw std::invalid_argument("'" + key + "': expected " + expected + ", got " + FormatNumber(value));
  };
  if (!(std::isfinite(translation_scale) && translation_scale > 0)) {
    fail("mapping.translation_scale", "a positive factor", translation_scale);
  }
  if (!(std::isfinite(rotation_scale) && rotation_scale > 0)) {
    fail("mapping.rotation_scale", "a positive factor", rotation_scale);
  }
  const Eigen::Matrix3d RtR = R_FO.transpose() * R_FO;
  if (!(R_FO.allFinite() && (RtR - Eigen::Matrix3d::Identity()).norm() < 1e-9 && R_FO.determinant() > 0)) {
    fail("mapping.rsr_from_hc_rpy_deg", "a proper rotation", R_FO.determinant());
  }
}

}  // namespace robossis::transfer
