#include "haptics/device/dhd_options.h"

#include <charconv>
#include <stdexcept>
#include <string_view>

#include "src/core/config.h"

namespace robossis::haptics {

namespace {

// The longest window the option accepts: beyond it the velocity is too late to damp anything.
constexpr int kMaxVelocityWindowMs = 100;

int ParseInt(const std::string& spec, std::string_view key, std::string_view value, int lo, int hi) {
  int out = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), out);
  if (error != std::errc{} || end != value.data() + value.size() || out < lo || out > hi) {
    throw std::invalid_argument("--device '" + spec + "': '" + std::string(key) + "' expected an integer in [" +
                                std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + std::string(value) +
                                "'");
  }
  return out;
}

}  // namespace

DhdOptions DhdOptionsFromYaml(const std::filesystem::path& file, DhdOptions defaults) {
  return DhdOptionsFromConfig(ConfigNode::Load(file), defaults);
}

DhdOptions DhdOptionsFromConfig(const ConfigNode& root, DhdOptions defaults) {
  defaults.velocity_window_ms =
      static_cast<int>(root.Child("velocity").NumberInRange("window_ms", 1, kMaxVelocityWindowMs));
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  return defaults;
}

DhdOptions ParseDhdOptions(const std::string& spec, DhdOptions defaults) {
  const std::string_view text(spec);
  if (text != "dhd" && text.substr(0, 4) != "dhd:") {
    throw std::invalid_argument("--device '" + spec + "': expected 'dhd' or 'dhd:key=value,...'");
  }
  std::string_view rest = text.size() > 4 ? text.substr(4) : std::string_view{};
  while (!rest.empty()) {
    const std::size_t comma = rest.find(',');
    const std::string_view item = rest.substr(0, comma);
    rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos || eq == 0 || eq + 1 == item.size()) {
      throw std::invalid_argument("--device '" + spec + "': expected key=value, got '" + std::string(item) + "'");
    }
    const std::string_view key = item.substr(0, eq), value = item.substr(eq + 1);
    if (key == "lib") {
      defaults.library_path = value;
    } else if (key == "drd") {
      defaults.drd_library_path = value;
      defaults.enable_hold = true;
    } else if (key == "serial") {
      defaults.serial = ParseInt(spec, key, value, 0, 65535);  // the SDK's serial numbers are 16 bits
    } else if (key == "index") {
      defaults.index = ParseInt(spec, key, value, 0, 127);  // the SDK's device ids are a signed char
    } else if (key == "hold") {
      defaults.enable_hold = ParseInt(spec, key, value, 0, 1) == 1;
    } else if (key == "window_ms") {
      defaults.velocity_window_ms = ParseInt(spec, key, value, 1, kMaxVelocityWindowMs);
    } else {
      throw std::invalid_argument("--device '" + spec + "': unknown key '" + std::string(key) +
                                  "' (known: lib, drd, serial, index, hold, window_ms)");
    }
  }
  if (defaults.serial >= 0 && defaults.index >= 0) {
    throw std::invalid_argument("--device '" + spec + "': give 'serial' or 'index', not both");
  }
  return defaults;
}

}  // namespace robossis::haptics
