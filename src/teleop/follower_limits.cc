#include "src/teleop/follower_limits.h"

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "src/core/files.h"

namespace robossis::teleop {

namespace {
// [assumed] rsr.yaml and actuation.yaml are a few kB; a larger file is not the robot's config.
constexpr std::uintmax_t kMaxModelConfigBytes = std::uintmax_t{1} << 20;

std::string Number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
}  // namespace

std::uint64_t ModelFingerprint(std::initializer_list<std::filesystem::path> files) {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a offset basis
  for (const std::filesystem::path& file : files) {
    for (const char c : ReadBoundedFile(file, kMaxModelConfigBytes, "robot config")) {
      h ^= static_cast<unsigned char>(c);
      h *= 1099511628211ull;  // FNV-1a prime
    }
  }
  return h;
}

FollowerLimits LimitsOf(const FollowerConfig& config) {
  const SetPointLimits& s = config.setpoint;
  FollowerLimits l;
  l.max_linear_speed_m_s = s.caps.max_linear_speed_m_s;
  l.max_angular_speed_rad_s = s.caps.max_angular_speed_rad_s;
  l.max_linear_accel_m_s2 = s.max_linear_accel_m_s2;
  l.max_angular_accel_rad_s2 = s.max_angular_accel_rad_s2;
  l.max_age_s = s.max_age_s;
  l.model_fingerprint = config.model_fingerprint;
  return l;
}

std::string CompareLimits(const FollowerLimits& leader, const FollowerLimits& follower) {
  const struct {
    const char* name;
    double FollowerLimits::*field;
  } fields[] = {{"max_linear_speed_m_s", &FollowerLimits::max_linear_speed_m_s},
                {"max_angular_speed_rad_s", &FollowerLimits::max_angular_speed_rad_s},
                {"max_linear_accel_m_s2", &FollowerLimits::max_linear_accel_m_s2},
                {"max_angular_accel_rad_s2", &FollowerLimits::max_angular_accel_rad_s2},
                {"max_age_s", &FollowerLimits::max_age_s}};
  for (const auto& f : fields) {
    if (leader.*f.field != follower.*f.field) {
      return std::string("set-point limit ") + f.name + ": the follower validates against " +
             Number(follower.*f.field) + ", this leader's config has " + Number(leader.*f.field) +
             " (follower.yaml/transfer.yaml must be the same on both machines)";
    }
  }
  if (leader.model_fingerprint != follower.model_fingerprint) {
    return "model config fingerprint: the follower's rsr.yaml and actuation.yaml give " +
           std::to_string(follower.model_fingerprint) + ", this leader's give " +
           std::to_string(leader.model_fingerprint) + " (both files must be the same on both machines)";
  }
  return "";
}

void CheckFollowerLimits(LeaderLink& link, const FollowerLimits& expected, double wait_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(wait_s);
  FollowerStatusMessage status;
  // A status without limits (all zero) is one the DDS link assembled before the follower's operating state arrived
  // (or a follower that does not publish them): wait for one that carries them.
  while (!link.TakeFollowerStatus(status) || status.limits.max_linear_speed_m_s == 0) {
    if (std::chrono::steady_clock::now() >= deadline) {
      throw std::runtime_error("no follower status carrying its set-point limits within " + Number(wait_s) +
                               " s: the follower's limits are unknown, the leader does not start");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (const std::string difference = CompareLimits(expected, status.limits); !difference.empty()) {
    throw std::runtime_error("the leader refuses to start: " + difference);
  }
}

}  // namespace robossis::teleop
