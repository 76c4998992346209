// libFuzzer target: the flight recorder's session log reader (`robossis replay LOG`). Any bytes give a log or a
// std::runtime_error naming what is wrong, never a crash, a hang or undefined behaviour.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "src/teleop/session_log.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = robossis::fuzz::InputFile(data, size, "session.rlog");
  try {
    robossis::teleop::ReadSessionLog(file);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
