#include "src/core/parse.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace robossis {

std::string FormatNumber(double value, const char* printf_format) {
  char buf[64];
  std::snprintf(buf, sizeof buf, printf_format, value);
  return buf;
}

std::string_view TrimField(std::string_view s) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '"' || c == '\r'; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

bool TryParseNumber(std::string_view field, double* out) {
  field = TrimField(field);
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  if (field.empty()) return false;
  double v = 0.0;
  const char* end = field.data() + field.size();
  const auto result = std::from_chars(field.data(), end, v);
  if (result.ec != std::errc() || result.ptr != end || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

double ParseNumber(std::string_view text, const std::string& option_name) {
  double v = 0.0;
  if (!TryParseNumber(text, &v)) {
    throw std::invalid_argument(option_name + ": expected a finite number, got '" + std::string(text) + "'");
  }
  return v;
}

namespace {
// The hint's comma-separated field names ("X_MM,Y_MM,..."); empty names where the hint has fewer than `count`.
std::vector<std::string_view> SplitFieldNames(std::string_view hint, std::size_t count) {
  std::vector<std::string_view> names(count);
  for (std::size_t i = 0; i < count && !hint.empty(); ++i) {
    const std::size_t comma = hint.find(',');
    names[i] = hint.substr(0, comma);
    hint = comma == std::string_view::npos ? std::string_view() : hint.substr(comma + 1);
  }
  return names;
}
}  // namespace

std::vector<double> ParseNumberList(std::string_view text, std::size_t count, const std::string& option_name,
                                    const std::string& format_hint, FieldBounds bounds) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    fields.push_back(text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  const std::string expected =
      "expected " + std::to_string(count) + " comma-separated numbers (" + format_hint + ")";
  if (fields.size() != count) {
    throw std::invalid_argument(option_name + ": " + expected + ", got " + std::to_string(fields.size()) + " in '" +
                                std::string(text) + "'");
  }
  const std::vector<std::string_view> names = SplitFieldNames(format_hint, count);
  std::vector<double> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    if (!TryParseNumber(fields[i], &out[i])) {
      throw std::invalid_argument(option_name + ": " + expected + "; value " + std::to_string(i + 1) + " is '" +
                                  std::string(fields[i]) + "', not a finite number");
    }
    if (bounds == FieldBounds::kFinite) continue;
    const auto ends_with = [&](std::string_view unit) {
      return names[i].size() > unit.size() && names[i].substr(names[i].size() - unit.size()) == unit;
    };
    const char* what = ends_with("_MM") ? "a position" : ends_with("_DEG") ? "an angle" : nullptr;
    const double bound = ends_with("_MM") ? kMaxEdgePositionMm : kMaxEdgeAngleDeg;
    if (what != nullptr && !(std::fabs(out[i]) <= bound)) {
      throw std::invalid_argument(option_name + ": " + std::string(names[i]) + " is '" +
                                  std::string(TrimField(fields[i])) + "'; expected " + what + " within +-" +
                                  FormatNumber(bound) + (ends_with("_MM") ? " mm" : " deg"));
    }
  }
  return out;
}

}  // namespace robossis
