// libFuzzer target: any bytes given to the Motive reader produce frames or a std::runtime_error, never a crash,
// a hang or undefined behaviour. Run: fuzz_motive_reader -max_total_time=60 tests/calibration/data/
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "calibration/mocap_track.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace robossis::calibration;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    MotiveReader reader(text, "fuzz.csv");
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
    MotiveReader reader(text, "fuzz.csv");
    InspectMotiveTake(reader);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
