// The flight recorder's session log: records come back byte for byte with a header that describes them, a log cut
// short (a crash mid-write) keeps everything before the cut, a killed writer process leaves a readable log, and a
// log whose layout differs from this program's is refused with the field named.

#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "src/core/files.h"
#include "src/core/rt/spsc_queue.h"
#include "src/teleop/flight_recorder.h"

namespace robossis::teleop {
namespace {

std::filesystem::path TempLog(const std::string& name) { return std::filesystem::temp_directory_path() / name; }

LeaderTickRecord Record(std::uint64_t k) {
  LeaderTickRecord r;
  r.tick = k;
  r.t_ns = static_cast<std::int64_t>(k) * 1'000'000;
  r.p_OH = {0.001 * k, -0.5, 0.25};
  r.f_O = {1.5, 0, -2};
  r.leader_state = 1;
  return r;
}

TEST(FlightRecorderTest, RecordsComeBackWithASelfDescribingHeader) {
  const auto file = TempLog("robossis_fr_roundtrip.rlog");
  {
    SessionLogWriter log(file, {{"method", "proxy"}, {"rate_hz", 1000}}, {LeaderStreamSpec()});
    rt::SpscQueue<LeaderTickRecord> queue(64);
    FlightRecorder recorder(log, [&](SessionLogWriter& w) {
      LeaderTickRecord r;
      while (queue.TryPop(r)) w.Append(kLeaderStream, &r);
    });
    recorder.Start();
    for (std::uint64_t k = 0; k < 500; ++k) {
      while (!queue.TryPush(Record(k))) std::this_thread::yield();
    }
    EXPECT_EQ(recorder.Stop(), "");
    EXPECT_EQ(log.frames(), 500u);
  }
  const SessionLog log = ReadSessionLog(file);
  EXPECT_EQ(log.version, 1);
  EXPECT_EQ(log.meta.at("method"), "proxy");
  EXPECT_FALSE(log.truncated);
  const StreamSpec* s = log.Find("leader");
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->record_size, sizeof(LeaderTickRecord));
  // The header alone locates a field: p_OH[0] of record 7.
  const auto field = std::find_if(s->fields.begin(), s->fields.end(), [](const FieldSpec& f) { return f.name == "p_OH"; });
  ASSERT_NE(field, s->fields.end());
  EXPECT_EQ(field->type, FieldType::kF64);
  EXPECT_EQ(field->count, 3);
  EXPECT_EQ(field->unit, "m");
  double x = 0;
  std::memcpy(&x, log.records[0].data() + 7 * s->record_size + field->offset, sizeof x);
  EXPECT_DOUBLE_EQ(x, 0.007);
  const std::vector<LeaderTickRecord> back = log.Decode<LeaderTickRecord>("leader", LeaderStreamSpec());
  ASSERT_EQ(back.size(), 500u);
  for (std::uint64_t k = 0; k < 500; ++k) {
    const LeaderTickRecord expected = Record(k);
    EXPECT_EQ(std::memcmp(&back[k], &expected, sizeof expected), 0) << k;
  }
  std::filesystem::remove(file);
}

TEST(FlightRecorderTest, FollowerRecordsKeepTheLatencyInstants) {
  // The end-to-end latency's two instants (the set-point's device-sample stamp, the joint command's time) are in
  // the follower stream's header with their units and come back from the log.
  const auto file = TempLog("robossis_fr_follower.rlog");
  {
    SessionLogWriter log(file, {}, {LeaderStreamSpec(), FollowerStreamSpec()});  // ids in order
    for (std::uint64_t k = 0; k < 50; ++k) {
      FollowerTickRecord r;
      r.tick = k;
      r.time_s = 1e-4 * static_cast<double>(k);
      r.setpoint_stamp_ns = 1000 * static_cast<std::int64_t>(k) - 7;
      r.command_time_s = r.time_s + 3e-6;
      log.Append(kFollowerStream, &r);
    }
    log.Flush();
  }
  const SessionLog log = ReadSessionLog(file);
  const StreamSpec* s = log.Find("follower");
  ASSERT_NE(s, nullptr);
  for (const auto& [name, unit] : {std::pair<std::string, std::string>{"setpoint_stamp_ns", "ns"},
                                   std::pair<std::string, std::string>{"command_time_s", "s"}}) {
    const auto f = std::find_if(s->fields.begin(), s->fields.end(), [&](const FieldSpec& x) { return x.name == name; });
    ASSERT_NE(f, s->fields.end()) << name;
    EXPECT_EQ(f->unit, unit);
  }
  const std::vector<FollowerTickRecord> back = log.Decode<FollowerTickRecord>("follower", FollowerStreamSpec());
  ASSERT_EQ(back.size(), 50u);
  EXPECT_EQ(back[9].setpoint_stamp_ns, 8993);
  EXPECT_DOUBLE_EQ(back[9].command_time_s, 9e-4 + 3e-6);
  std::filesystem::remove(file);
}

TEST(FlightRecorderTest, ALogCutShortKeepsEverythingBeforeTheCut) {
  const auto file = TempLog("robossis_fr_cut.rlog");
  {
    SessionLogWriter log(file, {}, {LeaderStreamSpec()});
    for (std::uint64_t k = 0; k < 10; ++k) {
      const LeaderTickRecord r = Record(k);
      log.Append(kLeaderStream, &r);
    }
  }
  const auto size = std::filesystem::file_size(file);
  std::filesystem::resize_file(file, size - sizeof(LeaderTickRecord) / 2);  // half of the last frame
  const SessionLog log = ReadSessionLog(file);
  EXPECT_TRUE(log.truncated);
  const auto back = log.Decode<LeaderTickRecord>("leader", LeaderStreamSpec());
  ASSERT_EQ(back.size(), 9u);
  EXPECT_EQ(back.back().tick, 8u);
  std::filesystem::remove(file);
}

// A writer never flushed by its caller (the simulated clock's run) still hands its records to the kernel as it goes:
// its buffer stays under kSessionLogBufferBytes plus one frame however many records, so the memory is flat.
TEST(FlightRecorderTest, TheWritersBufferIsBoundedWithoutFlushes) {
  const auto file = TempLog("robossis_fr_bounded.rlog");
  const std::size_t frame = 1 + sizeof(LeaderTickRecord);
  const std::uint64_t n = 4 * kSessionLogBufferBytes / frame;  // four buffers' worth
  {
    SessionLogWriter log(file, {}, {LeaderStreamSpec()});
    for (std::uint64_t k = 0; k < n; ++k) {
      const LeaderTickRecord r = Record(k);
      log.Append(kLeaderStream, &r);
      ASSERT_LT(log.buffered_bytes(), kSessionLogBufferBytes + frame) << "record " << k;
    }
    EXPECT_GE(std::filesystem::file_size(file), 3 * kSessionLogBufferBytes);  // on disk before the end
  }
  EXPECT_EQ(ReadSessionLog(file).Decode<LeaderTickRecord>("leader", LeaderStreamSpec()).size(), n);
  std::filesystem::remove(file);
}

TEST(FlightRecorderTest, AKilledWriterLeavesAReadableLog) {
  const auto file = TempLog("robossis_fr_killed.rlog");
  std::filesystem::remove(file);
  // The child's count of records pushed, in shared memory.
  auto* pushed = static_cast<std::atomic<std::uint64_t>*>(
      mmap(nullptr, sizeof(std::atomic<std::uint64_t>), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0));
  ASSERT_NE(pushed, MAP_FAILED);
  new (pushed) std::atomic<std::uint64_t>(0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    SessionLogWriter log(file, {}, {LeaderStreamSpec()});
    rt::SpscQueue<LeaderTickRecord> queue(4096);
    FlightRecorder recorder(log, [&](SessionLogWriter& w) {
      LeaderTickRecord r;
      while (queue.TryPop(r)) w.Append(kLeaderStream, &r);
    });
    recorder.Start();
    for (std::uint64_t k = 0;; ++k) {
      while (!queue.TryPush(Record(k))) std::this_thread::yield();
      pushed->store(k + 1);
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  }
  // Killed once the writer is well into its records and the recorder thread has put some on disk: waited for (60 s
  // bound), since on a loaded machine the recorder thread may not have run at all by the time 300 were pushed. The
  // log is read while the child appends to it: a torn tail is what the reader handles after the kill anyway.
  const auto on_disk = [&] {
    try {
      return !ReadSessionLog(file).Decode<LeaderTickRecord>("leader", LeaderStreamSpec()).empty();
    } catch (const std::exception&) {
      return false;  // not even the header yet
    }
  };
  for (int i = 0; i < 12000 && (pushed->load() < 300 || !on_disk()); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  const SessionLog log = ReadSessionLog(file);
  const auto back = log.Decode<LeaderTickRecord>("leader", LeaderStreamSpec());
  ASSERT_GT(back.size(), 0u);
  EXPECT_LE(back.size(), pushed->load());
  for (std::size_t i = 0; i < back.size(); ++i) ASSERT_EQ(back[i].tick, i);  // intact and in order
  munmap(pushed, sizeof(std::atomic<std::uint64_t>));
  std::filesystem::remove(file);
}

// A header the program did not write: a number that is no integer of the field's type is an error naming the field
// (converting 1e300 to a size is undefined behaviour; a libFuzzer run found the same in the atlas manifest).
TEST(FlightRecorderTest, AHeaderNumberOutOfItsTypesRangeIsRefusedNamingTheField) {
  const auto file = TempLog("robossis_fr_huge_record_size.rlog");
  const std::string header =
      R"({"meta": {}, "streams": [{"id": 0, "name": "leader", "record_size": 1e300, "fields": []}]})";
  const auto length = static_cast<std::uint32_t>(header.size());
  std::string bytes = "RBSSLOG1";
  bytes.append(reinterpret_cast<const char*>(&length), sizeof length);
  bytes += header;
  WriteFileAtomically(file, bytes);
  try {
    ReadSessionLog(file);
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("record_size: expected an integer"), std::string::npos) << e.what();
  }
  std::filesystem::remove(file);
}

TEST(FlightRecorderTest, ADifferentLayoutIsRefusedNamingTheField) {
  const auto file = TempLog("robossis_fr_layout.rlog");
  StreamSpec other = LeaderStreamSpec();
  other.fields[3].name = "p_hand";
  {
    SessionLogWriter log(file, {}, {other});
  }
  const SessionLog log = ReadSessionLog(file);
  try {
    log.Decode<LeaderTickRecord>("leader", LeaderStreamSpec());
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("p_hand"), std::string::npos) << e.what();
  }
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace robossis::teleop
