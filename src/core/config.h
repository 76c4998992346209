#pragma once
// YAML configuration reading with errors that name the file, the key and what was expected.
// Config structs are validated once, when loaded; nothing downstream re-checks them.

#include <filesystem>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace robossis {

// The data directory: $ROBOSSIS_DATA_DIR if set, else the source tree's data/ (fixed at build time).
std::filesystem::path DefaultDataDir();

// A YAML mapping with the file it came from and its key path, so every error can say where it is.
class ConfigNode {
 public:
  // Loads a YAML file; throws std::runtime_error naming the file if it is missing or not valid YAML.
  static ConfigNode Load(const std::filesystem::path& file);
  ConfigNode(YAML::Node node, std::string file, std::string key_path);

  bool Has(const std::string& key) const;
  ConfigNode Child(const std::string& key) const;  // throws if missing or not a mapping

  // Each throws std::runtime_error ("rsr.yaml: 'limits.stroke_min_m': expected a number, got 'abc'").
  double Number(const std::string& key) const;
  double NumberOr(const std::string& key, double fallback) const;
  double PositiveNumber(const std::string& key) const;
  double NumberInRange(const std::string& key, double lo, double hi) const;
  int Integer(const std::string& key) const;
  std::string String(const std::string& key) const;
  bool Bool(const std::string& key) const;
  std::vector<double> Numbers(const std::string& key, std::size_t expected_count) const;

  // "file: 'key.path': message" for errors found after reading.
  std::string Where(const std::string& key) const;
  [[noreturn]] void Fail(const std::string& key, const std::string& message) const;

  const std::string& file() const { return file_; }

 private:
  YAML::Node Require(const std::string& key) const;
  YAML::Node node_;
  std::string file_;
  std::string key_path_;
};

}  // namespace robossis
