// libFuzzer target: any bytes given to the Motive reader produce frames or a std::runtime_error, never a crash,
// a hang or undefined behaviour. Run: fuzz_motive_reader -max_total_time=60 tests/calibration/data/
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "calibration/mocap_track.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace robossis::calibration;
  std::optional<MotiveReader> parsed;
  try {
    parsed.emplace(std::string(reinterpret_cast<const char*>(data), size), "fuzz.csv");
  } catch (const std::runtime_error&) {
    return 0;
  }
  // The header is parsed once (half the target's time when each pass parsed it): a copy of the reader is at the
  // first frame too.
  MotiveReader inspected = *parsed;
  try {
    MotiveReader& reader = *parsed;
    MotiveRow row;
    int frames = 0;
    while (reader.ReadFrame(row) && frames < 100000) {
      for (int r = 0; r < static_cast<int>(reader.layout().rigid_bodies.size()); ++r) reader.RigidBodyPose(row, r);
      for (const MotiveMarkerColumns& m : reader.layout().markers) reader.MarkerPosition(row, m);
      ++frames;
    }
  } catch (const std::runtime_error&) {
  }
  try {
    InspectMotiveTake(inspected);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
