// libFuzzer target: the panel's script parser (`robossis panel --script FILE`). Any bytes give a list of timed
// actions or a std::invalid_argument naming the line, never a crash, a hang or undefined behaviour.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "src/panel/script.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    robossis::panel::ParseScript(std::string(reinterpret_cast<const char*>(data), size), "fuzz.txt");
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
