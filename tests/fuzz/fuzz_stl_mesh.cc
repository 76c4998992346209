// libFuzzer target: the femur mesh reader (the bone of the Bullet follower, sim.yaml's bone.mesh) and what the
// follower does with a mesh it read: its mass properties and the mid-shaft cut into two fragments. Any bytes give a
// mesh or a std::runtime_error / std::invalid_argument naming what is wrong, never a crash, a hang or undefined
// behaviour.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "robot/sim/bone_mesh.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace robossis;
  const auto file = fuzz::InputFile(data, size, "bone.stl");
  try {
    const sim::TriangleMesh mesh = sim::ReadStl(file);
    sim::CalcMassProperties(mesh);
    double z_min = mesh.vertices.front().z(), z_max = z_min;
    for (const auto& v : mesh.vertices) {
      z_min = std::min(z_min, v.z());
      z_max = std::max(z_max, v.z());
    }
    sim::CutMeshAtZ(mesh, 0.5 * (z_min + z_max));
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
