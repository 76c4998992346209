// libFuzzer target: the boundary atlas loader (manifest.json) and its binary PLY meshes. The first input byte
// chooses the reader: even → the bytes are a manifest in an otherwise empty atlas folder; odd → a PLY slice.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "geometry/boundary_atlas.h"
#include "geometry/triangle_mesh.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace robossis;
  if (size == 0) return 0;
  try {
    if (data[0] % 2 == 0) {
      const std::filesystem::path dir = fuzz::FuzzDir() / "atlas";
      std::filesystem::create_directories(dir);
      fuzz::InputFile(data + 1, size - 1, "atlas/manifest.json");
      geometry::BoundaryAtlas::Load(dir);
    } else {
      geometry::ParseBinaryPly(std::string(reinterpret_cast<const char*>(data + 1), size - 1), 1e-3, "fuzz.ply");
    }
  } catch (const std::runtime_error&) {
  }
  return 0;
}
