#include "src/teleop/streamed_text_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "src/teleop/session_log.h"

namespace robossis::teleop {

StreamedTextFile::StreamedTextFile(const std::filesystem::path& file) : file_(file) {
  fd_ = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(file.string() + ": cannot create: " + std::strerror(errno));
  pending_.reserve(2 * kStreamedTextChunkBytes);
}

StreamedTextFile::~StreamedTextFile() {
  try {
    Flush();
  } catch (...) {
    // A destructor must not throw; the caller flushes explicitly to see errors.
  }
  if (fd_ >= 0) ::close(fd_);
}

void StreamedTextFile::Append(std::string& text) {
  pending_ += text;
  text.clear();
  if (pending_.size() >= kStreamedTextChunkBytes) Flush();
}

void StreamedTextFile::Flush() {
  WriteAll(fd_, pending_, file_.string() + ": write failed");
  pending_.clear();
}

}  // namespace robossis::teleop
