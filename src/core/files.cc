#include "src/core/files.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace robossis {

namespace fs = std::filesystem;

namespace {

bool ProcessIsGone(long pid) { return pid > 0 && pid != ::getpid() && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH; }

// "NAME.partial-123" → 123 if `entry` is NAME followed by one of the suffixes and a PID; else 0.
long LeftoverPid(const std::string& entry, const std::string& name) {
  for (const char* suffix : {".partial-", ".old-", ".tmp-"}) {
    const std::string prefix = name + suffix;
    if (entry.size() <= prefix.size() || entry.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = entry.substr(prefix.size());
    if (digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 9) return 0;
    return std::strtol(digits.c_str(), nullptr, 10);
  }
  return 0;
}

fs::path WithoutTrailingSlash(const fs::path& p) {
  fs::path clean = p.lexically_normal();
  if (!clean.has_filename()) clean = clean.parent_path();
  return clean;
}

}  // namespace

void RemoveLeftoversOfDeadRuns(const fs::path& path) {
  const fs::path clean = WithoutTrailingSlash(path);
  const std::string name = clean.filename().string();
  const fs::path parent = clean.has_parent_path() ? clean.parent_path() : fs::path(".");
  std::error_code ec;
  fs::directory_iterator it(parent, ec);
  if (ec) return;  // the folder does not exist yet: nothing is left over
  for (const fs::directory_entry& entry : it) {
    const long pid = LeftoverPid(entry.path().filename().string(), name);
    if (pid != 0 && ProcessIsGone(pid)) {
      std::error_code ignored;
      fs::remove_all(entry.path(), ignored);
    }
  }
}

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

StagedOutputDir::StagedOutputDir(fs::path target, bool replace_any) : target_(std::move(target)) {
  if (target_.empty()) throw std::invalid_argument("--out: an output folder is required");
  const fs::path clean = WithoutTrailingSlash(target_);
  const std::string name = clean.filename().string();
  if (name.empty() || name == "." || name == "..") {
    throw std::invalid_argument("--out: '" + target_.string() + "': expected the name of a new or earlier output "
                                "folder, not '.', '..' or the root");
  }
  if (fs::exists(target_) && !fs::is_directory(target_)) {
    throw std::invalid_argument("--out: '" + target_.string() + "' exists and is not a folder");
  }
  if (fs::is_directory(target_) && !fs::is_empty(target_) && !fs::exists(target_ / kOutputMarker) && !replace_any) {
    throw std::invalid_argument("--out: '" + target_.string() + "' is a non-empty folder that is not an earlier "
                                "robossis output; expected a new or empty folder (or --force to replace it whole)");
  }
  RemoveLeftoversOfDeadRuns(clean);
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
  WriteFileAtomically(staging_ / kOutputMarker, "written by robossis; the whole folder is replaced by the next run\n");
  const fs::path clean = WithoutTrailingSlash(target_);
  if (fs::exists(clean)) {
    // Move the old output aside first: the rename of the new one then cannot merge, and a crash in between leaves
    // the old output in `.old-PID`, which the next run removes.
    const fs::path aside = clean.string() + ".old-" + std::to_string(::getpid());
    fs::remove_all(aside);
    fs::rename(clean, aside);
    fs::rename(staging_, clean);
    fs::remove_all(aside);
  } else {
    if (clean.has_parent_path()) fs::create_directories(clean.parent_path());
    fs::rename(staging_, clean);
  }
  committed_ = true;
}

}  // namespace robossis
