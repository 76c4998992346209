#pragma once
// A UDP relay that injects network faults between two DDS participants on loopback (this machine kind has no netem
// qdisc, so faults are injected in a layer the project controls). Each route listens on one address:port and
// forwards to another; the participants advertise the relay's addresses (LinkOptions::external_address) so that all
// their traffic crosses it. Faults: loss, duplicates, reordering (a packet held back behind the next one), delay
// spikes (the route stalls for 10–200 ms and then releases what it held, in order), and the replay of captured
// packets. Test and bench equipment, not a real-time component.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace robossis::link {

struct RelayRoute {
  std::string listen_address;  // e.g. 127.0.0.2
  std::uint16_t listen_port = 0;
  std::string forward_address;  // e.g. 127.0.0.1
  std::uint16_t forward_port = 0;
};

struct RelayFaults {
  double loss = 0.0;              // probability a packet is dropped
  double duplicate = 0.0;         // probability a packet is sent twice
  double reorder = 0.0;           // probability a packet is held back and sent after the next one (≤ 5 ms)
  double spike_probability = 0.0; // probability per packet that a stall starts
  double spike_min_s = 0.010;     // stall duration, uniform in [min, max]
  double spike_max_s = 0.200;
};

struct RelayStatistics {
  std::uint64_t received = 0, forwarded = 0, dropped = 0, duplicated = 0, reordered = 0, delayed = 0, spikes = 0;
  std::uint64_t replayed = 0;
};

class FaultRelay {
 public:
  // Binds every route (throws std::runtime_error naming the address:port) and starts the relay thread.
  FaultRelay(std::vector<RelayRoute> routes, std::uint64_t seed);
  ~FaultRelay();
  FaultRelay(const FaultRelay&) = delete;
  FaultRelay& operator=(const FaultRelay&) = delete;

  void SetFaults(const RelayFaults& faults);
  // Starts (or stops) recording the packets of route `route`; Replay() sends every recorded packet again.
  void SetCapture(std::size_t route, bool on);
  std::size_t Replay();
  RelayStatistics Statistics() const;

 private:
  struct Pending;
  void Loop();
  std::vector<RelayRoute> routes_;
  std::vector<int> sockets_;
  int wake_fd_ = -1;
  std::uint64_t seed_;
  mutable std::mutex mutex_;  // faults, capture, statistics (the relay is not real-time)
  RelayFaults faults_;
  std::vector<bool> capture_;
  std::vector<std::pair<std::size_t, std::vector<std::uint8_t>>> captured_;
  RelayStatistics stats_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace robossis::link
