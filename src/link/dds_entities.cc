#include "src/link/dds_entities.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <mutex>
#include <stdexcept>

#include "robossis_link.h"
#include "src/core/rt/periodic_loop.h"

namespace robossis::link {

const char* TopicName(Topic topic) {
  switch (topic) {
    case Topic::kSetPoint: return "setpoint";
    case Topic::kStateCommand: return "state_command";
    case Topic::kMeasuredCp: return "measured_cp";
    case Topic::kMeasuredJs: return "measured_js";
    case Topic::kOperatingState: return "operating_state";
    case Topic::kEStop: return "estop";
  }
  return "?";
}

std::string WireTopicName(const LinkOptions& options, Topic topic) {
  ValidateTopicNamespace(options.topic_namespace);
  return "rt/" + options.topic_namespace + "/" + TopicName(topic);
}

namespace {
const dds_topic_descriptor_t* Descriptor(Topic topic) {
  switch (topic) {
    case Topic::kSetPoint: return &robossis_msgs_msg_dds__SetPoint__desc;
    case Topic::kStateCommand: return &robossis_msgs_msg_dds__StateCommand__desc;
    case Topic::kMeasuredCp: return &geometry_msgs_msg_dds__PoseStamped__desc;
    case Topic::kMeasuredJs: return &sensor_msgs_msg_dds__JointState__desc;
    case Topic::kOperatingState: return &robossis_msgs_msg_dds__OperatingState__desc;
    case Topic::kEStop: return &robossis_msgs_msg_dds__EStop__desc;
  }
  return nullptr;
}
dds_duration_t Seconds(double s) { return static_cast<dds_duration_t>(s * 1e9); }
}  // namespace

dds_qos_t* CreateTopicQos(Topic topic, const LinkTuning& tuning) {
  dds_qos_t* q = dds_create_qos();
  switch (topic) {
    case Topic::kSetPoint:
      // A 1 kHz stream: only the newest value matters and a repair would arrive after the next sample.
      dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
      dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
      dds_qset_deadline(q, Seconds(tuning.setpoint_deadline_s));
      dds_qset_liveliness(q, DDS_LIVELINESS_AUTOMATIC, Seconds(tuning.liveliness_lease_s));
      break;
    case Topic::kMeasuredCp:
    case Topic::kMeasuredJs:
      // Streams at the follower's status rate: newest value only, as for set-points.
      dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
      dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
      break;
    case Topic::kStateCommand:
      // Every command counts (an E-stop must not be lost); an old command must not act on a late joiner.
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, Seconds(0.1));
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 32);
      dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
      break;
    case Topic::kEStop:
      // A latched level, not a stream of commands: reliable; the newest sample of each writer is all a reader needs
      // (every sample engages), and a follower that joins later gets it at once (transient-local).
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, Seconds(0.1));
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
      dds_qset_durability(q, DDS_DURABILITY_TRANSIENT_LOCAL);
      break;
    case Topic::kOperatingState:
      // A late joiner (restarted leader, a panel) needs the last state at once.
      dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, Seconds(0.1));
      dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
      dds_qset_durability(q, DDS_DURABILITY_TRANSIENT_LOCAL);
      break;
  }
  return q;
}

namespace {
// Cyclone reports a refused handshake only in its log (no status or listener says why a remote participant was not
// matched), so the link keeps the last such line. Process-wide: the line's domain id is not set by the security
// plugins (it reads as garbage in 0.10.2), so a participant takes the lines logged since it was created. The sink
// writes every line to stderr as Cyclone's default sink does. Cyclone's threads call it, never a real-time loop.
struct HandshakeLog {
  std::mutex mutex;
  std::uint64_t count = 0;  // refused handshakes logged so far
  std::string last;
};
HandshakeLog& Handshakes() {
  static HandshakeLog log;
  return log;
}
void LogSink(void*, const dds_log_data_t* data) {
  std::fwrite(data->message, 1, data->size, stderr);
  if (data->size == 0 || data->message[data->size - 1] != '\n') std::fputc('\n', stderr);
  std::fflush(stderr);
  std::string text(data->message, data->size);
  if (text.find("handshake") == std::string::npos || text.find("fail") == std::string::npos) return;
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  HandshakeLog& log = Handshakes();
  const std::lock_guard<std::mutex> lock(log.mutex);
  ++log.count;
  log.last = text;
}
void InstallLogSink() {
  static std::once_flag once;
  std::call_once(once, [] { dds_set_log_sink(&LogSink, nullptr); });
}
std::uint64_t HandshakeFailuresSoFar() {
  HandshakeLog& log = Handshakes();
  const std::lock_guard<std::mutex> lock(log.mutex);
  return log.count;
}
}  // namespace

