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

// Runs `halcmd -f FILE` with its output in `log`, without a pipe: the first `loadrt` starts rtapi_app, which keeps
// halcmd's output open for as long as HAL runs. Returns halcmd's exit status (-1 if it did not exit in time).
int RunHalFile(const std::filesystem::path& hal_file, const std::filesystem::path& log) {
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork() failed");
  if (pid == 0) {
    const int in = open("/dev/null", O_RDONLY);
    const int out = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(in, STDIN_FILENO);
    dup2(out, STDOUT_FILENO);
    dup2(out, STDERR_FILENO);
    execlp("halcmd", "halcmd", "-f", hal_file.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  for (int i = 0; i < 600; ++i) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

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
  // What halrun does, without its interactive shell. Nothing polls HAL while the file loads: a halcmd started then
  // can race the loading halcmd for HAL's shared memory, and the file does not load at all.
  Stop();  // a session left by a test binary that crashed would block this one
  log_ = std::filesystem::temp_directory_path() / ("robossis-halcmd-" + std::to_string(getpid()) + ".log");
  if (RunHalFile(hal_file, log_) == 0) return;
  const std::string log = ReadFile(log_);
  Stop();
  throw std::runtime_error("halcmd -f " + hal_file.string() + " failed: " + log);
}

HalSession::~HalSession() { Stop(); }

void HalSession::Stop() noexcept {
  try {
    Run("halrun -U", nullptr);  // stops HAL's threads, unloads every component, ends rtapi_app
  } catch (const std::exception&) {
  }
  if (!log_.empty()) {
    std::error_code ec;
    std::filesystem::remove(log_, ec);
  }
}

}  // namespace robossis::testing
