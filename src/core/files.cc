#include "src/core/files.h"

#include <unistd.h>

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace robossis {

namespace fs = std::filesystem;

void WriteFileAtomically(const fs::path& path, std::string_view contents) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  const fs::path tmp = path.string() + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path.string() + ": cannot open for writing");
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) {
      std::error_code ignored;
      fs::remove(tmp, ignored);
      throw std::runtime_error(path.string() + ": write failed");
    }
  }
  fs::rename(tmp, path);
}

std::string ReadTextFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open for reading");
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

StagedOutputDir::StagedOutputDir(fs::path target) : target_(std::move(target)) {
  if (target_.empty()) throw std::invalid_argument("--out: an output folder is required");
  if (fs::exists(target_) && !fs::is_directory(target_)) {
    throw std::invalid_argument("--out: '" + target_.string() + "' exists and is not a folder");
  }
  fs::path clean = target_.lexically_normal();
  if (!clean.has_filename()) clean = clean.parent_path();
  staging_ = clean.string() + ".partial-" + std::to_string(::getpid());
  fs::remove_all(staging_);
  fs::create_directories(staging_);
}

StagedOutputDir::~StagedOutputDir() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

fs::path StagedOutputDir::Path(const std::string& relative) const {
  const fs::path p = staging_ / relative;
  if (p.has_parent_path()) fs::create_directories(p.parent_path());
  return p;
}

void StagedOutputDir::Write(const std::string& relative, std::string_view contents) const {
  WriteFileAtomically(Path(relative), contents);
}

void StagedOutputDir::Commit() {
  fs::create_directories(target_);
  for (const auto& entry : fs::recursive_directory_iterator(staging_)) {
    const fs::path rel = fs::relative(entry.path(), staging_);
    const fs::path dest = target_ / rel;
    if (entry.is_directory()) {
      fs::create_directories(dest);
    }
  }
  for (const auto& entry : fs::recursive_directory_iterator(staging_)) {
    if (!entry.is_regular_file()) continue;
    const fs::path dest = target_ / fs::relative(entry.path(), staging_);
    fs::rename(entry.path(), dest);
  }
  fs::remove_all(staging_);
  committed_ = true;
}

}  // namespace robossis
