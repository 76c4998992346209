#include <cmath>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "haptics/transfer/transfer_config.h"
#include "src/apps/app_context.h"
#include "src/core/parse.h"

namespace robossis::apps {

Eigen::Isometry3d ParsePoseMmDeg(const std::string& text, const std::string& option_name, FieldBounds bounds) {
  const std::vector<double> v =
      ParseNumberList(text, 6, option_name, "X_MM,Y_MM,Z_MM,ROLL_DEG,PITCH_DEG,YAW_DEG", bounds);
  return PoseFromMmDeg(Eigen::Map<const Vector6d>(v.data()));
}

OutputPolicy AppContext::Output(std::vector<OutputPolicy::Input> inputs) const {
  for (const char* folder : kDataDirInputs) inputs.push_back({"--data-dir", data_dir / folder, true});
  return OutputPolicy(force, std::move(inputs));
}

std::filesystem::path DeviceInputPath(const std::string& device) {
  const std::string prefix = "replay:";
  return device.rfind(prefix, 0) == 0 ? std::filesystem::path(device.substr(prefix.size())) : std::filesystem::path();
}

std::string LinearSpeedCapHelp() {
  std::ostringstream os;
  os << "Linear speed cap in (0, " << transfer::kMaxLinearSpeedCapMmS << "] mm/s (default: transfer.yaml's caps)";
  return os.str();
}

std::string AngularSpeedCapHelp() {
  std::ostringstream os;
  os << "Angular speed cap in (0, " << transfer::kMaxAngularSpeedCapDegS << "] deg/s (default: transfer.yaml's caps)";
  return os.str();
}

void PrintJson(const nlohmann::ordered_json& document) { std::cout << document.dump(2) << "\n"; }

double OptionInRange(double value, double lo, double hi, const std::string& option_name, const std::string& unit) {
  if (!std::isfinite(value) || value < lo || value > hi) {
    std::ostringstream os;
    os << option_name << ": expected a finite number in [" << lo << ", " << hi << "]" << (unit.empty() ? "" : " ")
       << unit << ", got " << value;
    throw std::invalid_argument(os.str());
  }
  return value;
}

}  // namespace robossis::apps
