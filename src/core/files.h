#pragma once
// Output files that are never left half-written: each file is written beside its target and renamed into place,
// and a folder of outputs is staged and moved in only when the whole job succeeded.

#include <filesystem>
#include <string>
#include <string_view>

namespace robossis {

// Writes `contents` to `path` atomically (temporary file in the same folder, then rename). Throws on failure.
void WriteFileAtomically(const std::filesystem::path& path, std::string_view contents);

// Reads a whole text file; throws std::runtime_error naming the file.
std::string ReadTextFile(const std::filesystem::path& path);

// A folder of outputs built in a staging folder beside the target (`DIR.partial-PID`). Commit() moves every file
// into the target (created if needed; same-named files are replaced). If Commit() is never reached (an error, an
// exception), the destructor removes the staging folder, so the target never holds a partial result.
class StagedOutputDir {
 public:
  explicit StagedOutputDir(std::filesystem::path target);
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