dds_entity_t Check(dds_entity_t rc, const char* what) {
  if (rc < 0) throw std::runtime_error(std::string(what) + ": " + dds_strretcode(rc));
  return rc;
}

int NextLocalDomainId() {
  // Local ids only name the domain inside this process; the wire uses LinkOptions::domain_id.
  static std::atomic<int> next{0};
  return 100 + next.fetch_add(1) % 130;
}

DdsParticipant::DdsParticipant(const LinkOptions& options) : options_(options) {
  const auto properties = SecurityProperties(options);  // throws on missing credentials, before any DDS entity
  InstallLogSink();
  handshake_failures_before_ = HandshakeFailuresSoFar();
  const int local = NextLocalDomainId();
  const std::string config = BuildCycloneConfig(options, local, rt::FifoPermitted(rt::kLinkThreadFifoPriority));
  domain_ = Check(dds_create_domain(static_cast<dds_domainid_t>(local), config.c_str()), "DDS domain");
  dds_qos_t* qos = dds_create_qos();
  for (const auto& [name, value] : properties) dds_qset_prop(qos, name.c_str(), value.c_str());
  participant_ = dds_create_participant(static_cast<dds_domainid_t>(local), qos, nullptr);
  dds_delete_qos(qos);
  if (participant_ < 0) {
    const dds_entity_t rc = participant_;
    dds_delete(domain_);
    Check(rc, options.insecure ? "DDS participant" : "DDS participant (the credentials were refused)");
  }
}

DdsParticipant::~DdsParticipant() {
  if (participant_ > 0) dds_delete(participant_);
  if (domain_ > 0) dds_delete(domain_);
}

std::string DdsParticipant::HandshakeFailure() const {
  HandshakeLog& log = Handshakes();
  const std::lock_guard<std::mutex> lock(log.mutex);
  return log.count > handshake_failures_before_ ? log.last : std::string();
}

dds_entity_t DdsParticipant::TopicHandle(Topic topic) {
  dds_entity_t& t = topics_[static_cast<int>(topic)];
  if (t <= 0) {
    t = dds_create_topic(participant_, Descriptor(topic), WireTopicName(options_, topic).c_str(), nullptr, nullptr);
  }
  return t;
}

dds_entity_t DdsParticipant::Create(Topic topic, bool writer) {
  const std::string name = WireTopicName(options_, topic);
  dds_entity_t e = TopicHandle(topic);
  if (e > 0) {
    dds_qos_t* q = CreateTopicQos(topic, options_.tuning);
    e = writer ? dds_create_writer(participant_, e, q, nullptr) : dds_create_reader(participant_, e, q, nullptr);
    dds_delete_qos(q);
  }
  Check(e, ((writer ? "writer " : "reader ") + name).c_str());
  if (!writer) Check(dds_set_status_mask(e, DDS_DATA_AVAILABLE_STATUS), "reader status mask");
  return e;
}

dds_entity_t DdsParticipant::CreateWriter(Topic topic) { return Create(topic, true); }
dds_entity_t DdsParticipant::CreateReader(Topic topic) { return Create(topic, false); }

WakeSignal::WakeSignal() : fd_(eventfd(0, EFD_CLOEXEC)) {
  if (fd_ < 0) throw std::runtime_error("eventfd failed");
}
WakeSignal::~WakeSignal() { close(fd_); }
void WakeSignal::Notify() noexcept {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = write(fd_, &one, sizeof one);
}
void WakeSignal::Wait() noexcept {
  std::uint64_t value = 0;
  while (read(fd_, &value, sizeof value) < 0 && errno == EINTR) {
  }
}

}  // namespace robossis::link
