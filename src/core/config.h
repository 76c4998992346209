#pragma once
// YAML configuration reading with errors that name the file, the key and what was expected.
// Config structs are validated once, when loaded; nothing downstream re-checks them.

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

// yaml-cpp stays inside config.cc: a config loader sees only ConfigNode.
namespace YAML {
class Node;
}  // namespace YAML

namespace robossis {

// The data directory: $ROBOSSIS_DATA_DIR if set, else the source tree's data/ (fixed at build time) if it exists,
// else PREFIX/share/robossis/data beside an installed program (PREFIX/bin/robossis).
std::filesystem::path DefaultDataDir();

// A YAML mapping with the file it came from and its key path, so every error can say where it is.
// The nodes of one file share a log of the keys the loader asked for; RejectUnreadKeys() then reports any key in
// the file that no loader asked for (a typo, or a setting this version does not have) with the nearest valid key.
class ConfigNode {
 public:
  // Largest config file accepted (configs are a few kB; this bounds the memory before parsing).
  static constexpr std::uintmax_t kMaxFileBytes = 1u << 20;

  // Loads a YAML file; throws std::runtime_error naming the file if it is missing, not a regular file, larger
  // than kMaxFileBytes, not valid YAML, holds more than one YAML document ('---': the line is named), holds an
  // alias ('*name': the line is named), or has a key twice in one mapping (YAML forbids it; yaml-cpp keeps both).
  static ConfigNode Load(const std::filesystem::path& file);

  // The same document with an empty log of read keys, for a second loader of one parse: RejectUnreadKeys() then
  // judges only what that loader asked for, as if it had loaded the file itself.
  ConfigNode ForAnotherLoader() const { return ConfigNode(node_, file_, key_path_); }

  // Call once on the root after a loader has read everything: throws naming the file, the first key no loader
  // asked for and the nearest key that is valid at that place. Mappings read whole (Child) are checked inside.
  void RejectUnreadKeys() const;

  bool Has(const std::string& key) const;
  ConfigNode Child(const std::string& key) const;  // throws if missing or not a mapping

  // Each throws std::runtime_error ("rsr.yaml: 'limits.stroke_min_m': expected a number, got 'abc'").
  double Number(const std::string& key) const;
  double NumberOr(const std::string& key, double fallback) const;
  double PositiveNumber(const std::string& key) const;
  double NumberInRange(const std::string& key, double lo, double hi) const;
  int Integer(const std::string& key) const;  // exact: "2.5" and "2.0" are errors
  int IntegerInRange(const std::string& key, int lo, int hi) const;
  std::string String(const std::string& key) const;
  bool Bool(const std::string& key) const;
  std::vector<double> Numbers(const std::string& key, std::size_t expected_count) const;

  // "file: 'key.path': message" for errors found after reading.
  std::string Where(const std::string& key) const;
  [[noreturn]] void Fail(const std::string& key, const std::string& message) const;

  const std::string& file() const { return file_; }

 private:
  // Keys asked for, per mapping path ("" is the root), and the paths opened as child mappings.
  struct ReadLog {
    std::map<std::string, std::set<std::string>> asked;
    std::set<std::string> children;
  };
  ConfigNode(std::shared_ptr<const YAML::Node> node, std::string file, std::string key_path);
  YAML::Node Require(const std::string& key) const;
  void Note(const std::string& key) const;
  std::string PathOf(const std::string& key) const;
  void RejectUnreadKeysIn(const YAML::Node& node, const std::string& path) const;
  std::shared_ptr<const YAML::Node> node_;  // never null
  std::string file_;
  std::string key_path_;
  std::shared_ptr<ReadLog> log_;
};

}  // namespace robossis
