#pragma once
// A network namespace made for a test (`ip netns add`, as root) and removed when the object dies. Code runs inside
// it on a thread that joins it (setns), so DDS participants and relays made there bind their sockets in it; their
// own threads inherit it. Nothing is ever configured outside the namespaces the test made.

#include <functional>
#include <string>

namespace robossis::link::testing {

// Runs a shell command; throws std::runtime_error with the command if it fails.
void Shell(const std::string& command);

class NetNamespace {
 public:
  explicit NetNamespace(std::string name);
  ~NetNamespace();
  NetNamespace(const NetNamespace&) = delete;
  NetNamespace& operator=(const NetNamespace&) = delete;

  const std::string& name() const { return name_; }
  // Runs `f` on a thread inside this namespace and waits for it; rethrows what it threw.
  void Run(const std::function<void()>& f) const;

 private:
  std::string name_;
};

// True if this process may make namespaces and veth pairs (tried once with a probe namespace).
bool CanMakeNamespaces();

}  // namespace robossis::link::testing
