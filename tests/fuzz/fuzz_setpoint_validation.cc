// libFuzzer target: the follower's set-point validation. The input is a sequence of link messages as they could
// arrive from an authenticated but broken or hostile leader (any bytes for the pose, twist, flags, sequence and
// session, any arrival times). Every message gets a verdict, never a crash or undefined behaviour, and an accepted
// set-point is always inside the workspace by the exact IK.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "robot/rsr_kinematics.h"
#include "robot/rsr_model.h"
#include "src/teleop/setpoint_validator.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace robossis;
  static const robot::RsrModel model = robot::RsrModel::Default();
  teleop::SetPointValidator validator(model, teleop::SetPointLimits{});
  // One record: the message's bytes, then the arrival and "now" offsets (double each).
  constexpr std::size_t kRecord = sizeof(teleop::SetPointMessage) + 2 * sizeof(double);
  for (std::size_t off = 0; off + kRecord <= size; off += kRecord) {
    teleop::SetPointMessage message;
    std::memcpy(static_cast<void*>(&message), data + off, sizeof message);
    double arrival_s = 0, now_s = 0;
    std::memcpy(&arrival_s, data + off + sizeof message, sizeof(double));
    std::memcpy(&now_s, data + off + sizeof message + sizeof(double), sizeof(double));
    teleop::SetPointSample sample;
    if (validator.CheckMessage(message, arrival_s, now_s, sample) == teleop::SetPointVerdict::kAccepted &&
        !robot::CalcInverseKinematics(model, sample.X_FM).feasible) {
      std::abort();  // an accepted set-point outside the workspace
    }
  }
  return 0;
}
