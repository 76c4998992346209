#include "tests/drivers/hal_session.h"

#include <fcntl.h>
#include <pwd.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace robossis::testing {
namespace {

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs a shell command; returns its exit status and output.
int Run(const std::string& command, std::string* output) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("cannot run '" + command + "'");
  std::array<char, 4096> buf;
  std::string out;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  const int status = pclose(pipe);
  if (output) *output = out;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// halrun -I reads its standard input only once the file is done: a signal made from there marks the end of the
// file (its `start` included; a thread exists from its `loadrt threads` line on, long before the file's signals on a
// loaded machine). Removed again once seen, so the session holds only what the file made.
constexpr const char* kReadySignal = "robossis-hal-session-ready";

}  // namespace

void HalSession::PrepareEnvironment() {
  if (geteuid() != 0 || std::getenv("RTAPI_UID") != nullptr) return;
  const passwd* nobody = getpwnam("nobody");
  if (nobody == nullptr) throw std::runtime_error("running as root and no 'nobody' user for RTAPI_UID");
  const std::filesystem::path fifo_dir = std::filesystem::temp_directory_path() / "robossis-rtapi";
  std::filesystem::create_directories(fifo_dir);
  chmod(fifo_dir.c_str(), 0777);
  setenv("RTAPI_UID", std::to_string(nobody->pw_uid).c_str(), 1);
  setenv("RTAPI_FIFO_PATH", (fifo_dir / "rtapi_fifo").c_str(), 1);
}

bool HalSession::AnyComponentLoaded() {
  std::string out;
  if (Run("halcmd list comp", &out) != 0) return false;
  std::istringstream words(out);
  std::string w;
  while (words >> w) {
    if (w.rfind("halcmd", 0) != 0) return true;
  }
  return false;
}

std::string HalSession::Halcmd(const std::string& args) {
  std::string out;
  if (Run("halcmd " + args, &out) != 0) throw std::runtime_error("halcmd " + args + " failed: " + out);
  return out;
}

double HalSession::GetNumber(const std::string& name) {
  const std::string out = Halcmd("getp " + name);
  try {
    return std::stod(out);
  } catch (const std::exception&) {
    throw std::runtime_error("halcmd getp " + name + ": not a number: " + out);
  }
}

bool HalSession::GetBit(const std::string& name) {
  const std::string out = Halcmd("getp " + name);
  if (out.rfind("TRUE", 0) == 0) return true;
  if (out.rfind("FALSE", 0) == 0) return false;
  throw std::runtime_error("halcmd getp " + name + ": not a bit: " + out);
}

std::map<std::string, std::string> HalSession::PinValues(const std::string& prefix) {
  // Lines of `show pin`: owner, type, direction, value, name [, "==>" or "<==" signal].
  std::map<std::string, std::string> values;
  std::istringstream lines(Halcmd("show pin " + prefix));
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string owner, type, dir, value, name;
    if (words >> owner >> type >> dir >> value >> name && name.rfind(prefix, 0) == 0) values[name] = value;
  }
  return values;
}

HalSession::HalSession(const std::filesystem::path& hal_file) {
  PrepareEnvironment();
  // A session left by a test binary that crashed would block this one: clear it.
  if (AnyComponentLoaded()) Run("halrun -U", nullptr);
  log_ = std::filesystem::temp_directory_path() / ("robossis-halrun-" + std::to_string(getpid()) + ".log");
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe() failed");
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork() failed");
  if (pid == 0) {
    dup2(fds[0], STDIN_FILENO);
    const int log = open(log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(log, STDOUT_FILENO);
    dup2(log, STDERR_FILENO);
    close(fds[0]);
    close(fds[1]);
    execlp("halrun", "halrun", "-I", "-f", hal_file.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  close(fds[0]);
  stdin_fd_ = fds[1];
  pid_ = pid;
  const std::string ready = std::string("newsig ") + kReadySignal + " bit\n";
  if (write(stdin_fd_, ready.data(), ready.size()) != static_cast<ssize_t>(ready.size())) {
    Stop();
    throw std::runtime_error("cannot write to halrun's standard input");
  }
  for (int i = 0; i < 200; ++i) {
    std::string out;
    if (Run("halcmd list sig", &out) == 0 && out.find(kReadySignal) != std::string::npos) {
      Halcmd(std::string("delsig ") + kReadySignal);
      // halcmd names a failed line "FILE:LINE: ..." and goes on to its standard input.
      const std::string log = ReadFile(log_);
      if (log.find(hal_file.string() + ":") == std::string::npos) return;
      Stop();
      throw std::runtime_error("halrun -f " + hal_file.string() + " failed: " + log);
    }
    int status;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  const std::string log = ReadFile(log_);
  Stop();
  throw std::runtime_error("halrun -f " + hal_file.string() + " did not start: " + log);
}

HalSession::~HalSession() { Stop(); }

void HalSession::Stop() noexcept {
  if (stdin_fd_ >= 0) {
    close(stdin_fd_);  // halcmd -I sees end of input; halrun then unloads everything
    stdin_fd_ = -1;
  }
  if (pid_ > 0) {
    int status = 0;
    bool exited = false;
    for (int i = 0; i < 100 && !exited; ++i) {
      exited = waitpid(pid_, &status, WNOHANG) == pid_;
      if (!exited) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (!exited) {
      kill(pid_, SIGTERM);
      waitpid(pid_, &status, 0);
    }
    pid_ = -1;
  }
  try {
    if (AnyComponentLoaded()) Run("halrun -U", nullptr);
  } catch (const std::exception&) {
  }
  std::error_code ec;
  std::filesystem::remove(log_, ec);
}

}  // namespace robossis::testing
