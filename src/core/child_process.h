#pragma once
// A child process the program starts and always reaps: `robossis teleop --link dds` runs the leader and the
// follower as two processes, the tests start and kill them. The destructor kills (SIGKILL) and reaps a child that is
// still running, so no process outlives its owner's scope.

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace robossis {

// How a child ended.
struct ChildExit {
  bool exited = false;  // normal exit (then `code`), else killed by `signal`
  int code = 0;
  int signal = 0;
  std::string Describe() const;  // "exit 0", "killed by signal 9 (Killed)"
};

class ChildProcess {
 public:
  // Starts `program` (a path, or a name looked up in PATH) with `args` (argv[1..]) in `working_dir` (empty: this
  // process's). Its stdin is /dev/null; its stdout and stderr go to `output` (created or truncated; empty:
  // inherited). Throws std::runtime_error naming the program.
  ChildProcess(const std::filesystem::path& program, const std::vector<std::string>& args,
               const std::filesystem::path& output = {}, const std::filesystem::path& working_dir = {});
  ~ChildProcess();
  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&&) = delete;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const noexcept { return pid_; }
  bool running();  // reaps the child if it has ended
  void Signal(int signal) noexcept;  // no effect once reaped
  // Waits up to `timeout` for the child to end; nullopt if it is still running.
  std::optional<ChildExit> WaitFor(std::chrono::milliseconds timeout);
  // Waits without limit.
  ChildExit Wait();

 private:
  pid_t pid_ = -1;
  std::optional<ChildExit> exit_;
};

// This program's own executable (/proc/self/exe), to start another of its subcommands.
std::filesystem::path SelfExecutable();

}  // namespace robossis
