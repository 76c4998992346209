// Hostile inputs of the readers: files that are not regular files, a second YAML document, absurd values in a
// Motive export, an HC CSV and a session log, conflicting reference columns and numbers too large for a double in a
// log's header. Each runs the robossis binary as a user would.

#include <sys/stat.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/hostile_cli_test.h"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using robossis::testing::CommandRun;
using robossis::testing::Robossis;

class HostileReadersTest : public robossis::testing::HostileCliTest {
 protected:
  // A Motive 1.23 export of one rigid body 'A' at 100 Hz; `rows` are the data rows after the 'Frame' row.
  fs::path Take(const std::string& rows, int total_frames = 3) const {
    return Write("take.csv",
                 "Format Version,1.23,Take Name,t,Capture Frame Rate,100,Export Frame Rate,100,Total Exported Frames," +
                     std::to_string(total_frames) + ",Rotation Type,Quaternion,Length Units,Meters\n\n"
                     ",,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body\n"
                     ",,A,A,A,A,A,A,A\n"
                     ",,1,1,1,1,1,1,1\n"
                     ",,Rotation,Rotation,Rotation,Rotation,Position,Position,Position\n"
                     "Frame,Time (Seconds),X,Y,Z,W,X,Y,Z\n" + rows);
  }
  static std::string GoodRows() {
    return "0,0.000,0,0,0,1,0.1,0.2,0.3\n1,0.010,0,0,0,1,0.1,0.2,0.3\n2,0.020,0,0,0,1,0.1,0.2,0.3\n";
  }
  // A short simulated session's log (its header and records as the flight recorder wrote them).
  std::string SessionLog() const {
    const fs::path out = dir_ / "session";
    const std::string hand = (robossis::DefaultDataDir() / "teleop" / "fast_hand.csv").string();
    const CommandRun run = Robossis("teleop --device replay:" + Q(hand) + " --method proxy-safe --follower sim "
                                    "--rate-hz 1000 --duration-s 0.2 --clock simulated --no-plots --out " + Q(out));
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return Read(out / "session.rlog");
  }
  static nlohmann::json Header(const std::string& log, std::uint32_t* length) {
    std::memcpy(length, log.data() + 8, sizeof *length);
    return nlohmann::json::parse(log.substr(12, *length));
  }
};

TEST_F(HostileReadersTest, NonRegularFilesAreRefusedBeforeAnyRead) {
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // A FIFO with no writer and /dev/zero hung or read until out of memory; a directory was "empty".
  for (const std::string& input : {fifo.string(), std::string("/dev/zero"), dir_.string()}) {
    ExpectError(Robossis("replay " + Q(input) + " --no-plots --out " + Q(dir_ / "r")), "expected a regular file");
    ExpectError(Robossis("mocap inspect " + Q(input)), "expected a regular file");
    ExpectError(Robossis("transfer --hc " + Q(input) + " --no-plots --out " + Q(dir_ / "t")),
                "expected a regular file");
  }
  const fs::path data = dir_ / "data";
  fs::create_directories(data);
  fs::copy(robossis::DefaultDataDir() / "config", data / "config", fs::copy_options::recursive);
  fs::remove(data / "config" / "rsr.yaml");
  ASSERT_EQ(::mkfifo((data / "config" / "rsr.yaml").c_str(), 0600), 0);
  ExpectError(Robossis("--data-dir " + Q(data) + " robot info"), "expected a regular file (YAML config file)");
}

TEST_F(HostileReadersTest, ASecondYamlDocumentIsRefusedWithItsLine) {
  const fs::path data = dir_ / "data";
  fs::create_directories(data);
  fs::copy(robossis::DefaultDataDir() / "config", data / "config", fs::copy_options::recursive);
  const std::string rsr = Read(data / "config" / "rsr.yaml");
  std::size_t lines = 0;
  for (char c : rsr) lines += c == '\n';
  Write("data/config/rsr.yaml", rsr + "---\nlimits: {}\n");
  ExpectError(Robossis("--data-dir " + Q(data) + " robot info"),
              "rsr.yaml line " + std::to_string(lines + 1) + ": a second YAML document");
}

TEST_F(HostileReadersTest, MotiveExportWithAbsurdValuesIsRefusedNamingRowAndColumn) {
  ASSERT_EQ(Robossis("mocap inspect " + Q(Take(GoodRows()))).exit_code, 0);
  ExpectError(Robossis("mocap inspect " + Q(Take("0,0.000,0,0,0,1,1e30,0.2,0.3\n1,0.010,0,0,0,1,0.1,0.2,0.3\n"
                                                 "2,0.020,0,0,0,1,0.1,0.2,0.3\n"))),
              "take.csv line 8, column 7: got '1e30'; expected a position within");
  ExpectError(Robossis("mocap inspect " + Q(Take("0,0.000,0,0,0,5,0.1,0.2,0.3\n1,0.010,0,0,0,1,0.1,0.2,0.3\n"
                                                 "2,0.020,0,0,0,1,0.1,0.2,0.3\n"))),
              "take.csv line 8, columns 3-6 (rigid body 'A' Rotation X, Y, Z, W): quaternion norm 5");
  ExpectError(Robossis("mocap inspect " + Q(Take("0,0.000,0,0,0,1,0.1,0.2,0.3\n1,0.010,0,0,0,1,0.1\n"
                                                 "2,0.020,0,0,0,1,0.1,0.2,0.3\n"))),
              "take.csv line 9, column 8: the row ends after 7 cells; expected 9");
  ExpectError(Robossis("mocap inspect " + Q(Take("0,0.000,0,0,0,1,0.1,0.2,0.3\n1,0.500,0,0,0,1,0.1,0.2,0.3\n"
                                                 "2,0.600,0,0,0,1,0.1,0.2,0.3\n"))),
              "take.csv line 9, column 2 (Time): got '0.500'; expected 0.010000 s");
  // More rows than the export wrote is an edited file; fewer is an excerpt, read as it is and said so.
  ExpectError(Robossis("mocap inspect " + Q(Take(GoodRows(), 2))),
              "3 frames; the header's 'Total Exported Frames' is 2 (more rows than the export wrote");
  const CommandRun excerpt = Robossis("mocap inspect " + Q(Take(GoodRows(), 300)));
  EXPECT_EQ(excerpt.exit_code, 0) << excerpt.output;
  EXPECT_THAT(excerpt.output, HasSubstr("excerpt: 3 frames read of the header's 300"));
}

