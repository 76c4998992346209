// What a ROS 2 tool beside the robot sees, checked at the wire level without ROS 2 installed. A DDS participant that
// knows only ROS 2's upstream message definitions (ros2_idl/, compiled by idlc with no type information, registering
// the type names rmw_cyclonedds_cpp registers) reads the measured_cp and measured_js of a `robossis follower` process
// on a domain of this test process: insecure, and with the observer's credentials of `robossis keys init` given as
// Cyclone's security configuration (the CYCLONEDDS_URI form src/link/README.md documents). The same participant
// creates the topics every ROS 2 node creates. This test links nothing that holds the link's own IDL
// (src/link/idl): a type name, layout, encoding or QoS that differs from ROS 2's fails here.
//
// The follower is a process the test starts and always stops (ChildProcess kills and reaps it on scope exit). No
// timing assertion: the waits only bound how long a broken link may take to fail.

#include <dds/dds.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "geometry_msgs/msg/PoseStamped.h"
#include "rcl_interfaces/msg/Log.h"
#include "rcl_interfaces/msg/ParameterEvent.h"
#include "rcl_interfaces/srv/GetParameters.h"
#include "rmw_dds_common/msg/ParticipantEntitiesInfo.h"
#include "sensor_msgs/msg/JointState.h"
#include "src/core/child_process.h"
#include "src/core/files.h"
#include "tests/support/scratch_dir.h"

namespace robossis {
namespace {

using namespace std::chrono_literals;

// The follower's topics and frame (src/link/README.md, topic map).
constexpr char kMeasuredCp[] = "rt/rsr/measured_cp";
constexpr char kMeasuredJs[] = "rt/rsr/measured_js";
constexpr char kFrameId[] = "rsr_fixed_ring";
const std::vector<std::string> kJointNames = {"theta1", "theta2", "theta3", "d1", "d2", "d3"};
// The home pose of data/config/rsr.yaml: p = (0, 0, 284) mm, R = I. The recorder back end stands there; 1 µm and
// 1e-9 cover its forward kinematics' rounding.
constexpr double kHomeZ = 0.284, kPositionTolerance = 1e-6, kQuaternionTolerance = 1e-9;
// Samples of each stream to decode: a few seconds of the follower's status.
constexpr int kSamples = 1000;

// A DDS domain of this process (as the other link tests: 1..200 by process id), so parallel tests never meet.
int Domain() { return 1 + static_cast<int>(getpid() % 200); }

std::string FileUri(const std::filesystem::path& p) { return "file:" + std::filesystem::absolute(p).string(); }

// Debian ships the DDS Security plugins outside the loader's path (libddsc0debian/); a ROS 2 install has them on it.
std::filesystem::path PluginDir() {
  for (const char* dir : {"/usr/lib/x86_64-linux-gnu/libddsc0debian", "/usr/lib/aarch64-linux-gnu/libddsc0debian"}) {
    if (std::filesystem::exists(std::filesystem::path(dir) / "libdds_security_auth.so")) return dir;
  }
  return {};
}

// The Cyclone configuration of a ROS 2 node on the follower's machine, as src/link/README.md gives it (loopback, the
// follower as unicast peer) and, with the observer's folder, its DDS Security section.
std::string CycloneConfig(const std::filesystem::path& observer) {
  std::string x = R"(<CycloneDDS><Domain Id="any"><General><Interfaces><NetworkInterface address="127.0.0.1"/>)"
                  R"(</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>)"
                  R"(<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>20</MaxAutoParticipantIndex>)"
                  R"(<Peers><Peer address="127.0.0.1"/></Peers></Discovery>)";
  if (!observer.empty()) {
    const std::string lib = PluginDir().empty() ? "lib" : PluginDir().string() + "/lib";
    auto library = [&](const std::string& name, const std::string& init, const std::string& fini) {
      return "<Library path=\"" + lib + name + ".so\" initFunction=\"" + init + "\" finalizeFunction=\"" + fini +
             "\"/>";
    };
    x += "<Security><Authentication>" +
         library("dds_security_auth", "init_authentication", "finalize_authentication") +
         "<IdentityCertificate>" + FileUri(observer / "observer_cert.pem") + "</IdentityCertificate>" +
         "<IdentityCA>" + FileUri(observer / "ca_cert.pem") + "</IdentityCA>" +
         "<PrivateKey>" + FileUri(observer / "observer_key.pem") + "</PrivateKey></Authentication>" +
         "<AccessControl>" + library("dds_security_ac", "init_access_control", "finalize_access_control") +
         "<PermissionsCA>" + FileUri(observer / "ca_cert.pem") + "</PermissionsCA>" +
         "<Governance>" + FileUri(observer / "governance.p7s") + "</Governance>" +
         "<Permissions>" + FileUri(observer / "observer_permissions.p7s") + "</Permissions></AccessControl>" +
         "<Cryptographic>" + library("dds_security_crypto", "init_crypto", "finalize_crypto") +
         "</Cryptographic></Security>";
  }
  return x + "</Domain></CycloneDDS>";
}

// The QoS rmw_cyclonedds_cpp gives a ROS 2 profile, with XCDR1 only (what it writes and reads).
struct Ros2Qos {
  bool reliable = true;
  bool transient_local = false;
  std::int32_t depth = 10;
};
constexpr Ros2Qos kSensorData{false, false, 5};  // rclcpp::SensorDataQoS: best effort, volatile, keep last 5
constexpr Ros2Qos kDefault{true, false, 10};     // rclcpp's default QoS: reliable, volatile, keep last 10

dds_qos_t* CreateQos(const Ros2Qos& p) {
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, p.reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT, DDS_MSECS(100));
  dds_qset_durability(q, p.transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  dds_qset_history(q, DDS_HISTORY_KEEP_LAST, p.depth);
  const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
  dds_qset_data_representation(q, 1, &xcdr1);
  return q;
}

// One participant on the wire domain, made from a Cyclone XML configuration (as CYCLONEDDS_URI gives it to a node).
class Ros2Participant {
 public:
  Ros2Participant(int domain, const std::string& config) {
    domain_ = dds_create_domain(static_cast<dds_domainid_t>(domain), config.c_str());
    participant_ = domain_ > 0 ? dds_create_participant(static_cast<dds_domainid_t>(domain), nullptr, nullptr)
                               : domain_;
  }
  ~Ros2Participant() {
    if (domain_ > 0) dds_delete(domain_);
  }
  Ros2Participant(const Ros2Participant&) = delete;
  Ros2Participant& operator=(const Ros2Participant&) = delete;

