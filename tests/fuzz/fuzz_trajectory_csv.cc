// libFuzzer target: the strict CSV reader through its two numeric formats (the scenario trajectory CSV and the HC
// trajectory CSV). Any bytes give a result or a std::runtime_error, never a crash, a hang or undefined behaviour.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "haptics/scenarios/scenario.h"
#include "haptics/transfer/hc_trajectory.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace robossis;
  const auto file = fuzz::InputFile(data, size, "trajectory.csv");
  try {
    const haptics::Scenario s = haptics::LoadTrajectoryCsv(file, haptics::HandParams{});
    if (!s.episodes.empty()) s.episodes[0].target_FM(0.5 * s.episodes[0].duration_s);
  } catch (const std::runtime_error&) {
  }
  try {
    transfer::ReadHcCsv(file);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
