#include "src/link/fault_relay.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <deque>
#include <map>
#include <random>
#include <stdexcept>

namespace robossis::link {

namespace {
using Clock = std::chrono::steady_clock;

sockaddr_in Address(const std::string& ip, std::uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  if (inet_pton(AF_INET, ip.c_str(), &a.sin_addr) != 1) throw std::runtime_error("relay: bad address '" + ip + "'");
  return a;
}
}  // namespace

FaultRelay::FaultRelay(std::vector<RelayRoute> routes, std::uint64_t seed)
    : routes_(std::move(routes)), seed_(seed), capture_(routes_.size(), false) {
  for (const auto& r : routes_) {
    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    const sockaddr_in a = Address(r.listen_address, r.listen_port);
    if (fd < 0 || bind(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
      if (fd >= 0) close(fd);
      for (int s : sockets_) close(s);
      throw std::runtime_error("relay: cannot bind " + r.listen_address + ":" + std::to_string(r.listen_port) + ": " +
                               std::strerror(errno));
    }
    sockets_.push_back(fd);
  }
  wake_fd_ = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  thread_ = std::thread([this] { Loop(); });
}

FaultRelay::~FaultRelay() {
  stop_.store(true);
  const std::uint64_t one = 1;
  [[maybe_unused]] auto n = write(wake_fd_, &one, sizeof one);
  thread_.join();
  for (int s : sockets_) close(s);
  close(wake_fd_);
}

void FaultRelay::SetFaults(const RelayFaults& faults) {
  std::lock_guard lock(mutex_);
  faults_ = faults;
}

void FaultRelay::SetCapture(std::size_t route, bool on) {
  std::lock_guard lock(mutex_);
  capture_.at(route) = on;
}

std::size_t FaultRelay::Replay() {
  std::lock_guard lock(mutex_);
  for (const auto& [route, bytes] : captured_) {
    const sockaddr_in to = Address(routes_[route].forward_address, routes_[route].forward_port);
    sendto(sockets_[route], bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
    ++stats_.replayed;
  }
  return captured_.size();
}

RelayStatistics FaultRelay::Statistics() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

struct FaultRelay::Pending {
  Clock::time_point due;
  std::size_t route;
  std::vector<std::uint8_t> bytes;
};

void FaultRelay::Loop() {
  std::mt19937_64 rng(seed_);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<sockaddr_in> to;
  for (const auto& r : routes_) to.push_back(Address(r.forward_address, r.forward_port));
  std::multimap<Clock::time_point, Pending> queue;          // packets to send later, by due time
  std::vector<Clock::time_point> stall_until(routes_.size());  // a delay spike holds the route until then
  std::vector<std::deque<Pending>> held(routes_.size());     // reordering: held behind the next packet
  std::vector<pollfd> fds;
  for (int s : sockets_) fds.push_back({s, POLLIN, 0});
  fds.push_back({wake_fd_, POLLIN, 0});
  std::vector<std::uint8_t> buf(65536);
  auto send = [&](const Pending& p) {
    sendto(sockets_[p.route], p.bytes.data(), p.bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to[p.route]),
           sizeof to[p.route]);
    std::lock_guard lock(mutex_);
    ++stats_.forwarded;
  };
  while (!stop_.load()) {
    const auto now = Clock::now();
    int timeout_ms = 100;
    if (!queue.empty()) {
      const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(queue.begin()->first - now).count();
      timeout_ms = static_cast<int>(std::max<long long>(0, std::min<long long>(wait + 1, 100)));
    }
    poll(fds.data(), fds.size(), timeout_ms);
    for (std::size_t r = 0; r < sockets_.size(); ++r) {
      if (!(fds[r].revents & POLLIN)) continue;
      for (;;) {
        const ssize_t n = recv(sockets_[r], buf.data(), buf.size(), MSG_DONTWAIT);
        if (n <= 0) break;
        const auto t = Clock::now();
        RelayFaults f;
        {
          std::lock_guard lock(mutex_);
          f = faults_;
          ++stats_.received;
          if (capture_[r]) captured_.emplace_back(r, std::vector<std::uint8_t>(buf.begin(), buf.begin() + n));
        }
        Pending p{t, r, std::vector<std::uint8_t>(buf.begin(), buf.begin() + n)};
        if (u(rng) < f.loss) {
          std::lock_guard lock(mutex_);
          ++stats_.dropped;
          continue;
        }
        if (t >= stall_until[r] && u(rng) < f.spike_probability) {
          const double d = f.spike_min_s + (f.spike_max_s - f.spike_min_s) * u(rng);
          stall_until[r] = t + std::chrono::microseconds(static_cast<long long>(d * 1e6));
          std::lock_guard lock(mutex_);
          ++stats_.spikes;
        }
        if (t < stall_until[r]) {
          p.due = stall_until[r];
          std::lock_guard lock(mutex_);
          ++stats_.delayed;
        }
        const bool dup = u(rng) < f.duplicate;
        if (u(rng) < f.reorder && held[r].empty()) {
          p.due = std::max(p.due, t + std::chrono::milliseconds(5));  // released by the next packet, or after 5 ms
          held[r].push_back(p);
          std::lock_guard lock(mutex_);
          ++stats_.reordered;
          continue;
        }
        queue.emplace(p.due, p);
        if (dup) {
          queue.emplace(p.due, p);
          std::lock_guard lock(mutex_);
          ++stats_.duplicated;
        }
        while (!held[r].empty()) {  // the held packet goes after this one
          Pending h = held[r].front();
          held[r].pop_front();
          h.due = p.due;
          queue.emplace(p.due + std::chrono::microseconds(1), h);
        }
      }
    }
    const auto t = Clock::now();
    for (std::size_t r = 0; r < held.size(); ++r) {
      while (!held[r].empty() && held[r].front().due <= t) {
        queue.emplace(t, held[r].front());
        held[r].pop_front();
      }
    }
    while (!queue.empty() && queue.begin()->first <= t) {
      send(queue.begin()->second);
      queue.erase(queue.begin());
    }
  }
}

}  // namespace robossis::link
