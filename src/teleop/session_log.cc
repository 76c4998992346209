#include "src/teleop/session_log.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "src/core/files.h"
#include "src/core/json_finite.h"
#include "src/core/json_integer.h"

namespace robossis::teleop {

namespace {
constexpr char kMagic[8] = {'R', 'B', 'S', 'S', 'L', 'O', 'G', '1'};
constexpr int kVersion = 1;

FieldType ParseType(const std::string& s, const std::string& where) {
  for (FieldType t : {FieldType::kF64, FieldType::kI64, FieldType::kU64, FieldType::kU32, FieldType::kU8,
                      FieldType::kBool}) {
    if (s == ToString(t)) return t;
  }
  throw std::runtime_error(where + ": unknown field type '" + s + "'");
}
std::size_t FieldBytes(FieldType type) {
  switch (type) {
    case FieldType::kF64:
    case FieldType::kI64:
    case FieldType::kU64: return 8;
    case FieldType::kU32: return 4;
    case FieldType::kU8:
    case FieldType::kBool: return 1;
  }
  return 8;
}

// The SI value of a logged number in `unit` (the jitter fields are logged in us).
double ToSi(double v, const std::string& unit) { return unit == "us" ? v * 1e-6 : unit == "ns" ? v * 1e-9 : v; }

// Every f64 of one record finite and within kMaxSessionLogMagnitudeSi in SI: a corrupt or hostile log is refused
// with the record's index instead of being replayed into the summary and the CSVs.
void CheckRecordValues(const StreamSpec& s, const char* record, std::size_t index, const std::string& file) {
  for (const FieldSpec& f : s.fields) {
    if (f.type != FieldType::kF64) continue;
    for (int k = 0; k < f.count; ++k) {
      double v = 0;
      std::memcpy(&v, record + f.offset + 8 * static_cast<std::size_t>(k), sizeof v);
      if (std::isfinite(v) && std::fabs(ToSi(v, f.unit)) <= kMaxSessionLogMagnitudeSi) continue;
      char value[40];
      std::snprintf(value, sizeof value, "%.6g", v);
      throw std::runtime_error(file + ": record " + std::to_string(index) + " of stream '" + s.name + "', field '" +
                               f.name + (f.count > 1 ? "[" + std::to_string(k) + "]" : std::string()) + "': got " +
                               value + "; expected a finite value of magnitude at most 1e6 (SI units)");
    }
  }
}

}  // namespace

const char* ToString(FieldType type) {
  switch (type) {
    case FieldType::kF64: return "f64";
    case FieldType::kI64: return "i64";
    case FieldType::kU64: return "u64";
    case FieldType::kU32: return "u32";
    case FieldType::kU8: return "u8";
    case FieldType::kBool: return "bool";
  }
  return "unknown";
}

SessionLogWriter::SessionLogWriter(const std::filesystem::path& file, const nlohmann::json& meta,
                                   std::vector<StreamSpec> streams)
    : file_(file), streams_(std::move(streams)) {
  nlohmann::ordered_json header;
  header["format"] = "robossis-session-log";
  header["version"] = kVersion;
  header["meta"] = meta;
  header["streams"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < streams_.size(); ++i) {
    if (streams_[i].id != i) throw std::invalid_argument("session log: stream ids must be 0, 1, ... in order");
    nlohmann::ordered_json s;
    s["id"] = streams_[i].id;
    s["name"] = streams_[i].name;
    s["record_size"] = streams_[i].record_size;
    s["fields"] = nlohmann::ordered_json::array();
    for (const FieldSpec& f : streams_[i].fields) {
      s["fields"].push_back({{"name", f.name}, {"type", ToString(f.type)}, {"offset", f.offset},
                             {"count", f.count}, {"unit", f.unit}});
    }
    header["streams"].push_back(s);
  }
  fd_ = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(file.string() + ": cannot create the session log: " + std::strerror(errno));
  const std::string text = header.dump();
  const std::uint32_t length = static_cast<std::uint32_t>(text.size());
  buffer_.insert(buffer_.end(), kMagic, kMagic + 8);
  const char* l = reinterpret_cast<const char*>(&length);
  buffer_.insert(buffer_.end(), l, l + sizeof length);
  buffer_.insert(buffer_.end(), text.begin(), text.end());
  Flush();
}

SessionLogWriter::~SessionLogWriter() {
  try {
    Flush();
  } catch (...) {
    // A destructor must not throw; the caller flushes explicitly to see errors.
  }
  if (fd_ >= 0) ::close(fd_);
}

void SessionLogWriter::Append(std::uint8_t stream_id, const void* record) {
  const StreamSpec& s = streams_.at(stream_id);
  buffer_.push_back(static_cast<char>(stream_id));
  const char* p = static_cast<const char*>(record);
  buffer_.insert(buffer_.end(), p, p + s.record_size);
  ++frames_;
  if (buffer_.size() >= kSessionLogBufferBytes) Flush();
}

void WriteAll(int fd, std::string_view bytes, const std::string& what) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(what + ": " + std::strerror(errno));
    }
    done += static_cast<std::size_t>(n);
  }
}

