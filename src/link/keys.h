#pragma once
// The credentials of the secured link (DDS Security: authentication, access control, cryptography), made with the
// `openssl` command line: one CA (identity and permissions CA), an identity certificate and key for the leader, the
// follower, the control panel and the observer (ROS 2 tools that watch the robot), a signed governance document that
// authenticates and encrypts everything, and a signed permissions document per participant that grants it only its
// own topics. Each role gets a bundle of its own (`leader/`, `follower/`, `panel/`, `observer/`: its key and
// certificate, the CA certificate, the signed governance and its own signed permissions); the CA's key is kept apart
// (`ca/`), to be stored offline. Private keys are mode 0600, the folders 0700.

#include <filesystem>
#include <string>
#include <vector>

#include "src/link/link_options.h"

namespace robossis::link {

// Bounds of KeysInitOptions (assumptions: the paper gives none). 100 years covers any deployment; X.509 limits an
// organisation name to 64 characters (RFC 5280 ub-organization-name).
inline constexpr int kMaxValidityDays = 36500;
inline constexpr std::size_t kMaxOrganisationLength = 64;

struct KeysInitOptions {
  // The participants use kTopicNamespace; another namespace makes credentials no participant can use, so the
  // command line does not offer it. Checked by ValidateTopicNamespace.
  std::string topic_namespace = kTopicNamespace;
  // 1 to kMaxValidityDays. One year [assumed]: a lost or copied credential stops working within a year, and a
  // yearly renewal (a new `keys init`) is a routine maintenance step.
  int validity_days = 365;
  // Goes into every certificate subject (`/O=...`): letters, digits, space, '.', '_' and '-' only, so it can add no
  // subject field of its own ('/', '=', '+', ',').
  std::string organisation = "Robossis";
};

// Throws std::invalid_argument naming the option that is out of its bounds (all of them, as above).
void ValidateKeysInitOptions(const KeysInitOptions& options);

// The topics each role may publish and subscribe to (wire names), as the permissions grant them. Throws
// std::invalid_argument for a namespace ValidateTopicNamespace refuses.
struct RoleTopics {
  std::vector<std::string> publish;
  std::vector<std::string> subscribe;
};
RoleTopics TopicsOf(Role role, const std::string& topic_namespace);
// The ROS 2 topics (DDS names) the observer may publish and subscribe to besides the robot's status, so that a
// ROS 2 node can start with its credentials (see TopicsOf).
std::vector<std::string> Ros2NodeTopics();

// The governance and permissions documents (unsigned XML), exposed for tests and inspection. Every value is
// XML-escaped; the namespace is validated as in TopicsOf.
std::string GovernanceXml();
std::string PermissionsXml(Role role, const std::string& subject_name, const std::string& topic_namespace,
                           const std::string& not_before, const std::string& not_after);

// The folder of `dir` that holds the CA (certificate, key, governance): never copied to a unit.
inline constexpr char kCaFolder[] = "ca";

// Makes the credentials in `dir` (which must not exist or be empty): dir/ca, dir/leader, dir/follower, dir/panel,
// dir/observer. The options are checked (ValidateKeysInitOptions) before anything is written; everything is made in
// a staging folder and moved in only when complete. Throws std::runtime_error naming the openssl step that failed.
void InitKeys(const std::filesystem::path& dir, const KeysInitOptions& options);

// Refuses (std::runtime_error naming the file and the fix) a role's credentials folder that holds the CA's key or
// another role's key, or whose private key group or others may access. Called before the participant is made.
void CheckCredentialBundle(const std::filesystem::path& bundle, Role role);

}  // namespace robossis::link
