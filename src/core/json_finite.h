#pragma once
// Numbers in JSON the program reads back (a session log header, a unit's summary.json): nlohmann parses a number
// that overflows a double (1e999) as inf, which no later check expects. One walk over the document refuses it.

#include <cmath>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace robossis {

// Throws std::runtime_error "WHAT: '/path/to/value': got inf; expected a finite number" at the first non-finite
// number anywhere in `j` (objects and arrays included).
template <typename Json>
void RequireFiniteNumbers(const Json& j, const std::string& what, const std::string& path = "") {
  if (j.is_number_float()) {
    const double v = j.template get<double>();
    if (!std::isfinite(v)) {
      throw std::runtime_error(what + ": '" + (path.empty() ? "/" : path) + "': got " +
                               (std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf") +
                               " (a number too large for a double); expected a finite number");
    }
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) RequireFiniteNumbers(it.value(), what, path + "/" + it.key());
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) RequireFiniteNumbers(j[i], what, path + "/" + std::to_string(i));
  }
}

// Parses JSON the program reads back, in the project's words: nlohmann refuses a number that overflows a double
// (1e999) with its own text ("[json.exception.out_of_range.406] ..."); this names `what` and says what was wrong.
// Then RequireFiniteNumbers. Throws std::runtime_error.
template <typename Json = nlohmann::json, typename It>
Json ParseJsonInput(It begin, It end, const std::string& what) {
  Json j;
  try {
    j = Json::parse(begin, end);
  } catch (const nlohmann::json::out_of_range& e) {
    if (e.id != 406) throw std::runtime_error(what + ": not valid JSON");
    throw std::runtime_error(what + ": a number too large for a double (such as 1e999); expected finite numbers");
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error(what + ": not valid JSON (at byte " + std::to_string(e.byte) + ")");
  }
  RequireFiniteNumbers(j, what);
  return j;
}

}  // namespace robossis