TEST_F(HostileReadersTest, ReferenceWithTwoColumnSetsForOneQuantityIsRefused) {
  const std::string rows = "0,0,0,0.284,1,0,0,0,0,0,0\n1,0,0,0.284,1,0,0,0,0,0,0\n";
  ExpectError(Robossis("mocap simulate --reference " +
                       Q(Write("ref.csv", "t_s,x_m,y_m,z_m,qw,qx,qy,qz,roll_deg,pitch_deg,yaw_deg\n" + rows)) +
                       " --out " + Q(dir_ / "o")),
              "conflicting orientation columns 'qw' and 'roll_deg'");
  ExpectError(Robossis("mocap simulate --reference " +
                       Q(Write("ref2.csv", "t_s,x_m,y_m,z_m,qw,qx,qy,qz,x_mm,y_mm,z_mm\n" + rows)) + " --out " +
                       Q(dir_ / "o")),
              "conflicting position columns 'x_m' and 'x_mm'");
}

TEST_F(HostileReadersTest, HcCsvWithAbsurdPoseIsRefusedNamingRowAndColumn) {
  const std::string header = "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n";
  ExpectError(Robossis("transfer --hc " + Q(Write("hc.csv", header + "0,0,0,0,0,0,0\n0.001,1e9,0,0,0,0,0\n")) +
                       " --no-plots --out " + Q(dir_ / "o")),
              "hc.csv line 3, column 2 (x_mm): got '1e9'; expected a position within +-1000 mm");
  ExpectError(Robossis("transfer --hc " + Q(Write("hc2.csv", header + "0,0,0,0,1e6,0,0\n0.001,0,0,0,0,0,0\n")) +
                       " --no-plots --out " + Q(dir_ / "o")),
              "hc2.csv line 2, column 5 (roll_deg): got '1e6'; expected an angle within +-3600 deg");
  EXPECT_FALSE(fs::exists(dir_ / "o"));
}

TEST_F(HostileReadersTest, SessionLogWithAbsurdRecordOrInfiniteHeaderIsRefused) {
  const std::string log = SessionLog();
  ASSERT_GT(log.size(), 12u);
  std::uint32_t length = 0;
  const nlohmann::json header = Header(log, &length);
  // The first leader record: walk the frames (u8 stream id, then the record) to the first of stream 0.
  std::vector<std::size_t> sizes;
  std::size_t p_offset = 0;
  for (const auto& s : header["streams"]) {
    sizes.push_back(s["record_size"].get<std::size_t>());
    if (s["name"] == "leader") {
      for (const auto& f : s["fields"]) {
        if (f["name"] == "p_OH") p_offset = f["offset"].get<std::size_t>();
      }
    }
  }
  std::size_t pos = 12 + length;
  while (pos < log.size() && static_cast<unsigned char>(log[pos]) != 0) {
    pos += 1 + sizes.at(static_cast<unsigned char>(log[pos]));
  }
  ASSERT_LT(pos, log.size());
  for (const double bad : {1e300, std::nan("")}) {
    std::string corrupt = log;
    std::memcpy(corrupt.data() + pos + 1 + p_offset, &bad, sizeof bad);
    ExpectError(Robossis("replay " + Q(Write("bad.rlog", corrupt)) + " --no-plots --out " + Q(dir_ / "r")),
                "record 0 of stream 'leader', field 'p_OH[0]': got " + std::string(bad > 0 ? "1e+300" : "nan"));
  }
  // A number that overflows a double in the header (nlohmann refused it in its own words, "[json.exception...]").
  std::string text = log.substr(12, length);
  const std::size_t key = text.find("\"version\":1");
  ASSERT_NE(key, std::string::npos);
  text.replace(key, 11, "\"version\":1,\"x\":1e999");
  const std::uint32_t new_length = static_cast<std::uint32_t>(text.size());
  std::string infinite = log.substr(0, 8);
  infinite.append(reinterpret_cast<const char*>(&new_length), sizeof new_length);
  infinite += text + log.substr(12 + length);
  ExpectError(Robossis("replay " + Q(Write("inf.rlog", infinite)) + " --no-plots --out " + Q(dir_ / "r")),
              "the session log header: a number too large for a double");
  EXPECT_FALSE(fs::exists(dir_ / "r"));
}

}  // namespace
