#include "tests/link/net_namespace.h"

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <thread>

namespace robossis::link::testing {

void Shell(const std::string& command) {
  if (std::system(command.c_str()) != 0) throw std::runtime_error("command failed: " + command);
}

bool CanMakeNamespaces() {
  if (geteuid() != 0) return false;
  // Try it: root in a container may still lack the right to make namespaces or veth pairs.
  const std::string probe = "rbs-probe-" + std::to_string(getpid());
  const bool ok = std::system(("ip netns add " + probe + " > /dev/null 2>&1 && ip -n " + probe +
                               " link add p0 type veth peer name p1 > /dev/null 2>&1").c_str()) == 0;
  std::system(("ip netns del " + probe + " > /dev/null 2>&1").c_str());
  return ok;
}

NetNamespace::NetNamespace(std::string name) : name_(std::move(name)) {
  std::system(("ip netns del " + name_ + " > /dev/null 2>&1").c_str());  // a leftover of a crashed run
  Shell("ip netns add " + name_);
  Shell("ip -n " + name_ + " link set lo up");
}

NetNamespace::~NetNamespace() { std::system(("ip netns del " + name_ + " > /dev/null 2>&1").c_str()); }

void NetNamespace::Run(const std::function<void()>& f) const {
  std::exception_ptr error;
  std::thread t([&] {
    try {
      const int fd = open(("/run/netns/" + name_).c_str(), O_RDONLY | O_CLOEXEC);
      if (fd < 0 || setns(fd, CLONE_NEWNET) != 0) throw std::runtime_error("cannot enter namespace " + name_);
      close(fd);
      f();
    } catch (...) {
      error = std::current_exception();
    }
  });
  t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace robossis::link::testing
