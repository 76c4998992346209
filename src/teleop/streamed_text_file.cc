#include "src/teleop/streamed_text_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

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
  std::size_t done = 0;
  while (done < pending_.size()) {
    const ssize_t n = ::write(fd_, pending_.data() + done, pending_.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      pending_.erase(0, done);
      throw std::runtime_error(file_.string() + ": write failed: " + std::strerror(errno));
    }
    done += static_cast<std::size_t>(n);
  }
  pending_.clear();
}

}  // namespace robossis::teleop
