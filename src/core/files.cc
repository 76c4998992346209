#include "src/core/files.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include <fstream>
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

namespace {

// Closes the descriptor on every path out of ReadBoundedFile.
struct Descriptor {
  int fd = -1;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

std::string OpenProblem(int error) {
  switch (error) {
    case ENOENT: return "no such file";
    case ENOTDIR: return "a folder on its path is not a folder";
    case EACCES: return "permission denied";
    case ELOOP: return "too many symbolic links";
    case ENXIO: return "expected a regular file; it is a device or a socket";
    default: return "cannot open it (error " + std::to_string(error) + ")";
  }
}

}  // namespace

std::string ReadBoundedFile(const fs::path& file, std::uintmax_t max_bytes, const std::string& what) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer. The checks are made on the opened
  // descriptor (fstat), so the file cannot be swapped for another between the check and the read.
  Descriptor d;
  do {
    d.fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  } while (d.fd < 0 && errno == EINTR);
  if (d.fd < 0) throw std::runtime_error(file.string() + ": cannot open the " + what + ": " + OpenProblem(errno));
  struct stat st {};
  if (::fstat(d.fd, &st) != 0) throw std::runtime_error(file.string() + ": cannot read the size of the " + what);
  if (!S_ISREG(st.st_mode)) {
    throw std::runtime_error(file.string() + ": expected a regular file (" + what +
                             "); it is a directory, a device or a pipe");
  }
  const auto size = static_cast<std::uintmax_t>(st.st_size);
  if (size > max_bytes) {
    throw std::runtime_error(file.string() + ": " + std::to_string(size) + " bytes; expected a " + what +
                             " of at most " + std::to_string(max_bytes) + " bytes");
  }
  std::string text(static_cast<std::size_t>(size), '\0');
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::read(d.fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  char extra = 0;
  if (done != text.size() || ::read(d.fd, &extra, 1) != 0) {
    throw std::runtime_error(file.string() + ": the " + what + " changed or could not be read while reading");
  }
  return text;
}

std::string ReadTextFile(const fs::path& path) { return ReadBoundedFile(path, kMaxTextFileBytes, "file"); }

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
