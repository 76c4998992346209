#pragma once
// How to find and open a Force Dimension device: the options of `--device dhd[:key=value,...]`.
//   dhd                              the first sigma.7 found, libdhd from the usual places
//   dhd:serial=12345                 the device with this serial number
//   dhd:index=1                      the SDK's device index 1
//   dhd:lib=/opt/fd/lib/libdhd.so    this library (and no other)
//   dhd:hold=1                       load libdrd instead (it carries libdhd), to hold the handle at a pose
//   dhd:drd=/opt/fd/lib/libdrd.so    the same, from this library
//   dhd:window_ms=5                  the SDK's velocity estimator window

#include <filesystem>
#include <string>

#include "haptics/device/haptic_device.h"

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::haptics {

struct DhdOptions {
  std::string library_path;      // libdhd; empty: $ROBOSSIS_DHD_LIBRARY, then the usual names (dhd_library.h)
  std::string drd_library_path;  // libdrd (with the hold); empty: $ROBOSSIS_DRD_LIBRARY, then the usual names
  int index = -1;                // >= 0: open this SDK device index
  int serial = -1;               // >= 0: open the device with this serial number
  bool enable_hold = false;      // load libdrd (not libdhd) so that DhdDevice::HoldAt/HoldHere can be used
  // The SDK's velocity estimator window (dhd.yaml, [assumed]; the SDK's default is 20 ms).
  int velocity_window_ms = 5;
  DeviceLimits limits;  // the sigma.7's own limits (haptic_device.h)
};

// Reads the [assumed] values of data/config/dhd.yaml into `defaults`' fields. Throws std::runtime_error naming the
// file and the key.
DhdOptions DhdOptionsFromYaml(const std::filesystem::path& file, DhdOptions defaults = {});
// The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
DhdOptions DhdOptionsFromConfig(const ConfigNode& root, DhdOptions defaults = {});

// Parses "dhd" or "dhd:key=value,key=value" over `defaults`. Throws std::invalid_argument naming the spec, the key
// and what was expected.
DhdOptions ParseDhdOptions(const std::string& spec, DhdOptions defaults = {});

}  // namespace robossis::haptics
