#pragma once
// A LinuxCNC HAL session for the tests: loads FILE with `halcmd -f FILE` (HAL stays up after halcmd exits), runs
// halcmd, and always stops it again (`halrun -U`, before and after). As root, HAL needs RTAPI_UID (an unprivileged
// uid: the `nobody` account) and RTAPI_FIFO_PATH (a folder that uid can write): the session sets both.

#include <filesystem>
#include <map>
#include <string>

namespace robossis::testing {

class HalSession {
 public:
  // Throws std::runtime_error with halcmd's output if the file does not load, and leaves no HAL running.
  explicit HalSession(const std::filesystem::path& hal_file);
  ~HalSession();
  HalSession(const HalSession&) = delete;
  HalSession& operator=(const HalSession&) = delete;

  // Runs `halcmd ARGS`; returns its output (stdout and stderr). Throws if halcmd fails.
  static std::string Halcmd(const std::string& args);
  // `halcmd getp NAME` as a number / a bit.
  static double GetNumber(const std::string& name);
  static bool GetBit(const std::string& name);
  // Every pin whose name starts with `prefix`, name -> value as halcmd prints it, from one `halcmd show pin`.
  static std::map<std::string, std::string> PinValues(const std::string& prefix);
  // Sets RTAPI_UID/RTAPI_FIFO_PATH in this process when running as root (idempotent).
  static void PrepareEnvironment();

 private:
  void Stop() noexcept;

  std::filesystem::path log_;
};

}  // namespace robossis::testing
