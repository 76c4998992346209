#include "src/core/config.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include "src/core/files.h"

namespace robossis {

std::filesystem::path DefaultDataDir() {
  if (const char* env = std::getenv("ROBOSSIS_DATA_DIR"); env != nullptr && *env != '\0') return env;
  // The build tree's data/ when it exists; else an installed program's PREFIX/share/robossis/data.
  std::error_code ec;
  if (std::filesystem::is_directory(ROBOSSIS_DEFAULT_DATA_DIR, ec)) return ROBOSSIS_DEFAULT_DATA_DIR;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "robossis" / "data";
    if (std::filesystem::is_directory(installed, ec)) return installed;
  }
  return ROBOSSIS_DEFAULT_DATA_DIR;
}

namespace {

// Levenshtein distance, for "did you mean" hints on short keys.
std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::string Joined(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

// Throws on a key that appears twice in one mapping, anywhere in the document (mappings inside lists included).
void RejectDuplicateKeys(const YAML::Node& node, const std::string& file, const std::string& path) {
  if (node.IsMap()) {
    std::map<std::string, int> first_line;
    for (auto it = node.begin(); it != node.end(); ++it) {
      const std::string key = it->first.IsScalar() ? it->first.Scalar() : std::string("?");
      const int line = it->first.Mark().line + 1;
      const auto [seen, inserted] = first_line.emplace(key, line);
      if (!inserted) {
        throw std::runtime_error(file + ": '" + Joined(path, key) + "': duplicated key (lines " +
                                 std::to_string(seen->second) + " and " + std::to_string(line) + ")");
      }
      RejectDuplicateKeys(it->second, file, Joined(path, key));
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      RejectDuplicateKeys(node[i], file, path + "[" + std::to_string(i) + "]");
    }
  }
}

// What the event pass sees of the document stream: the number of documents (counted up to 2) and the line of the
// first alias. Not YAML::LoadAll: on some malformed inputs its parser reports empty documents without end, and
// LoadAll never returns (found by fuzz_yaml_configs).
struct DocumentScan {
  int documents = 0;
  int first_alias_line = 0;  // 1-based; 0 when there is none
};

DocumentScan ScanDocuments(const std::string& text) {
  struct Scan : YAML::EventHandler {
    int first_alias_line = 0;
    void OnDocumentStart(const YAML::Mark&) override {}
    void OnDocumentEnd() override {}
    void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
    void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
      if (first_alias_line == 0) first_alias_line = mark.line + 1;
    }
    void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
    void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
    void OnSequenceEnd() override {}
    void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
    void OnMapEnd() override {}
  } scan;
  std::istringstream in(text);
  YAML::Parser parser(in);
  DocumentScan result;
  while (result.documents < 2 && parser.HandleNextDocument(scan)) ++result.documents;
  result.first_alias_line = scan.first_alias_line;
  return result;
}

// The 1-based line of the marker that starts the second document: a "---" at the start of a line (YAML allows a
// document marker nowhere else), the first one if content came before it, else the second.
int SecondDocumentLine(const std::string& text) {
  int line = 0, markers = 0;
  bool content_before_marker = false;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string_view l(text.data() + pos, end - pos);
    ++line;
    pos = end + 1;
    const bool marker = l.substr(0, 3) == "---" && (l.size() == 3 || l[3] == ' ' || l[3] == '\t' || l[3] == '\r');
    if (marker) {
      ++markers;
      if (markers == (content_before_marker ? 1 : 2)) return line;
      continue;
    }
    const std::size_t first = l.find_first_not_of(" \t\r");
    if (markers == 0 && first != std::string_view::npos && l[first] != '#' && l[first] != '%') {
      content_before_marker = true;
    }
  }
  return line;
}

}  // namespace

