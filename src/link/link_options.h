#pragma once
// How a link end joins the network: the DDS domain, the network interface, the discovery peers, its credentials,
// and the link's timing assumptions (data/config/link.yaml). Everything here is decided before the link starts;
// nothing is read from it on a real-time path.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace robossis {
class ConfigNode;
}  // namespace robossis

namespace robossis::link {

// The kinds of participant that hold credentials (`robossis keys init` makes one identity for each). The observer
// is not a link end: it is a ROS 2 node (rviz, ros2 bag, ...) that watches the robot's status and commands nothing.
enum class Role { kLeader, kFollower, kPanel, kObserver };
const char* ToString(Role role);

// Timing and sanity bounds of the link (data/config/link.yaml, every value [assumed] there).
struct LinkTuning {
  double setpoint_max_age_s = 0.030;         // older set-points are dropped (the follower's 30 ms watchdog)
  double session_takeover_s = 0.030;         // silence of the current leader before a new leader session is taken
  double setpoint_deadline_s = 0.010;        // DDS deadline QoS on the set-point topic (10 missed 1 kHz ticks)
  double liveliness_lease_s = 0.100;         // DDS liveliness lease of the set-point writer
  double clock_drift_allowance = 1e-4;       // relative drift between the two units' clocks the age estimate absorbs
  double max_position_m = 1.0;               // |p_FM| bound of a sane set-point (the RSR's reach is ~0.3 m)
  double max_linear_speed_m_per_s = 1.0;     // |v| bound of a sane set-point twist
  double max_angular_speed_rad_per_s = 10.0; // |omega| bound
  double quaternion_norm_tolerance = 1e-3;   // | |q| - 1 | bound
  double status_state_period_s = 0.100;      // operating_state is also re-sent at this period (its counters move)
  double command_max_age_s = 1.0;            // older state commands are dropped (command_freshness.h)
  double peer_wait_s = 10.0;                 // a leader that authenticates no follower this long exits

  static LinkTuning FromYaml(const std::filesystem::path& file);
  // The same from a document already loaded (ConfigNode::Load): one parse read by several loaders.
  static LinkTuning FromConfig(const ConfigNode& root);
};

// The topic namespace of every participant and of the permissions `robossis keys init` signs: one constant, so
// credentials always grant the topics the link uses.
inline constexpr char kTopicNamespace[] = "rsr";

// A namespace is one DDS topic-name part: 1 to kMaxTopicNamespaceLength of [A-Za-z0-9_]. Anything else (a '*'
// or '?' wildcard, a '/', XML markup, an empty part) would widen or break the signed permissions. Throws
// std::invalid_argument naming the value and the rule.
inline constexpr std::size_t kMaxTopicNamespaceLength = 64;
void ValidateTopicNamespace(const std::string& topic_namespace);

// `s` with &, <, > and " replaced by their XML entities (text and attribute values of the XML documents).
std::string XmlEscape(const std::string& s);

struct LinkOptions {
  Role role = Role::kLeader;
  // The DDS domain on the wire (ports 7400 + 250·domain + …). Participants must agree on it.
  int domain_id = 42;
  // The network interface to use: an address ("127.0.0.1", "192.168.10.2") or an interface name ("eth1").
  std::string network_interface = "127.0.0.1";
  // Unicast discovery peers (addresses, optionally "address:port"). Empty: multicast discovery on the interface.
  std::vector<std::string> peers = {"127.0.0.1"};
  // Fixed participant index (ports 7410 + 250·domain + 2·index and +1), or -1 for the first free one.
  int participant_index = -1;
  int max_auto_participant_index = 20;
  // The address advertised to the peers instead of the interface's (a relay or NAT in between); empty: none.
  std::string external_address;
  // This role's credentials: the DIR/<role> folder `robossis keys init DIR` makes (only this role's key in it, no
  // CA key, the key mode 0600: CheckCredentialBundle). Empty and insecure = false is an error.
  std::filesystem::path keys_dir;
  bool insecure = false;  // a lab bench without DDS Security (the caller says so loudly)
  // Topics are rt/<namespace>/<name> (ROS 2's "rt/" prefix for topics).
  std::string topic_namespace = kTopicNamespace;
  LinkTuning tuning;
};

// The Cyclone DDS configuration (XML) of one link end. `local_domain_id` is this process's domain, mapped onto
// options.domain_id on the wire (so two ends can live in one process, as the tests do). With `realtime_threads`,
// Cyclone's receive, delivery and timed-event threads run at SCHED_FIFO rt::kLinkThreadFifoPriority (only where the
// process may: Cyclone refuses to start a thread it cannot schedule so).
std::string BuildCycloneConfig(const LinkOptions& options, int local_domain_id, bool realtime_threads = false);

// The DDS Security participant properties (name, value) for the role's credentials in options.keys_dir.
// Throws std::runtime_error naming the missing or misplaced file (CheckCredentialBundle). Empty when insecure.
std::vector<std::pair<std::string, std::string>> SecurityProperties(const LinkOptions& options);

// Where the DDS Security plugins are (Debian ships them in libddsc0debian/, outside the loader's path).
std::filesystem::path SecurityPluginDir();

}  // namespace robossis::link
