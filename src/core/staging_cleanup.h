#pragma once
// The staging folders of outputs being written (StagedOutputDir's `.partial-PID`) are removed when the process is
// interrupted (SIGINT, Ctrl-C) or asked to end (SIGTERM), so that an interrupted run leaves nothing behind. The
// process then ends by the same signal, as it would have without the clean-up.
//
// The handler is installed only where the signal's disposition is still the default: a command with its own
// handling (the real-time units end their run cleanly and commit or remove their output themselves) keeps it.
// The removal runs inside the signal handler, with async-signal-safe system calls only (openat, getdents64,
// unlinkat): no allocation, no lock.

#include <filesystem>

namespace robossis {

// At most this many staging folders are registered at once [assumed: a command writes one or two outputs].
inline constexpr int kMaxRegisteredStagingDirs = 8;

// Registers `dir` for removal on SIGINT/SIGTERM (installing the handler the first time); returns a slot for
// UnregisterStagingDir, or -1 if every slot is taken or the path is longer than PATH_MAX (the folder is then only
// removed by the next run, as a leftover of a dead one).
int RegisterStagingDir(const std::filesystem::path& dir);
void UnregisterStagingDir(int slot) noexcept;

}  // namespace robossis
