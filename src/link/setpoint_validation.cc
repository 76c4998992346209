#include "src/link/setpoint_validation.h"

#include <cmath>

namespace robossis::link {

namespace {
template <std::size_t N>
bool AllFinite(const std::array<double, N>& a) noexcept {
  for (double v : a) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}
double Norm3(double x, double y, double z) noexcept { return std::sqrt(x * x + y * y + z * z); }
}  // namespace

bool IsSaneSetPoint(const teleop::SetPointMessage& m, const LinkTuning& t, const char** why) noexcept {
  const char* failed = nullptr;
  if (!AllFinite(m.p_FM)) failed = "p_FM not finite";
  else if (!AllFinite(m.q_FM)) failed = "q_FM not finite";
  else if (!AllFinite(m.twist_F)) failed = "twist_F not finite";
  else if (Norm3(m.p_FM[0], m.p_FM[1], m.p_FM[2]) > t.max_position_m) failed = "p_FM beyond max_position_m";
  else if (std::abs(std::sqrt(m.q_FM[0] * m.q_FM[0] + m.q_FM[1] * m.q_FM[1] + m.q_FM[2] * m.q_FM[2] +
                              m.q_FM[3] * m.q_FM[3]) - 1.0) > t.quaternion_norm_tolerance) {
    failed = "q_FM not a unit quaternion";
  } else if (Norm3(m.twist_F[0], m.twist_F[1], m.twist_F[2]) > t.max_linear_speed_m_per_s) {
    failed = "twist_F linear beyond max_linear_speed_m_per_s";
  } else if (Norm3(m.twist_F[3], m.twist_F[4], m.twist_F[5]) > t.max_angular_speed_rad_per_s) {
    failed = "twist_F angular beyond max_angular_speed_rad_per_s";
  }
  if (why != nullptr) *why = failed;
  return failed == nullptr;
}

}  // namespace robossis::link
