#pragma once
// Output files that are never left half-written: each file is written beside its target and renamed into place,
// and a folder of outputs is staged and moved in only when the whole job succeeded.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace robossis {

// Writes `contents` to `path` atomically (temporary file `path.tmp-PID` in the same folder, then rename; the
// temporary is removed if either step fails). Throws std::runtime_error naming `path` and the reason. A file at a
// path the user chose goes through WriteOutputFile instead.
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

// What a command's output may replace: whether the user gave --force, and the paths the command reads. An output
// that is, contains or lies inside one of those inputs would replace (delete) or change what the run reads, so it
// is refused before any work starts, with an error naming both options. Every command gets its policy from one
// place (the command line's AppContext::Output) and hands it to StagedOutputDir or WriteOutputFile.
class OutputPolicy {
 public:
  struct Input {
    std::string option;  // "--hc", "LOG", "--data-dir": named in the error
    std::filesystem::path path;  // a file or folder the command reads; empty: not given (ignored)
    // The option names a folder (--atlas, --keys): an output inside it is refused too. A file option given a
    // folder is left to its reader's own error ("expected a regular file").
    bool folder = false;
  };

  OutputPolicy() = default;  // no --force, no inputs: a library's own folder
  OutputPolicy(bool replace_any, std::vector<Input> inputs);

  bool replace_any() const { return replace_any_; }
  const std::vector<Input>& inputs() const { return inputs_; }

  // Throws std::invalid_argument ("--out 'A' is the folder of --atlas 'A'...") if `target` is, contains or lies
  // inside an input. Paths are compared after resolving symbolic links, '.' and '..'.
  void RefuseOutputOverInputs(const std::string& out_option, const std::filesystem::path& target) const;
  // Every check of an output folder, before any work: a usable name, not a file, not a foreign non-empty folder
  // (unless --force), not over an input. Throws std::invalid_argument naming `out_option`.
  void CheckFolder(const std::string& out_option, const std::filesystem::path& target) const;
  // The same for a single output file: not a folder or a device, not over an input.
  void CheckFile(const std::string& out_option, const std::filesystem::path& target) const;

 private:
  bool replace_any_ = false;
  std::vector<Input> inputs_;
};

// Writes one output file the user named (`out_option`, e.g. "--out"): checks it with `policy` (CheckFile), removes
// the leftovers of runs that died (`FILE.tmp-PID`), then writes atomically, so the file is either the old one or
// the whole new one and no temporary is left when a step fails. Errors name the option and the path, never a
// library's raw text.
void WriteOutputFile(const OutputPolicy& policy, const std::filesystem::path& path, std::string_view contents,
                     const std::string& out_option = "--out");

// A folder of outputs built in a staging folder beside the target (`DIR.partial-PID`). Commit() replaces the
// target whole with the staging folder (the old target is moved aside and removed), so no stale file of an earlier
// run is left beside the new ones. If Commit() is never reached (an error, an exception), the destructor removes
// the staging folder, so the target never holds a partial result; so does an interrupt (SIGINT, SIGTERM: see
// staging_cleanup.h).
//
// The target may be missing, empty, or an earlier output (it holds the kOutputMarker file that Commit() writes);
// any other non-empty folder is refused unless the policy's replace_any (the CLI's --force), so a mistyped --out
// never deletes someone's data, and a target over one of the policy's inputs is always refused. Staging, aside and
// temporary files (`.partial-PID`, `.old-PID`, `.tmp-PID`) left by runs that died are removed when the next run
// starts. `out_option` names the target in every error ("--out", "keys init DIR").
class StagedOutputDir {
 public:
  static constexpr const char* kOutputMarker = ".robossis-output";

  explicit StagedOutputDir(std::filesystem::path target, const OutputPolicy& policy = {},
                           std::string out_option = "--out");
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
  std::string option_;
  std::filesystem::path staging_;
  int cleanup_slot_ = -1;  // staging_cleanup.h: removed on SIGINT/SIGTERM
  bool committed_ = false;
};

}  // namespace robossis
