// Loads the installed RSR configuration and checks that its home pose is feasible (exit 0) through the installed
// headers and libraries.
#include <cstdio>

#include "robot/rsr_kinematics.h"
#include "robot/rsr_model.h"

int main() {
  using namespace robossis;
  const robot::RsrModel rsr = robot::RsrModel::FromYaml(std::filesystem::path(CONSUMER_DATA_DIR) / "config" / "rsr.yaml");
  const robot::RsrIkResult ik = robot::CalcInverseKinematics(rsr, rsr.geometry().X_FM_home);
  std::printf("home pose feasible: %s\n", ik.feasible ? "yes" : "no");
  return ik.feasible ? 0 : 1;
}
