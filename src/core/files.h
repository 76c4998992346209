#pragma once
// Output files that are never left half-written: each file is written beside its target and renamed into place,
// and a folder of outputs is staged and moved in only when the whole job succeeded.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace robossis {

// Writes `contents` to `path` atomically (temporary file `path.tmp-PID` in the same folder, then rename). Throws on
// failure. A command writing one file at a path the user chose calls RemoveLeftoversOfDeadRuns(path) first.
void WriteFileAtomically(const std::filesystem::path& path, std::string_view contents);

// The one way the project reads an input file. It opens `file` without blocking (a FIFO cannot hang it), refuses
// anything but a regular file (a directory, /dev/zero, a pipe, a socket) and a file over `max_bytes` before
// reading a byte, and reads the whole file. Throws std::runtime_error naming the file and `what` ("YAML config
// file"): missing, not a regular file, larger than the bound, or unreadable. Never a library's raw text.
std::string ReadBoundedFile(const std::filesystem::path& file, std::uintmax_t max_bytes, const std::string& what);

// The size bound of a file read without a bound of its own kind (ReadTextFile): above every file the project
// writes or reads (a boundary-atlas slice, a log of a child process), far below the machine's memory.
inline constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t{256} << 20;  // 256 MiB

// Reads a whole file through ReadBoundedFile with kMaxTextFileBytes.
std::string ReadTextFile(const std::filesystem::path& path);

// Removes the siblings of `path` named `NAME.SUFFIX-PID` (SUFFIX: partial, old, tmp) whose process is gone.
void RemoveLeftoversOfDeadRuns(const std::filesystem::path& path);

// A folder of outputs built in a staging folder beside the target (`DIR.partial-PID`). Commit() replaces the
// target whole with the staging folder (the old target is moved aside and removed), so no stale file of an earlier
// run is left beside the new ones. If Commit() is never reached (an error, an exception), the destructor removes
// the staging folder, so the target never holds a partial result.
//
// The target may be missing, empty, or an earlier output (it holds the kOutputMarker file that Commit() writes);
// any other non-empty folder is refused unless `replace_any` (the CLI's --force), so a mistyped --out never
// deletes someone's data. Staging, aside and temporary files (`.partial-PID`, `.old-PID`, `.tmp-PID`) left by
// runs that died are removed when the next run starts.
class StagedOutputDir {
 public:
  static constexpr const char* kOutputMarker = ".robossis-output";

  explicit StagedOutputDir(std::filesystem::path target, bool replace_any = false);
  ~StagedOutputDir();
  StagedOutputDir(const StagedOutputDir&) = delete;
  StagedOutputDir& operator=(const StagedOutputDir&) = delete;

  // Where to write now: a path inside the staging folder (sub-folders are created).
  std::filesystem::path Path(const std::string& relative) const;
  void Write(const std::string& relative, std::string_view contents) const;
  void Commit();

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& staging() const { return staging_; }

 private:
  std::filesystem::path target_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace robossis
