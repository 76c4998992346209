#pragma once
// The DDS side of a link end, shared by the leader and follower: one domain and participant per end (with its
// credentials), the topics of the topic map (src/link/README.md) and their QoS, a wake-up signal, and RAII for the
// C API's handles. Internal to the link library; constructed and destroyed off the real-time path.

#include <atomic>
#include <cstdint>
#include <string>

#include <dds/dds.h>

#include "src/link/link_options.h"

namespace robossis::link {

// The topics (names on the wire are rt/<namespace>/<name>).
enum class Topic { kSetPoint, kStateCommand, kMeasuredCp, kMeasuredJs, kOperatingState, kEStop };
inline constexpr int kNumTopics = 6;
const char* TopicName(Topic topic);  // "setpoint", "state_command", "measured_cp", ...
std::string WireTopicName(const LinkOptions& options, Topic topic);  // "rt/rsr/setpoint"

// The QoS of each topic (the README justifies them).
dds_qos_t* CreateTopicQos(Topic topic, const LinkTuning& tuning);

class DdsParticipant {
 public:
  // Creates this end's domain (mapped onto options.domain_id on the wire) and participant. Throws
  // std::runtime_error with Cyclone's reason (for example, credentials the plugins refuse).
  explicit DdsParticipant(const LinkOptions& options);
  ~DdsParticipant();
  DdsParticipant(const DdsParticipant&) = delete;
  DdsParticipant& operator=(const DdsParticipant&) = delete;

  dds_entity_t participant() const { return participant_; }
  // The last DDS Security handshake Cyclone refused since this participant was created ("" if none): its log line,
  // for example "Begin handshake reply failed: Certificate not valid: error: certificate signature failure; subject:
  // /C=US/O=Robossis/CN=follower(code: 200)" (the subject is the certificate it refused). Process-wide: with several
  // participants in one process (tests) it may be another's.
  std::string HandshakeFailure() const;
  dds_entity_t CreateWriter(Topic topic);
  dds_entity_t CreateReader(Topic topic);  // with DATA_AVAILABLE in its status mask

 private:
  dds_entity_t TopicHandle(Topic topic);  // < 0: Cyclone's return code
  dds_entity_t Create(Topic topic, bool writer);
  LinkOptions options_;
  std::uint64_t handshake_failures_before_ = 0;
  dds_entity_t domain_ = 0;
  dds_entity_t participant_ = 0;
  dds_entity_t topics_[kNumTopics] = {};
};

// A wake-up from a real-time thread to a link thread: an eventfd (a non-blocking write system call, no lock and no
// allocation in user space).
class WakeSignal {
 public:
  WakeSignal();
  ~WakeSignal();
  WakeSignal(const WakeSignal&) = delete;
  WakeSignal& operator=(const WakeSignal&) = delete;
  void Notify() noexcept;
  void Wait() noexcept;  // blocks until notified at least once since the last Wait

 private:
  int fd_ = -1;
};

// Takes every sample waiting on `reader` (loaned by Cyclone and returned after use: nothing is copied) and calls
// `apply(const Sample&)` for each one that carries data. True if any did. Link threads only (dds_take locks).
template <typename Sample, typename Apply>
bool TakeEach(dds_entity_t reader, Apply&& apply) {
  constexpr int kBatch = 16;
  void* samples[kBatch];
  dds_sample_info_t infos[kBatch];
  bool any = false;
  for (;;) {
    for (auto& s : samples) s = nullptr;  // null buffers: Cyclone lends its own
    const dds_return_t n = dds_take(reader, samples, infos, kBatch, kBatch);
    if (n <= 0) return any;
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      apply(*static_cast<const Sample*>(samples[i]));
      any = true;
    }
    dds_return_loan(reader, samples, n);
  }
}

// Throws std::runtime_error("what: <Cyclone's reason>") when rc < 0.
dds_entity_t Check(dds_entity_t rc, const char* what);

// A process-unique local domain id, so several link ends (tests) can live in one process.
int NextLocalDomainId();

}  // namespace robossis::link