void SessionLogWriter::Flush() {
  WriteAll(fd_, std::string_view(buffer_.data(), buffer_.size()), file_.string() + ": session log write failed");
  buffer_.clear();
}

const StreamSpec* SessionLog::Find(const std::string& name) const {
  for (const StreamSpec& s : streams) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::size_t SessionLog::count(const StreamSpec& s) const {
  return records[static_cast<std::size_t>(&s - streams.data())].size() / s.record_size;
}

void CheckSameLayout(const StreamSpec& actual, const StreamSpec& expected, const std::string& where) {
  if (actual.record_size != expected.record_size || actual.fields.size() != expected.fields.size()) {
    throw std::runtime_error(where + ": record layout differs from this program's (" +
                             std::to_string(actual.record_size) + " bytes, " +
                             std::to_string(actual.fields.size()) + " fields; expected " +
                             std::to_string(expected.record_size) + " bytes, " +
                             std::to_string(expected.fields.size()) + " fields)");
  }
  for (std::size_t i = 0; i < actual.fields.size(); ++i) {
    const FieldSpec &a = actual.fields[i], &e = expected.fields[i];
    if (a.name != e.name || a.type != e.type || a.offset != e.offset || a.count != e.count) {
      throw std::runtime_error(where + ": field " + std::to_string(i) + " is '" + a.name + "'; expected '" +
                               e.name + "' with the same type, offset and count");
    }
  }
}

SessionLog ReadSessionLog(const std::filesystem::path& file) {
  const std::string bytes = ReadBoundedFile(file, kMaxSessionLogBytes, "session log");
  if (bytes.size() < 12 || std::memcmp(bytes.data(), kMagic, 7) != 0) {
    throw std::runtime_error(file.string() + ": not a robossis session log (bad magic)");
  }
  SessionLog log;
  log.version = bytes[7] - '0';
  if (log.version != kVersion) {
    throw std::runtime_error(file.string() + ": session log version " + std::to_string(log.version) +
                             "; this program reads version " + std::to_string(kVersion));
  }
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 8, sizeof length);
  if (12 + static_cast<std::size_t>(length) > bytes.size()) {
    throw std::runtime_error(file.string() + ": the header is cut short");
  }
  const nlohmann::json header = ParseJsonInput(bytes.begin() + 12, bytes.begin() + 12 + length,
                                               file.string() + ": the session log header");
  try {
    log.meta = header.at("meta");
    for (const auto& s : header.at("streams")) {
      StreamSpec spec;
      spec.id = JsonInteger<std::uint8_t>(s.at("id"), "stream id");
      spec.name = s.at("name").get<std::string>();
      spec.record_size = JsonInteger<std::size_t>(s.at("record_size"), "record_size");
      for (const auto& f : s.at("fields")) {
        spec.fields.push_back(FieldSpec{f.at("name").get<std::string>(),
                                        ParseType(f.at("type").get<std::string>(), file.string()),
                                        JsonInteger<std::size_t>(f.at("offset"), "offset"),
                                        JsonInteger<int>(f.at("count"), "count"),
                                        f.at("unit").get<std::string>()});
      }
      for (const FieldSpec& f : spec.fields) {
        // A field outside its record would be read outside the record's bytes.
        if (f.count < 1 || f.offset > spec.record_size ||
            static_cast<std::size_t>(f.count) > (spec.record_size - f.offset) / FieldBytes(f.type)) {
          throw std::runtime_error("field '" + f.name + "' does not fit in its " + std::to_string(spec.record_size) +
                                   "-byte record");
        }
      }
      if (spec.id != log.streams.size() || spec.record_size == 0) {
        throw std::runtime_error("stream ids must be 0, 1, ... and record sizes positive");
      }
      log.streams.push_back(std::move(spec));
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(file.string() + ": bad session log header: " + e.what());
  }
  log.records.resize(log.streams.size());
  std::size_t pos = 12 + length;
  while (pos < bytes.size()) {
    const auto id = static_cast<std::uint8_t>(bytes[pos]);
    if (id >= log.streams.size()) {
      throw std::runtime_error(file.string() + ": byte " + std::to_string(pos) + ": unknown stream id " +
                               std::to_string(id));
    }
    const std::size_t size = log.streams[id].record_size;
    if (size > bytes.size() - pos - 1) {  // (no overflow: pos < bytes.size())
      log.truncated = true;  // the crash cut the last frame: keep everything before it
      break;
    }
    CheckRecordValues(log.streams[id], bytes.data() + pos + 1, log.records[id].size() / size, file.string());
    log.records[id].insert(log.records[id].end(), bytes.begin() + pos + 1, bytes.begin() + pos + 1 + size);
    pos += 1 + size;
  }
  return log;
}

}  // namespace robossis::teleop
