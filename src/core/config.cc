#include "src/core/config.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace robossis {

std::filesystem::path DefaultDataDir() {
  if (const char* env = std::getenv("ROBOSSIS_DATA_DIR"); env != nullptr && *env != '\0') return env;
  return ROBOSSIS_DEFAULT_DATA_DIR;
}

ConfigNode ConfigNode::Load(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) throw std::runtime_error(file.string() + ": config file not found");
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(file.string() + ": not valid YAML: " + e.what());
  }
  if (!root.IsMap()) throw std::runtime_error(file.string() + ": expected a YAML mapping at the top level");
  return ConfigNode(root, file.string(), "");
}

ConfigNode::ConfigNode(YAML::Node node, std::string file, std::string key_path)
    : node_(std::move(node)), file_(std::move(file)), key_path_(std::move(key_path)) {}

std::string ConfigNode::Where(const std::string& key) const {
  return file_ + ": '" + (key_path_.empty() ? key : key_path_ + "." + key) + "'";
}

void ConfigNode::Fail(const std::string& key, const std::string& message) const {
  throw std::runtime_error(Where(key) + ": " + message);
}

bool ConfigNode::Has(const std::string& key) const { return node_[key].IsDefined() && !node_[key].IsNull(); }

YAML::Node ConfigNode::Require(const std::string& key) const {
  const YAML::Node n = node_[key];
  if (!n.IsDefined() || n.IsNull()) Fail(key, "missing");
  return n;
}

ConfigNode ConfigNode::Child(const std::string& key) const {
  const YAML::Node n = Require(key);
  if (!n.IsMap()) Fail(key, "expected a mapping");
  return ConfigNode(n, file_, key_path_.empty() ? key : key_path_ + "." + key);
}

namespace {
std::string Text(const YAML::Node& n) {
  if (n.IsScalar()) return n.Scalar();
  std::ostringstream os;
  os << n;
  return os.str();
}
}  // namespace

double ConfigNode::Number(const std::string& key) const {
  const YAML::Node n = Require(key);
  double v = 0.0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v)) {
    Fail(key, "expected a finite number, got '" + Text(n) + "'");
  }
  return v;
}

double ConfigNode::NumberOr(const std::string& key, double fallback) const {
  return Has(key) ? Number(key) : fallback;
}

double ConfigNode::PositiveNumber(const std::string& key) const {
  const double v = Number(key);
  if (!(v > 0.0)) Fail(key, "expected a positive number, got " + Text(node_[key]));
  return v;
}

double ConfigNode::NumberInRange(const std::string& key, double lo, double hi) const {
  const double v = Number(key);
  if (v < lo || v > hi) {
    std::ostringstream os;
    os << "expected a number in [" << lo << ", " << hi << "], got " << v;
    Fail(key, os.str());
  }
  return v;
}

int ConfigNode::Integer(const std::string& key) const {
  const YAML::Node n = Require(key);
  int v = 0;
  if (!n.IsScalar() || !YAML::convert<int>::decode(n, v)) Fail(key, "expected an integer, got '" + Text(n) + "'");
  return v;
}

std::string ConfigNode::String(const std::string& key) const {
  const YAML::Node n = Require(key);
  if (!n.IsScalar()) Fail(key, "expected a string");
  return n.Scalar();
}

bool ConfigNode::Bool(const std::string& key) const {
  const YAML::Node n = Require(key);
  bool v = false;
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) Fail(key, "expected true or false, got '" + Text(n) + "'");
  return v;
}

std::vector<double> ConfigNode::Numbers(const std::string& key, std::size_t expected_count) const {
  const YAML::Node n = Require(key);
  if (!n.IsSequence() || n.size() != expected_count) {
    Fail(key, "expected a list of " + std::to_string(expected_count) + " numbers, got '" + Text(n) + "'");
  }
  std::vector<double> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    double v = 0.0;
    if (!n[i].IsScalar() || !YAML::convert<double>::decode(n[i], v) || !std::isfinite(v)) {
      Fail(key, "element " + std::to_string(i) + ": expected a finite number, got '" + Text(n[i]) + "'");
    }
    out.push_back(v);
  }
  return out;
}

}  // namespace robossis
