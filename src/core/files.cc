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

#include "src/core/staging_cleanup.h"

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
  if (!clean.has_filename() && clean.has_parent_path()) clean = clean.parent_path();
  return clean;
}

// The path as the file system sees it: absolute, symbolic links of its existing part resolved, no '.' or '..'.
fs::path Resolved(const fs::path& p) {
  std::error_code ec;
  fs::path absolute = fs::absolute(p, ec);
  if (ec) absolute = p;
  fs::path resolved = fs::weakly_canonical(absolute, ec);
  if (ec) resolved = absolute.lexically_normal();
  return WithoutTrailingSlash(resolved);
}

// Whether `inner` is `outer` or lies inside it (whole path components: "a/bc" is not inside "a/b").
bool IsWithin(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

std::string Quoted(const fs::path& p) {
  std::string q = p.string();  // appended in place: GCC 12 warns (-Wrestrict, falsely) on "'" + s + "'"
  q.insert(q.begin(), '\'');
  q.push_back('\'');
  return q;
}

std::string ErrnoText() { return errno != 0 ? std::error_code(errno, std::generic_category()).message() : "unknown"; }

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
  std::error_code ec;
  if (path.has_parent_path()) {
    fs::create_directories(path.parent_path(), ec);
    if (ec) throw std::runtime_error(path.string() + ": cannot create its folder: " + ec.message());
  }
  const fs::path tmp = path.string() + ".tmp-" + std::to_string(::getpid());
  {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path.string() + ": cannot open for writing (" + ErrnoText() + ")");
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) {
      const std::string why = ErrnoText();
      out.close();
      fs::remove(tmp, ec);
      throw std::runtime_error(path.string() + ": write failed (" + why + ")");
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);  // a failed rename leaves no temporary behind
    throw std::runtime_error(path.string() + ": cannot move the new file into place: " + ec.message());
  }
}

OutputPolicy::OutputPolicy(bool replace_any, std::vector<Input> inputs)
    : replace_any_(replace_any), inputs_(std::move(inputs)) {}

void OutputPolicy::RefuseOutputOverInputs(const std::string& out_option, const fs::path& target) const {
  if (target.empty()) return;
  const fs::path out = Resolved(target);
  for (const Input& input : inputs_) {
    if (input.path.empty()) continue;
    const fs::path in = Resolved(input.path);
    const char* relation = nullptr;
    const char* consequence = nullptr;
    if (in == out) {
      relation = "is";
      consequence = "replace it";
    } else if (IsWithin(in, out)) {
      relation = "contains";
      consequence = "replace the folder whole and delete it";
    } else if (input.folder && IsWithin(out, in)) {
      relation = "is inside";
      consequence = "change it";
    } else {
      continue;
    }
    throw std::invalid_argument(out_option + " " + Quoted(target) + " " + relation + " " + input.option + " " +
                                Quoted(input.path) + ", which this run reads: the output would " + consequence +
                                "; expected " + out_option + " outside every input");
  }
}

void OutputPolicy::CheckFolder(const std::string& out_option, const fs::path& target) const {
  if (target.empty()) throw std::invalid_argument(out_option + ": an output folder is required");
  const std::string name = WithoutTrailingSlash(target).filename().string();
  if (name.empty() || name == "." || name == "..") {
    throw std::invalid_argument(out_option + ": " + Quoted(target) + ": expected the name of a new or earlier output "
                                "folder, not '.', '..' or the root");
  }
  std::error_code ec;
  const fs::file_status status = fs::status(target, ec);
  if (fs::exists(status) && !fs::is_directory(status)) {
    throw std::invalid_argument(out_option + ": " + Quoted(target) + " exists and is not a folder");
  }
  RefuseOutputOverInputs(out_option, target);
  if (fs::is_directory(status)) {
    const bool empty = fs::is_empty(target, ec);
    if (ec) throw std::invalid_argument(out_option + ": " + Quoted(target) + ": cannot be read: " + ec.message());
    if (!empty && !fs::exists(target / StagedOutputDir::kOutputMarker, ec) && !replace_any_) {
      throw std::invalid_argument(out_option + ": " + Quoted(target) + " is a non-empty folder that is not an "
                                  "earlier robossis output; expected a new or empty folder (or --force to replace it "
                                  "whole)");
    }
  }
}