  dds_entity_t participant() const { return participant_; }
  // A reader or writer (< 0: Cyclone's refusal).
  dds_entity_t Create(const dds_topic_descriptor_t& type, const char* topic_name, const Ros2Qos& profile, bool writer) {
    const dds_entity_t topic = dds_create_topic(participant_, &type, topic_name, nullptr, nullptr);
    if (topic < 0) return topic;
    dds_qos_t* q = CreateQos(profile);
    const dds_entity_t e = writer ? dds_create_writer(participant_, topic, q, nullptr)
                                  : dds_create_reader(participant_, topic, q, nullptr);
    dds_delete_qos(q);
    return e;
  }

 private:
  dds_entity_t domain_ = 0;
  dds_entity_t participant_ = 0;
};

// Takes every sample waiting on `reader` and applies `check` (a description of what is wrong, "" if nothing).
template <typename Sample, typename Check>
void TakeAll(dds_entity_t reader, int& decoded, int& wrong, std::string& first_wrong, Check&& check) {
  constexpr int kBatch = 16;
  void* samples[kBatch];
  dds_sample_info_t infos[kBatch];
  for (;;) {
    for (auto& s : samples) s = nullptr;
    const dds_return_t n = dds_take(reader, samples, infos, kBatch, kBatch);
    if (n <= 0) return;
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      ++decoded;
      const std::string what = check(*static_cast<const Sample*>(samples[i]));
      if (!what.empty() && wrong++ == 0) first_wrong = what;
    }
    dds_return_loan(reader, samples, n);
  }
}

std::int64_t SystemNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// "" if the header is the follower's frame stamped within a second of this machine's system clock.
std::string CheckHeader(const std_msgs_msg_dds__Header_& h) {
  const std::int64_t stamp = static_cast<std::int64_t>(h.stamp.sec) * 1000000000 + h.stamp.nanosec;
  const double off_s = 1e-9 * static_cast<double>(SystemNowNs() - stamp);
  if (h.frame_id == nullptr || std::string(h.frame_id) != kFrameId) {
    return "frame_id '" + std::string(h.frame_id ? h.frame_id : "(null)") + "', expected " + kFrameId;
  }
  if (std::abs(off_s) >= 1.0) return "stamp " + std::to_string(h.stamp.sec) + " s is " + std::to_string(off_s) +
                                     " s from the system clock";
  return "";
}

std::string CheckPose(const geometry_msgs_msg_dds__PoseStamped_& m) {
  if (std::string h = CheckHeader(m.header); !h.empty()) return "measured_cp: " + h;
  const auto& p = m.pose.position;
  const auto& q = m.pose.orientation;
  if (std::abs(p.x) > kPositionTolerance || std::abs(p.y) > kPositionTolerance ||
      std::abs(p.z - kHomeZ) > kPositionTolerance) {
    return "measured_cp: position (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) +
           ") m, expected the home pose (0, 0, 0.284)";
  }
  const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (std::abs(norm - 1) > kQuaternionTolerance || std::abs(std::abs(q.w) - 1) > kQuaternionTolerance) {
    return "measured_cp: orientation (x y z w) = (" + std::to_string(q.x) + ", " + std::to_string(q.y) + ", " +
           std::to_string(q.z) + ", " + std::to_string(q.w) + "), expected the unit quaternion of R = I";
  }
  return "";
}

std::string CheckJoints(const sensor_msgs_msg_dds__JointState_& m) {
  if (std::string h = CheckHeader(m.header); !h.empty()) return "measured_js: " + h;
  if (m.name._length != kJointNames.size() || m.position._length != kJointNames.size()) {
    return "measured_js: " + std::to_string(m.name._length) + " names and " + std::to_string(m.position._length) +
           " positions, expected 6 of each";
  }
  for (std::uint32_t i = 0; i < m.name._length; ++i) {
    if (m.name._buffer[i] == nullptr || kJointNames[i] != m.name._buffer[i]) {
      return "measured_js: joint " + std::to_string(i) + " is named '" +
             std::string(m.name._buffer[i] ? m.name._buffer[i] : "(null)") + "', expected " + kJointNames[i];
    }
    if (!std::isfinite(m.position._buffer[i])) return "measured_js: position " + std::to_string(i) + " not finite";
  }
  return "";
}

// A ROS 2 topic every node (or its rmw) creates as it starts, with the QoS rclcpp gives it.
struct NodeTopic {
  const char* name;
  const dds_topic_descriptor_t* type;
  Ros2Qos qos;
};

// Creates a writer and a reader on each of a node's own topics and writes one sample on each message topic; an
// entity Cyclone refuses ("Not Allowed By Security" when the credentials do not grant it) fails the test.
void ExpectANodeCanStart(Ros2Participant& node) {
  const NodeTopic topics[] = {
      {"ros_discovery_info", &rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc, {true, true, 1}},
      {"rt/rosout", &rcl_interfaces_msg_dds__Log__desc, {true, true, 1000}},
      {"rt/parameter_events", &rcl_interfaces_msg_dds__ParameterEvent__desc, {true, false, 1000}},
      {"rq/robossis_observer/get_parametersRequest", &rcl_interfaces_srv_dds__GetParameters_Request__desc, kDefault},
      {"rr/robossis_observer/get_parametersReply", &rcl_interfaces_srv_dds__GetParameters_Response__desc, kDefault},
  };
  char empty[] = "", node_name[] = "/robossis_observer", text[] = "watching the robot";
  for (const NodeTopic& t : topics) {
    const dds_entity_t reader = node.Create(*t.type, t.name, t.qos, false);
    const dds_entity_t writer = node.Create(*t.type, t.name, t.qos, true);
    EXPECT_GT(reader, 0) << t.name << " reader: " << dds_strretcode(reader);
    EXPECT_GT(writer, 0) << t.name << " writer: " << dds_strretcode(writer);
    if (writer <= 0) continue;
    const std::string name = t.name;
    dds_return_t rc = DDS_RETCODE_OK;
    if (name == "ros_discovery_info") {
      rmw_dds_common_msg_dds__ParticipantEntitiesInfo_ info{};
      rc = dds_write(writer, &info);
    } else if (name == "rt/rosout") {
      rcl_interfaces_msg_dds__Log_ log{};
      log.level = 20;  // INFO
      log.name = node_name;
      log.msg = text;
      log.file = log.function = empty;
      rc = dds_write(writer, &log);
    } else if (name == "rt/parameter_events") {
      rcl_interfaces_msg_dds__ParameterEvent_ event{};
      event.node = node_name;
      rc = dds_write(writer, &event);
    }
    EXPECT_EQ(rc, DDS_RETCODE_OK) << t.name << ": " << dds_strretcode(rc);
  }
}

// Reads the follower as a ROS 2 node would, insecure or with the observer's credentials.
void ReadTheFollowerAsARos2Node(bool secured) {
  // The types were compiled as rmw_cyclonedds_cpp registers its own: ROS 2's names, no type information.
  EXPECT_STREQ(geometry_msgs_msg_dds__PoseStamped__desc.m_typename, "geometry_msgs::msg::dds_::PoseStamped_");
  EXPECT_STREQ(sensor_msgs_msg_dds__JointState__desc.m_typename, "sensor_msgs::msg::dds_::JointState_");
  EXPECT_EQ(geometry_msgs_msg_dds__PoseStamped__desc.m_flagset & DDS_TOPIC_XTYPES_METADATA, 0u);
  EXPECT_EQ(sensor_msgs_msg_dds__JointState__desc.m_flagset & DDS_TOPIC_XTYPES_METADATA, 0u);

  const testing::ScratchDir dir("robossis-ros2-wire-test");
  std::filesystem::create_directories(dir.path());
  const std::filesystem::path keys = dir.path() / "keys";
  if (secured) {
    ChildProcess init(ROBOSSIS_BINARY, {"keys", "init", keys.string()}, dir.path() / "keys.log");
    const ChildExit e = init.Wait();
    ASSERT_TRUE(e.exited && e.code == 0) << e.Describe() << ": " << ReadTextFile(dir.path() / "keys.log");
  }
  std::vector<std::string> args = {"follower", "--follower", "recorder", "--domain", std::to_string(Domain()),
                                   "--interface", "127.0.0.1", "--peer", "127.0.0.1", "--no-plots",
                                   "--duration-s", "600", "--out", (dir.path() / "follower").string()};
  if (secured) args.insert(args.end(), {"--keys", (keys / "follower").string()});
  else args.push_back("--insecure");
  const std::filesystem::path log = dir.path() / "follower.log";
  ChildProcess follower(ROBOSSIS_BINARY, args, log);

  Ros2Participant node(Domain(), CycloneConfig(secured ? keys / "observer" : std::filesystem::path()));
  ASSERT_GT(node.participant(), 0) << "participant: " << dds_strretcode(node.participant());
  const dds_entity_t cp = node.Create(geometry_msgs_msg_dds__PoseStamped__desc, kMeasuredCp, kSensorData, false);
  const dds_entity_t js = node.Create(sensor_msgs_msg_dds__JointState__desc, kMeasuredJs, kSensorData, false);
  // rclcpp's default QoS (reliable) asks more than the best-effort stream offers: DDS refuses the match.
  const dds_entity_t reliable = node.Create(geometry_msgs_msg_dds__PoseStamped__desc, kMeasuredCp, kDefault, false);
  ASSERT_GT(cp, 0) << dds_strretcode(cp);
  ASSERT_GT(js, 0) << dds_strretcode(js);
  ASSERT_GT(reliable, 0) << dds_strretcode(reliable);
  ExpectANodeCanStart(node);

  int cp_decoded = 0, js_decoded = 0, wrong = 0;
  std::string first_wrong;
  const auto give_up = std::chrono::steady_clock::now() + 60s;  // a bound for a broken link, not a measurement
  while ((cp_decoded < kSamples || js_decoded < kSamples) && std::chrono::steady_clock::now() < give_up &&
         follower.running()) {
    TakeAll<geometry_msgs_msg_dds__PoseStamped_>(cp, cp_decoded, wrong, first_wrong, CheckPose);
    TakeAll<sensor_msgs_msg_dds__JointState_>(js, js_decoded, wrong, first_wrong, CheckJoints);
    std::this_thread::sleep_for(5ms);
  }
  dds_requested_incompatible_qos_status_t incompatible{};
  dds_get_requested_incompatible_qos_status(reliable, &incompatible);
  std::cout << (secured ? "secured" : "insecure") << ": decoded " << cp_decoded << " measured_cp and " << js_decoded
            << " measured_js samples, " << wrong << " wrong; a reliable reader was refused " << incompatible.total_count
            << " time(s) as incompatible\n";
  EXPECT_GE(cp_decoded, kSamples) << "follower log: " << ReadTextFile(log);
  EXPECT_GE(js_decoded, kSamples) << "follower log: " << ReadTextFile(log);
  EXPECT_EQ(wrong, 0) << first_wrong;
  EXPECT_GT(incompatible.total_count, 0u);

  follower.Signal(SIGINT);
  const auto exit = follower.WaitFor(30s);
  ASSERT_TRUE(exit.has_value()) << "the follower did not stop; log: " << ReadTextFile(log);
  EXPECT_TRUE(exit->exited && exit->code == 0) << exit->Describe() << "; log: " << ReadTextFile(log);
}

TEST(Ros2Wire, ARos2NodeReadsTheFollowersPoseAndJointsInsecure) { ReadTheFollowerAsARos2Node(false); }

TEST(Ros2Wire, ARos2NodeWithTheObserversCredentialsReadsTheFollowerAndStarts) { ReadTheFollowerAsARos2Node(true); }

}  // namespace
}  // namespace robossis
