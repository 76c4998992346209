#pragma once
// Runs the `robossis` binary as a user would, for the command-line tests. The test target defines
// ROBOSSIS_BINARY (the path of the built binary) and depends on the `robossis` target.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#ifndef ROBOSSIS_BINARY
#error "define ROBOSSIS_BINARY (the path of the robossis binary) for this test target"
#endif

namespace robossis::testing {

struct CommandRun {
  int exit_code = -1;
  std::string output;  // stdout, and stderr unless left out
};

// A shell command line: its stdout and exit code (-1 if it did not exit normally).
inline CommandRun RunShell(const std::string& command) {
  CommandRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe) != nullptr) run.output += buf.data();
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

// `robossis <args>` through the shell (so args may quote and redirect), its output and exit code. With
// with_stderr = false the output is stdout alone (e.g. to parse --json while progress goes to stderr).
inline CommandRun Robossis(const std::string& args, bool with_stderr = true) {
  return RunShell(std::string(ROBOSSIS_BINARY) + " " + args + (with_stderr ? " 2>&1" : " 2>/dev/null"));
}

}  // namespace robossis::testing
