#pragma once
// Integers read from JSON the program did not write itself (an atlas manifest, a session log header).
// nlohmann's get<int>() converts a floating-point value with static_cast, which is undefined behaviour when the
// value does not fit (a manifest "version": 2.2e126), and wraps an integer that does not fit without a word.

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include <nlohmann/json.hpp>

namespace robossis {

// `j` as a T: it must be a JSON integer (not 2.0, not "2") within T's range; else std::runtime_error naming `what`.
template <typename T>
T JsonInteger(const nlohmann::json& j, const std::string& what) {
  static_assert(std::is_integral_v<T> && !std::is_same_v<T, bool>);
  if (j.is_number_unsigned()) {
    const auto v = j.get<std::uint64_t>();
    if (std::in_range<T>(v)) return static_cast<T>(v);
  } else if (j.is_number_integer()) {
    const auto v = j.get<std::int64_t>();
    if (std::in_range<T>(v)) return static_cast<T>(v);
  }
  throw std::runtime_error(what + ": expected an integer from " + std::to_string(+std::numeric_limits<T>::min()) +
                           " to " + std::to_string(+std::numeric_limits<T>::max()) + ", got " + j.dump());
}

}  // namespace robossis