void OutputPolicy::CheckFile(const std::string& out_option, const fs::path& target) const {
  if (target.empty()) throw std::invalid_argument(out_option + ": an output file is required");
  const std::string name = target.filename().string();
  if (name.empty() || name == "." || name == "..") {
    throw std::invalid_argument(out_option + ": " + Quoted(target) + ": expected a file name, not a folder");
  }
  std::error_code ec;
  const fs::file_status status = fs::status(target, ec);
  if (fs::is_directory(status)) {
    throw std::invalid_argument(out_option + ": " + Quoted(target) + " is a folder; expected a file name");
  }
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    throw std::invalid_argument(out_option + ": " + Quoted(target) + " exists and is not a regular file (a device, "
                                "a pipe or a socket); expected a new file or an earlier output file");
  }
  RefuseOutputOverInputs(out_option, target);
}

void WriteOutputFile(const OutputPolicy& policy, const fs::path& path, std::string_view contents,
                     const std::string& out_option) {
  policy.CheckFile(out_option, path);
  RemoveLeftoversOfDeadRuns(path);
  try {
    WriteFileAtomically(path, contents);
  } catch (const std::exception& e) {
    throw std::runtime_error(out_option + ": " + e.what());
  }
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

StagedOutputDir::StagedOutputDir(fs::path target, const OutputPolicy& policy, std::string out_option)
    : target_(std::move(target)), option_(std::move(out_option)) {
  policy.CheckFolder(option_, target_);
  const fs::path clean = WithoutTrailingSlash(target_);
  RemoveLeftoversOfDeadRuns(clean);
  staging_ = clean.string() + ".partial-" + std::to_string(::getpid());
  cleanup_slot_ = RegisterStagingDir(staging_);  // before it exists: no moment when it exists unregistered
  std::error_code ec;
  fs::remove_all(staging_, ec);
  if (!ec) fs::create_directories(staging_, ec);
  if (ec) {
    UnregisterStagingDir(cleanup_slot_);
    throw std::runtime_error(option_ + ": " + Quoted(target_) + ": cannot create the staging folder " +
                             Quoted(staging_) + ": " + ec.message());
  }
}

StagedOutputDir::~StagedOutputDir() {
  UnregisterStagingDir(cleanup_slot_);
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

fs::path StagedOutputDir::Path(const std::string& relative) const {
  const fs::path p = staging_ / relative;
  if (p.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
    if (ec) throw std::runtime_error(option_ + ": cannot create " + Quoted(p.parent_path()) + ": " + ec.message());
  }
  return p;
}

void StagedOutputDir::Write(const std::string& relative, std::string_view contents) const {
  try {
    WriteFileAtomically(Path(relative), contents);
  } catch (const std::exception& e) {
    throw std::runtime_error(option_ + ": " + e.what());
  }
}

void StagedOutputDir::Commit() {
  Write(kOutputMarker, "written by robossis; the whole folder is replaced by the next run\n");
  const fs::path clean = WithoutTrailingSlash(target_);
  std::error_code ec;
  const auto fail = [&](const std::string& step) {
    throw std::runtime_error(option_ + ": " + Quoted(target_) + ": cannot " + step + ": " + ec.message() +
                             " (the earlier output, if any, is kept)");
  };
  if (fs::exists(clean, ec)) {
    // Move the old output aside first: the rename of the new one then cannot merge, and a crash in between leaves
    // the old output in `.old-PID`, which the next run removes.
    const fs::path aside = clean.string() + ".old-" + std::to_string(::getpid());
    fs::remove_all(aside, ec);
    fs::rename(clean, aside, ec);
    if (ec) fail("move the earlier output aside");
    fs::rename(staging_, clean, ec);
    if (ec) {
      std::error_code ignored;
      fs::rename(aside, clean, ignored);  // put the earlier output back
      fail("move the new output into place");
    }
    fs::remove_all(aside, ec);
  } else {
    if (clean.has_parent_path()) fs::create_directories(clean.parent_path(), ec);
    if (!ec) fs::rename(staging_, clean, ec);
    if (ec) fail("move the new output into place");
  }
  committed_ = true;
}

}  // namespace robossis
