#pragma once
// A folder of the test process's own under the system's temp directory: empty when made (a leftover of an earlier
// run is removed first), unique per process (CTest runs tests in parallel processes), removed when destroyed.

#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace robossis::testing {

class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace robossis::testing
