#include <iostream>
#include <vector>

#include "src/apps/app_context.h"
#include "src/core/parse.h"

namespace robossis::apps {

Eigen::Isometry3d ParsePoseMmDeg(const std::string& text, const std::string& option_name) {
  const std::vector<double> v =
      ParseNumberList(text, 6, option_name, "X_MM,Y_MM,Z_MM,ROLL_DEG,PITCH_DEG,YAW_DEG");
  return PoseFromMmDeg(Eigen::Map<const Vector6d>(v.data()));
}

void PrintJson(const nlohmann::ordered_json& document) { std::cout << document.dump(2) << "\n"; }

}  // namespace robossis::apps