ConfigNode ConfigNode::Load(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(file, ec))) {
    throw std::runtime_error(file.string() + ": config file not found");  // the usual mistake, said plainly
  }
  const std::string text = ReadBoundedFile(file, kMaxFileBytes, "YAML config file");
  YAML::Node root;
  DocumentScan scan;
  try {
    scan = ScanDocuments(text);
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(file.string() + ": not valid YAML: " + e.what());
  }
  if (scan.documents > 1) {
    // A second document would be ignored by every loader: the file says two things and only one would count.
    throw std::runtime_error(file.string() + " line " + std::to_string(SecondDocumentLine(text)) +
                             ": a second YAML document ('---'); expected one document per config file");
  }
  if (scan.first_alias_line > 0) {
    // An alias shares a node: one that names its own ancestor makes the document a cycle, and nested ones grow it
    // exponentially when walked (found by fuzz_yaml_configs: the duplicate-key walk overflowed the stack).
    throw std::runtime_error(file.string() + " line " + std::to_string(scan.first_alias_line) +
                             ": a YAML alias ('*name'); expected no aliases in a config file: write the "
                             "value out");
  }
  if (!root.IsMap()) throw std::runtime_error(file.string() + ": expected a YAML mapping at the top level");
  RejectDuplicateKeys(root, file.string(), "");
  return ConfigNode(std::make_shared<const YAML::Node>(root), file.string(), "");
}

ConfigNode::ConfigNode(std::shared_ptr<const YAML::Node> node, std::string file, std::string key_path)
    : node_(std::move(node)), file_(std::move(file)), key_path_(std::move(key_path)),
      log_(std::make_shared<ReadLog>()) {}

std::string ConfigNode::PathOf(const std::string& key) const { return Joined(key_path_, key); }

void ConfigNode::Note(const std::string& key) const { log_->asked[key_path_].insert(key); }

void ConfigNode::RejectUnreadKeys() const { RejectUnreadKeysIn(*node_, key_path_); }

void ConfigNode::RejectUnreadKeysIn(const YAML::Node& node, const std::string& path) const {
  const auto asked = log_->asked.find(path);
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string key = it->first.IsScalar() ? it->first.Scalar() : std::string("?");
    if (asked == log_->asked.end() || asked->second.count(key) == 0) {
      std::string nearest;
      std::size_t best = static_cast<std::size_t>(-1);
      if (asked != log_->asked.end()) {
        for (const std::string& valid : asked->second) {
          const std::size_t d = EditDistance(key, valid);
          if (d < best) best = d, nearest = valid;
        }
      }
      throw std::runtime_error(file_ + ": '" + Joined(path, key) + "' (line " +
                               std::to_string(it->first.Mark().line + 1) + "): unknown key" +
                               (nearest.empty() ? std::string(" (this mapping takes no keys)")
                                                : "; the nearest valid key is '" + nearest + "'"));
    }
    if (log_->children.count(Joined(path, key)) != 0) RejectUnreadKeysIn(it->second, Joined(path, key));
  }
}

std::string ConfigNode::Where(const std::string& key) const {
  return file_ + ": '" + (key_path_.empty() ? key : key_path_ + "." + key) + "'";
}

void ConfigNode::Fail(const std::string& key, const std::string& message) const {
  throw std::runtime_error(Where(key) + ": " + message);
}

bool ConfigNode::Has(const std::string& key) const {
  Note(key);
  return (*node_)[key].IsDefined() && !(*node_)[key].IsNull();
}

YAML::Node ConfigNode::Require(const std::string& key) const {
  Note(key);
  const YAML::Node n = (*node_)[key];
  if (!n.IsDefined() || n.IsNull()) Fail(key, "missing");
  return n;
}

ConfigNode ConfigNode::Child(const std::string& key) const {
  const YAML::Node n = Require(key);
  if (!n.IsMap()) Fail(key, "expected a mapping");
  ConfigNode child(std::make_shared<const YAML::Node>(n), file_, PathOf(key));
  child.log_ = log_;
  log_->children.insert(PathOf(key));
  return child;
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
  if (!(v > 0.0)) Fail(key, "expected a positive number, got " + Text((*node_)[key]));
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

int ConfigNode::IntegerInRange(const std::string& key, int lo, int hi) const {
  const int v = Integer(key);
  if (v < lo || v > hi) {
    Fail(key, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                  std::to_string(v));
  }
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
