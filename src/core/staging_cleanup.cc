#include "src/core/staging_cleanup.h"

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>

namespace robossis {

namespace {

struct StagingSlot {
  std::atomic<bool> used{false};
  char path[PATH_MAX] = {};
};
StagingSlot g_slots[kMaxRegisteredStagingDirs];
std::mutex g_register_mutex;  // registration only; the handler reads `used` and `path`

// Depth bound of the removal [assumed]: outputs are a few folders deep; deeper trees are left to the next run.
constexpr int kMaxDepth = 16;

bool IsDotOrDotDot(const char* name) {
  return name[0] == '.' && (name[1] == '\0' || (name[1] == '.' && name[2] == '\0'));
}

// Removes `name` (relative to parent_fd) and everything under it. Async-signal-safe: system calls and a buffer on
// the stack only.
void RemoveTree(int parent_fd, const char* name, int depth) noexcept {
  if (::unlinkat(parent_fd, name, 0) == 0 || errno != EISDIR || depth > kMaxDepth) return;
  const int fd = ::openat(parent_fd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  // Entries are removed while the folder is read: read it again from the start until nothing but . and .. is left.
  for (bool removed_any = true; removed_any;) {
    removed_any = false;
    if (::lseek(fd, 0, SEEK_SET) != 0) break;
    alignas(dirent64) char buffer[4096];
    for (ssize_t n; (n = ::getdents64(fd, buffer, sizeof buffer)) > 0;) {
      for (ssize_t offset = 0; offset < n;) {
        const auto* entry = reinterpret_cast<const dirent64*>(buffer + offset);
        offset += entry->d_reclen;
        if (IsDotOrDotDot(entry->d_name)) continue;
        RemoveTree(fd, entry->d_name, depth + 1);
        removed_any = true;
      }
    }
  }
  ::close(fd);
  ::unlinkat(parent_fd, name, AT_REMOVEDIR);
}

void OnTerminatingSignal(int signal_number) {
  const int saved_errno = errno;
  for (StagingSlot& slot : g_slots) {
    if (slot.used.load(std::memory_order_acquire)) RemoveTree(AT_FDCWD, slot.path, 0);
  }
  errno = saved_errno;
  // SA_RESETHAND restored the default action: the process ends by this signal, as it would have.
  ::raise(signal_number);
}

void InstallWhereDefault(int signal_number) {
  struct sigaction current {};
  if (::sigaction(signal_number, nullptr, &current) != 0 || current.sa_handler != SIG_DFL) return;
  struct sigaction action {};
  action.sa_handler = OnTerminatingSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  ::sigaction(signal_number, &action, nullptr);
}

}  // namespace

int RegisterStagingDir(const std::filesystem::path& dir) {
  static std::once_flag installed;
  std::call_once(installed, [] {
    InstallWhereDefault(SIGINT);
    InstallWhereDefault(SIGTERM);
  });
  const std::string path = std::filesystem::absolute(dir).string();
  if (path.size() >= PATH_MAX) return -1;
  const std::lock_guard<std::mutex> lock(g_register_mutex);
  for (int i = 0; i < kMaxRegisteredStagingDirs; ++i) {
    StagingSlot& slot = g_slots[i];
    if (slot.used.load(std::memory_order_relaxed)) continue;
    std::memcpy(slot.path, path.c_str(), path.size() + 1);  // written before it is published to the handler
    slot.used.store(true, std::memory_order_release);
    return i;
  }
  return -1;
}

void UnregisterStagingDir(int slot) noexcept {
  if (slot < 0 || slot >= kMaxRegisteredStagingDirs) return;
  const std::lock_guard<std::mutex> lock(g_register_mutex);
  g_slots[slot].used.store(false, std::memory_order_release);
}

}  // namespace robossis
