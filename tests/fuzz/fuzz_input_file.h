#pragma once
// The fuzz targets' bridge to readers that take a path: the input bytes as a file in a per-process temporary
// folder (tmpfs where available), rewritten for every input.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace robossis::fuzz {

inline std::filesystem::path FuzzDir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path shm = "/dev/shm";
    const std::filesystem::path base = std::filesystem::is_directory(shm) ? shm : std::filesystem::temp_directory_path();
    const std::filesystem::path d = base / ("robossis-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

// Writes the input to FuzzDir()/name and returns the path.
inline std::filesystem::path InputFile(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const std::filesystem::path p = FuzzDir() / name;
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return p;
}

}  // namespace robossis::fuzz
