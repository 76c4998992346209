#pragma once
// The session log of the flight recorder: a self-describing binary file that survives a crash.
//
// Layout (version 1, little-endian, as the machine writes it):
//   "RBSSLOG1"                      8 bytes of magic, the last one the format version
//   u32 header_length, header       a JSON object: {"format": "robossis-session-log", "version": 1, "meta": {...},
//                                   "streams": [{"id", "name", "record_size", "fields": [{"name", "type",
//                                   "offset", "count", "unit"}]}]}: enough to decode every record without this
//                                   program (types f64, i64, u64, u32, u8, bool)
//   frames                          u8 stream id, then record_size bytes of that stream's record
// A frame cut short (the process was killed mid-write) is ignored by the reader; everything before it is kept.
//
// The writer buffers in user space and hands the buffer to the kernel (write(2)) on every Flush(), and on its own
// once kSessionLogBufferBytes are buffered, so that its memory stays flat however long the run (the simulated clock
// flushes only at the end); a killed process loses only what was not yet flushed (the logger thread flushes every
// few milliseconds). Not real-time: the loops never call it, they push records to SpscQueues that the logger thread
// drains.

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <nlohmann/json.hpp>

namespace robossis::teleop {

enum class FieldType : std::uint8_t { kF64, kI64, kU64, kU32, kU8, kBool };
const char* ToString(FieldType type);

struct FieldSpec {
  std::string name;
  FieldType type = FieldType::kF64;
  std::size_t offset = 0;
  int count = 1;     // array length (1 for a scalar)
  std::string unit;  // SI unit ("m", "rad", "N", "ns", "s", ...) or "" for codes and counts
};

struct StreamSpec {
  std::uint8_t id = 0;
  std::string name;
  std::size_t record_size = 0;
  std::vector<FieldSpec> fields;
};

namespace detail {
template <typename T> struct FieldTraits;
template <> struct FieldTraits<double> { static constexpr FieldType type = FieldType::kF64; static constexpr int count = 1; };
template <> struct FieldTraits<std::int64_t> { static constexpr FieldType type = FieldType::kI64; static constexpr int count = 1; };
template <> struct FieldTraits<std::uint64_t> { static constexpr FieldType type = FieldType::kU64; static constexpr int count = 1; };
template <> struct FieldTraits<std::uint32_t> { static constexpr FieldType type = FieldType::kU32; static constexpr int count = 1; };
template <> struct FieldTraits<std::uint8_t> { static constexpr FieldType type = FieldType::kU8; static constexpr int count = 1; };
template <> struct FieldTraits<bool> { static constexpr FieldType type = FieldType::kBool; static constexpr int count = 1; };
template <typename T, std::size_t N> struct FieldTraits<std::array<T, N>> {
  static constexpr FieldType type = FieldTraits<T>::type;
  static constexpr int count = static_cast<int>(N);
};
template <typename T>
FieldSpec Describe(const char* name, std::size_t offset, const char* unit) {
  using U = std::conditional_t<std::is_enum_v<T>, std::uint8_t, T>;
  if constexpr (std::is_enum_v<T>) static_assert(sizeof(T) == 1, "enum fields are logged as u8");
  return FieldSpec{name, FieldTraits<U>::type, offset, FieldTraits<U>::count, unit};
}
}  // namespace detail

// One field of a record struct: ROBOSSIS_LOG_FIELD(LeaderTickRecord, p_OH, "m").
#define ROBOSSIS_LOG_FIELD(Struct, member, unit) \
  ::robossis::teleop::detail::Describe<decltype(Struct::member)>(#member, offsetof(Struct, member), unit)

// [assumed] The writer's buffer: at most this much (plus one record) waits in memory for a write(2); 1 MiB is ~1000
// follower ticks, few enough write calls that the buffering still pays, small beside a run's other memory.
inline constexpr std::size_t kSessionLogBufferBytes = std::size_t{1} << 20;

class SessionLogWriter {
 public:
  // Creates (truncates) the file and writes the header. Throws std::runtime_error naming the file.
  SessionLogWriter(const std::filesystem::path& file, const nlohmann::json& meta, std::vector<StreamSpec> streams);
  ~SessionLogWriter();
  SessionLogWriter(const SessionLogWriter&) = delete;
  SessionLogWriter& operator=(const SessionLogWriter&) = delete;

  // Appends one record of a stream (its record_size bytes at `record`); flushes once kSessionLogBufferBytes are
  // buffered (then throws as Flush() does).
  void Append(std::uint8_t stream_id, const void* record);
  // Hands everything appended to the kernel. Throws std::runtime_error on a write error.
  void Flush();
  std::uint64_t frames() const { return frames_; }
  std::size_t buffered_bytes() const { return buffer_.size(); }  // appended, not yet handed to the kernel
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  int fd_ = -1;
  std::vector<StreamSpec> streams_;
  std::vector<char> buffer_;
  std::uint64_t frames_ = 0;
};

// A whole log read back: the header and each stream's records (raw bytes, record_size apart).
struct SessionLog {
  int version = 0;
  nlohmann::json meta;
  std::vector<StreamSpec> streams;
  std::vector<std::vector<char>> records;  // per stream, in stream order
  bool truncated = false;                  // the last frame was cut short (a crash)

  const StreamSpec* Find(const std::string& name) const;
  std::size_t count(const StreamSpec& s) const;
  // Copies record i of stream s into `out` after checking that the stream's layout is exactly `expected`'s (the
  // struct this program compiled). Throws std::runtime_error naming the stream and the field that differs.
  template <typename T>
  std::vector<T> Decode(const std::string& name, const StreamSpec& expected) const;
};

// Hands all of `bytes` to the kernel (write(2), again after EINTR or a short write). Throws std::runtime_error
// "`what`: strerror" on a write error (a full disk).
void WriteAll(int fd, std::string_view bytes, const std::string& what);

// Bounds of a log read back. Size: an hour (the longest session) of 1 kHz leader and 10 kHz follower records of
// under 512 bytes is ~20 GB; a larger file is not a log this program wrote. Values: every f64 of a record is finite
// and at most 1e6 in SI units (m, rad, N, s): far above any pose, force or time of a session.
inline constexpr std::uintmax_t kMaxSessionLogBytes = std::uintmax_t{32} << 30;  // 32 GiB
inline constexpr double kMaxSessionLogMagnitudeSi = 1e6;

// Reads a log. Throws std::runtime_error naming the file and what is wrong (magic, version, header, a field outside
// its record, a non-finite number in the header, a record value that is not finite or above
// kMaxSessionLogMagnitudeSi: "record N of stream 'leader', field 'p_OH[0]': got 1e+300; ...").
SessionLog ReadSessionLog(const std::filesystem::path& file);

// Throws std::runtime_error if `actual` does not have `expected`'s record size and fields.
void CheckSameLayout(const StreamSpec& actual, const StreamSpec& expected, const std::string& where);

template <typename T>
std::vector<T> SessionLog::Decode(const std::string& name, const StreamSpec& expected) const {
  static_assert(std::is_trivially_copyable_v<T> || std::is_standard_layout_v<T>, "plain records");
  std::vector<T> out;
  const StreamSpec* s = Find(name);
  if (s == nullptr) return out;
  CheckSameLayout(*s, expected, "stream '" + name + "'");
  const std::size_t index = static_cast<std::size_t>(s - streams.data());
  const std::size_t n = count(*s);
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::memcpy(static_cast<void*>(&out[i]), records[index].data() + i * s->record_size, sizeof(T));
  }
  return out;
}

}  // namespace robossis::teleop
