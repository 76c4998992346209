#include "src/link/keys.h"

#include <chrono>
#include <ctime>
#include <optional>
#include <stdexcept>

#include "src/core/child_process.h"
#include "src/core/files.h"
#include "src/link/dds_entities.h"

namespace robossis::link {

namespace {

constexpr Role kRoles[] = {Role::kLeader, Role::kFollower, Role::kPanel, Role::kObserver};

// Runs `openssl args...` in `dir`, stdout and stderr to `log`. Throws naming the step on failure.
void RunOpenssl(const std::vector<std::string>& args, const std::filesystem::path& dir,
                const std::filesystem::path& log, const std::string& step) {
  std::optional<ChildProcess> openssl;
  try {
    openssl.emplace("openssl", args, log, dir);
  } catch (const std::runtime_error&) {
    throw std::runtime_error("keys init: cannot run openssl (install the openssl package)");
  }
  const ChildExit exit = openssl->Wait();
  if (!exit.exited || exit.code != 0) {
    std::string detail = ReadTextFile(log);
    while (!detail.empty() && (detail.back() == '\n' || detail.back() == '\r')) detail.pop_back();
    const auto nl = detail.rfind('\n');
    if (nl != std::string::npos) detail = detail.substr(nl + 1);
    throw std::runtime_error("keys init: openssl failed to " + step + ": " + detail);
  }
}

std::string IsoUtc(std::chrono::system_clock::time_point t) {
  const std::time_t tt = std::chrono::system_clock::to_time_t(t);
  std::tm tm{};
  gmtime_r(&tt, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  return buf;
}

std::string TopicList(const std::vector<std::string>& topics) {
  std::string x = "<topics>";
  for (const auto& t : topics) x += "<topic>" + XmlEscape(t) + "</topic>";
  return x + "</topics>";
}

}  // namespace

std::vector<std::string> Ros2NodeTopics() {
  // rmw_cyclonedds's graph topic (written as a node starts), each node's log and parameter events, the transforms
  // rviz and tf2 listen to (a static transform placing the robot is a user's to publish), and the parameter services
  // every rclcpp node serves (request rq/<node>/...Request, reply rr/<node>/...Reply). The robot answers no service.
  return {"ros_discovery_info", "rt/rosout", "rt/parameter_events", "rt/tf", "rt/tf_static", "rq/*", "rr/*"};
}

RoleTopics TopicsOf(Role role, const std::string& ns) {  // WireTopicName validates ns
  LinkOptions o;
  o.topic_namespace = ns;
  auto n = [&](Topic t) { return WireTopicName(o, t); };
  const std::vector<std::string> status = {n(Topic::kMeasuredCp), n(Topic::kMeasuredJs), n(Topic::kOperatingState)};
  // Who may command is decided here, by DDS Security access control on the follower (never by a field in the
  // message): the leader sends set-points only; enable, reset, home and disable are the panel's (the robot-side
  // console commands its follower without the network).
  RoleTopics topics;
  switch (role) {
    case Role::kLeader: topics = {{n(Topic::kSetPoint)}, status}; break;
    case Role::kFollower: topics = {status, {n(Topic::kSetPoint), n(Topic::kStateCommand)}}; break;
    case Role::kPanel: topics = {{n(Topic::kStateCommand)}, status}; break;
    case Role::kObserver: {
      // A ROS 2 node that watches: the status topics, and what every ROS 2 node needs to start. It publishes only
      // those ROS 2 topics, none of them under rt/<ns>/, so it can command nothing (not even an E-stop).
      const std::vector<std::string> ros2 = Ros2NodeTopics();
      topics = {ros2, status};
      topics.subscribe.insert(topics.subscribe.end(), ros2.begin(), ros2.end());
      return topics;
    }
  }
  // The E-stop is every link end's to give (the leader on a device failure, the panel, `robossis estop`); the
  // follower reads it.
  (role == Role::kFollower ? topics.subscribe : topics.publish).push_back(n(Topic::kEStop));
  return topics;
}

std::string GovernanceXml() {
  // Unauthenticated participants are refused; discovery, liveliness, the RTPS messages and every topic's data are
  // encrypted (AES-GCM: encrypted and authenticated); reads and writes are access-controlled per topic.
  return R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>230</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>ENCRYPT</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
)";
}

std::string PermissionsXml(Role role, const std::string& subject_name, const std::string& ns,
                           const std::string& not_before, const std::string& not_after) {
  const RoleTopics topics = TopicsOf(role, ns);
  std::string x = R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name=")";
  x += std::string(ToString(role)) + "_grant\">\n      <subject_name>" + XmlEscape(subject_name) + "</subject_name>\n";
  x += "      <validity><not_before>" + XmlEscape(not_before) + "</not_before><not_after>" + XmlEscape(not_after) +
       "</not_after></validity>\n";
  x += "      <allow_rule>\n        <domains><id_range><min>0</min><max>230</max></id_range></domains>\n";
  x += "        <publish>" + TopicList(topics.publish) + "</publish>\n";
  x += "        <subscribe>" + TopicList(topics.subscribe) + "</subscribe>\n";
  x += "      </allow_rule>\n      <default>DENY</default>\n    </grant>\n  </permissions>\n</dds>\n";
  return x;
}

void ValidateKeysInitOptions(const KeysInitOptions& options) {
  ValidateTopicNamespace(options.topic_namespace);
  if (options.validity_days < 1 || options.validity_days > kMaxValidityDays) {
    throw std::invalid_argument("keys init: validity " + std::to_string(options.validity_days) +
                                " days: expected 1 to " + std::to_string(kMaxValidityDays));
  }
  const std::string& org = options.organisation;
  if (org.empty() || org.size() > kMaxOrganisationLength ||
      org.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789 ._-") !=
          std::string::npos) {
    throw std::invalid_argument("keys init: organisation '" + org + "': expected 1 to " +
                                std::to_string(kMaxOrganisationLength) +
                                " characters A-Z, a-z, 0-9, space, '.', '_' or '-'");
  }
}

void InitKeys(const std::filesystem::path& dir, const KeysInitOptions& options) {
  ValidateKeysInitOptions(options);
  if (std::filesystem::exists(dir) && !std::filesystem::is_empty(dir)) {
    throw std::runtime_error("keys init: " + dir.string() + " is not empty (refusing to overwrite credentials)");
  }
  StagedOutputDir out(dir, {}, "keys init DIR");
  const std::filesystem::path s = out.staging();
  std::filesystem::permissions(s, std::filesystem::perms::owner_all, std::filesystem::perm_options::replace);
  const std::filesystem::path log = s / "openssl.log";
  const std::string days = std::to_string(options.validity_days);
  const std::string org = options.organisation;
  const std::vector<std::string> ec = {"-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes"};

  auto with = [](std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  RunOpenssl(with(with({"req", "-x509"}, ec), {"-keyout", "ca_key.pem", "-out", "ca_cert.pem", "-days", days, "-subj",
                                                "/C=US/O=" + org + "/CN=" + org + " link CA", "-sha256"}),
             s, log, "make the CA");
  const auto now = std::chrono::system_clock::now();
  const std::string not_before = IsoUtc(now - std::chrono::hours(24));
  const std::string not_after = IsoUtc(now + std::chrono::hours(24) * options.validity_days);
  out.Write("governance.xml", GovernanceXml());
  RunOpenssl({"smime", "-sign", "-in", "governance.xml", "-text", "-out", "governance.p7s", "-signer", "ca_cert.pem",
              "-inkey", "ca_key.pem"},
             s, log, "sign the governance");
  int serial = 1;
  for (Role role : kRoles) {
    const std::string r = ToString(role);
    RunOpenssl(with(with({"req"}, ec), {"-keyout", r + "_key.pem", "-out", r + ".csr", "-subj",
                                        "/C=US/O=" + org + "/CN=" + r}),
               s, log, "make the " + r + " key");
    RunOpenssl({"x509", "-req", "-in", r + ".csr", "-CA", "ca_cert.pem", "-CAkey", "ca_key.pem", "-set_serial",
                std::to_string(++serial), "-out", r + "_cert.pem", "-days", days, "-sha256"},
               s, log, "sign the " + r + " certificate");
    std::filesystem::remove(s / (r + ".csr"));
    RunOpenssl({"x509", "-in", r + "_cert.pem", "-noout", "-subject", "-nameopt", "RFC2253"}, s, log,
               "read the " + r + " subject");
    std::string subject = ReadTextFile(log);
    while (!subject.empty() && (subject.back() == '\n' || subject.back() == '\r')) subject.pop_back();
    if (subject.rfind("subject=", 0) == 0) subject = subject.substr(8);
    out.Write(r + "_permissions.xml", PermissionsXml(role, subject, options.topic_namespace, not_before, not_after));
    RunOpenssl({"smime", "-sign", "-in", r + "_permissions.xml", "-text", "-out", r + "_permissions.p7s", "-signer",
                "ca_cert.pem", "-inkey", "ca_key.pem"},
               s, log, "sign the " + r + " permissions");
  }
  std::filesystem::remove(log);
  // One bundle per role with only what that unit needs, and the CA (its key signs new credentials) apart.
  namespace fs = std::filesystem;
  for (Role role : kRoles) {
    const std::string r = ToString(role);
    fs::create_directory(s / r);
    for (const char* shared : {"ca_cert.pem", "governance.p7s", "governance.xml"}) fs::copy_file(s / shared, s / r / shared);
    for (const std::string own : {"_cert.pem", "_key.pem", "_permissions.p7s", "_permissions.xml"}) {
      fs::rename(s / (r + own), s / r / (r + own));
    }
  }
  fs::create_directory(s / kCaFolder);
  for (const char* ca : {"ca_cert.pem", "ca_key.pem", "governance.p7s", "governance.xml"}) {
    fs::rename(s / ca, s / kCaFolder / ca);
  }
  out.Write(std::string(kCaFolder) + "/README.txt",
            "This folder holds the CA's private key (ca_key.pem): whoever has it can make credentials that command\n"
            "the robot. Store it offline (an encrypted removable drive in a locked place), never on the leader PC,\n"
            "the robot PC or the panel. It is needed only to sign new credentials.\n");
  for (const auto& entry : fs::recursive_directory_iterator(s)) {
    const bool secret = entry.path().filename().string().find("_key.pem") != std::string::npos;
    fs::permissions(entry.path(),
                    entry.is_directory() ? fs::perms::owner_all
                    : secret             ? fs::perms::owner_read | fs::perms::owner_write
                                         : fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read |
                                               fs::perms::others_read,
                    fs::perm_options::replace);
  }
  out.Commit();
  fs::permissions(dir, fs::perms::owner_all, fs::perm_options::replace);
}

void CheckCredentialBundle(const std::filesystem::path& bundle, Role role) {
  namespace fs = std::filesystem;
  const std::string where = "--keys " + bundle.string() + ": ";
  if (fs::exists(bundle / "ca_key.pem")) {
    throw std::runtime_error(where + "holds ca_key.pem, the CA's private key: move it off this machine and keep it "
                             "offline (with the `" + std::string(kCaFolder) + "/` folder of `robossis keys init`)");
  }
  for (Role other : kRoles) {
    const std::string key = std::string(ToString(other)) + "_key.pem";
    if (other != role && fs::exists(bundle / key)) {
      throw std::runtime_error(where + "holds " + key + ", the " + ToString(other) + "'s private key: the " +
                               ToString(role) + " needs only its own bundle (the `" + ToString(role) +
                               "/` folder of `robossis keys init`); remove " + key + " from this machine");
    }
  }
  const fs::path key = bundle / (std::string(ToString(role)) + "_key.pem");
  const fs::perms others = fs::perms::group_all | fs::perms::others_all;
  if (fs::exists(key) && (fs::status(key).permissions() & others) != fs::perms::none) {
    throw std::runtime_error("--keys " + key.string() + ": the private key is accessible to group or others: run "
                             "`chmod 600 " + key.string() + "`");
  }
}

}  // namespace robossis::link
