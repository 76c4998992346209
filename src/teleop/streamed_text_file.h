#pragma once
// A text file written as a run goes (the session's CSVs): the text is handed to the kernel in chunks, so that a run
// of any length keeps at most one chunk of it in memory. Not real-time (the logger thread writes it).

#include <cstddef>
#include <filesystem>
#include <string>

namespace robossis::teleop {

// [assumed] Text handed to the kernel once this much is pending: 256 KiB is ~1000 leader.csv rows (1 s at 1 kHz),
// few write calls, little memory.
inline constexpr std::size_t kStreamedTextChunkBytes = std::size_t{256} << 10;

class StreamedTextFile {
 public:
  // Creates (truncates) the file. Throws std::runtime_error naming it.
  explicit StreamedTextFile(const std::filesystem::path& file);
  ~StreamedTextFile();
  StreamedTextFile(const StreamedTextFile&) = delete;
  StreamedTextFile& operator=(const StreamedTextFile&) = delete;

  // Takes `text` (leaves it empty, its capacity kept); writes once kStreamedTextChunkBytes are pending. Throws
  // std::runtime_error naming the file on a write error (a full disk).
  void Append(std::string& text);
  // Writes everything pending. Throws as Append.
  void Flush();
  std::size_t pending_bytes() const { return pending_.size(); }

 private:
  std::filesystem::path file_;
  int fd_ = -1;
  std::string pending_;
};

}  // namespace robossis::teleop
