// libFuzzer target: the reference trajectory readers (project CSV and TUM, chosen by content).
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "calibration/trajectory.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace robossis;
  try {
    const calibration::PoseTrajectory t =
        calibration::ReadReferenceTrajectory(fuzz::InputFile(data, size, "reference.csv"));
    Eigen::Vector3d p;
    Eigen::Quaterniond q;
    calibration::InterpolatePose(t, t.t_s.front() + 0.5 * t.duration_s(), p, q);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
