#include "src/link/link_options.h"

#include <stdexcept>

#include "src/core/config.h"
#include "src/core/rt/periodic_loop.h"
#include "src/link/keys.h"

namespace robossis::link {

const char* ToString(Role role) {
  switch (role) {
    case Role::kLeader: return "leader";
    case Role::kFollower: return "follower";
    case Role::kPanel: return "panel";
    case Role::kObserver: return "observer";
  }
  return "?";
}

LinkTuning LinkTuning::FromYaml(const std::filesystem::path& file) {
  return FromConfig(ConfigNode::Load(file));
}

LinkTuning LinkTuning::FromConfig(const ConfigNode& root) {
  LinkTuning t;
  const ConfigNode sp = root.Child("setpoint");
  t.setpoint_max_age_s = sp.PositiveNumber("max_age_s");
  t.session_takeover_s = sp.PositiveNumber("session_takeover_s");
  t.setpoint_deadline_s = sp.PositiveNumber("deadline_s");
  t.liveliness_lease_s = sp.PositiveNumber("liveliness_lease_s");
  t.clock_drift_allowance = sp.NumberInRange("clock_drift_allowance", 0.0, 0.01);
  t.max_position_m = sp.PositiveNumber("max_position_m");
  t.max_linear_speed_m_per_s = sp.PositiveNumber("max_linear_speed_m_per_s");
  t.max_angular_speed_rad_per_s = sp.PositiveNumber("max_angular_speed_rad_per_s");
  t.quaternion_norm_tolerance = sp.NumberInRange("quaternion_norm_tolerance", 0.0, 0.5);
  t.status_state_period_s = root.Child("status").PositiveNumber("state_period_s");
  t.command_max_age_s = root.Child("command").PositiveNumber("max_age_s");
  t.peer_wait_s = root.Child("discovery").PositiveNumber("peer_wait_s");
  root.RejectUnreadKeys();  // a typo or a key this version does not read is an error
  return t;
}

void ValidateTopicNamespace(const std::string& ns) {
  const bool ok = !ns.empty() && ns.size() <= kMaxTopicNamespaceLength &&
                  ns.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_") ==
                      std::string::npos;
  if (!ok) {
    throw std::invalid_argument("topic namespace '" + ns + "': expected 1 to " +
                                std::to_string(kMaxTopicNamespaceLength) + " characters A-Z, a-z, 0-9 or _");
  }
}

std::string XmlEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

bool LooksLikeAddress(const std::string& s) {
  return !s.empty() && s.find_first_not_of("0123456789.:") == std::string::npos;
}

std::string FileUri(const std::filesystem::path& p) { return "file:" + std::filesystem::absolute(p).string(); }

}  // namespace

std::string BuildCycloneConfig(const LinkOptions& o, int local_domain_id, bool realtime_threads) {
  std::string x = "<CycloneDDS><Domain Id=\"" + std::to_string(local_domain_id) + "\"><General><Interfaces>";
  x += LooksLikeAddress(o.network_interface) ? "<NetworkInterface address=\"" : "<NetworkInterface name=\"";
  x += XmlEscape(o.network_interface) + "\"/></Interfaces>";
  x += o.peers.empty() ? "<AllowMulticast>spdp</AllowMulticast>" : "<AllowMulticast>false</AllowMulticast>";
  if (!o.external_address.empty()) x += "<ExternalNetworkAddress>" + XmlEscape(o.external_address) + "</ExternalNetworkAddress>";
  x += "</General><Discovery><ExternalDomainId>" + std::to_string(o.domain_id) + "</ExternalDomainId>";
  x += "<ParticipantIndex>" + (o.participant_index < 0 ? std::string("auto") : std::to_string(o.participant_index)) +
       "</ParticipantIndex>";
  x += "<MaxAutoParticipantIndex>" + std::to_string(o.max_auto_participant_index) + "</MaxAutoParticipantIndex>";
  if (!o.peers.empty()) {
    x += "<Peers>";
    for (const auto& p : o.peers) x += "<Peer address=\"" + XmlEscape(p) + "\"/>";
    x += "</Peers>";
  }
  x += "</Discovery>";
  if (realtime_threads) {
    x += "<Threads>";
    for (const char* name : {"recv", "dq.user", "dq.builtins", "tev"}) {
      x += std::string("<Thread name=\"") + name + "\"><Scheduling><Class>realtime</Class><Priority>" +
           std::to_string(rt::kLinkThreadFifoPriority) + "</Priority></Scheduling></Thread>";
    }
    // One receive thread for every socket: Cyclone's unicast receive thread (recvUC) takes no scheduling of its own.
    x += "</Threads><Internal><MultipleReceiveThreads>false</MultipleReceiveThreads></Internal>";
  }
  x += "</Domain></CycloneDDS>";
  return x;
}

std::filesystem::path SecurityPluginDir() {
  for (const char* dir : {"/usr/lib/x86_64-linux-gnu/libddsc0debian", "/usr/lib/aarch64-linux-gnu/libddsc0debian",
                          "/usr/lib/x86_64-linux-gnu", "/usr/local/lib"}) {
    if (std::filesystem::exists(std::filesystem::path(dir) / "libdds_security_auth.so")) return dir;
  }
  throw std::runtime_error("DDS Security plugins: libdds_security_auth.so not found (install libddsc0debian)");
}

std::vector<std::pair<std::string, std::string>> SecurityProperties(const LinkOptions& o) {
  if (o.insecure) return {};
  if (o.keys_dir.empty()) throw std::runtime_error("--keys: no credentials directory given (or run with --insecure)");
  const std::string role = ToString(o.role);
  const std::filesystem::path d = o.keys_dir;
  const std::filesystem::path files[] = {d / "ca_cert.pem", d / (role + "_cert.pem"), d / (role + "_key.pem"),
                                         d / "governance.p7s", d / (role + "_permissions.p7s")};
  for (const auto& f : files) {
    if (!std::filesystem::exists(f)) {
      throw std::runtime_error("--keys " + d.string() + ": missing " + f.filename().string() +
                               " (expected the " + role + "'s folder made by `robossis keys init DIR`: DIR/" + role +
                               ")");
    }
  }
  CheckCredentialBundle(d, o.role);
  const std::filesystem::path plugins = SecurityPluginDir();
  return {
      {"dds.sec.auth.library.path", (plugins / "libdds_security_auth.so").string()},
      {"dds.sec.auth.library.init", "init_authentication"},
      {"dds.sec.auth.library.finalize", "finalize_authentication"},
      {"dds.sec.crypto.library.path", (plugins / "libdds_security_crypto.so").string()},
      {"dds.sec.crypto.library.init", "init_crypto"},
      {"dds.sec.crypto.library.finalize", "finalize_crypto"},
      {"dds.sec.access.library.path", (plugins / "libdds_security_ac.so").string()},
      {"dds.sec.access.library.init", "init_access_control"},
      {"dds.sec.access.library.finalize", "finalize_access_control"},
      {"dds.sec.auth.identity_ca", FileUri(files[0])},
      {"dds.sec.auth.identity_certificate", FileUri(files[1])},
      {"dds.sec.auth.private_key", FileUri(files[2])},
      {"dds.sec.access.permissions_ca", FileUri(files[0])},
      {"dds.sec.access.governance", FileUri(files[3])},
      {"dds.sec.access.permissions", FileUri(files[4])},
  };
}

}  // namespace robossis::link
