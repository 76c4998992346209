// HC trajectory files: clear errors for bad input; the built-in scenarios.

#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "src/core/config.h"
#include "haptics/transfer/hc_trajectory.h"
#include "haptics/transfer/transfer_config.h"

namespace robossis::transfer {
namespace {

using ::testing::HasSubstr;

std::filesystem::path WriteTemp(const std::string& name, const std::string& text) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() / ("robossis_transfer_test_" + name);
  std::ofstream(p) << text;
  return p;
}

std::string ErrorOf(const std::string& name, const std::string& text) {
  try {
    ReadHcCsv(WriteTemp(name, text));
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

const char* kHeader = "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n";

TEST(HcTrajectoryTest, ReadsAValidFile) {
  const HcTrajectory t = ReadHcCsv(WriteTemp("ok.csv", std::string(kHeader) + "0,1,2,3,0,0,0\n0.001,1.1,2,3,0,0,1\n"));
  ASSERT_EQ(t.records.size(), 2u);
  EXPECT_DOUBLE_EQ(t.records[1].pose_mm_deg[0], 1.1);
  EXPECT_DOUBLE_EQ(t.records[1].arrival_s, 0.001);
}

TEST(HcTrajectoryTest, MissingColumnIsNamed) {
  EXPECT_THAT(ErrorOf("missing.csv", "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg\n0,1,2,3,0,0\n0.1,1,2,3,0,0\n"),
              HasSubstr("missing column 'yaw_deg'"));
}

TEST(HcTrajectoryTest, NonMonotonicTimeIsRejected) {
  EXPECT_THAT(ErrorOf("order.csv", std::string(kHeader) + "0.002,1,2,3,0,0,0\n0.001,1,2,3,0,0,0\n"),
              HasSubstr("line 3, column 1 (time_s): got '0.001'; expected a time not before 0.002"));
}

TEST(HcTrajectoryTest, NanIsRejectedWithItsColumn) {
  EXPECT_THAT(ErrorOf("nan.csv", std::string(kHeader) + "0,1,2,3,0,0,0\n0.001,nan,2,3,0,0,0\n"),
              HasSubstr("line 3, column 2 (x_mm): got 'nan'; expected a finite number"));
}

TEST(HcTrajectoryTest, ShortRowAndBadClutchAreRejected) {
  EXPECT_THAT(ErrorOf("short.csv", std::string(kHeader) + "0,1,2,3,0,0,0\n0.001,1,2\n"), HasSubstr("line 3: 3 cells"));
  EXPECT_THAT(ErrorOf("clutch.csv", "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,clutch\n0,1,2,3,0,0,0,2\n"
                                         "0.1,1,2,3,0,0,0,1\n"),
              HasSubstr("(clutch): got '2'; expected 0 or 1"));
}

TEST(HcTrajectoryTest, EmptyFileIsRejected) {
  EXPECT_THAT(ErrorOf("empty.csv", ""), HasSubstr("is empty"));
  EXPECT_THAT(ErrorOf("one.csv", std::string(kHeader) + "0,1,2,3,0,0,0\n"), HasSubstr("expected at least 2"));
}

TEST(HcTrajectoryTest, ExtraCellsUnknownOrRepeatedColumnsAndUnboundedTimesAreRejected) {
  EXPECT_THAT(ErrorOf("extra.csv", std::string(kHeader) + "0,1,2,3,0,0,0\n0.1,1,2,3,0,0,0,5\n"),
              HasSubstr("line 3: 8 cells; expected exactly 7"));
  EXPECT_THAT(ErrorOf("dup.csv", "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,x_mm\n0,1,2,3,0,0,0,1\n"),
              HasSubstr("'x_mm' appears twice (columns 2 and 8)"));
  EXPECT_THAT(ErrorOf("typo.csv", "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,arival_s\n0,1,2,3,0,0,0,1\n"),
              HasSubstr("column 8: header name 'arival_s'; expected a known column"));
  EXPECT_THAT(ErrorOf("negative.csv", std::string(kHeader) + "-5,1,2,3,0,0,0\n0,1,2,3,0,0,0\n"),
              HasSubstr("line 2, column 1 (time_s): got '-5'; expected a time in [0, 600]"));
  EXPECT_THAT(ErrorOf("late.csv", "time_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,arrival_s\n0,1,2,3,0,0,0,1e6\n"
                                  "0.1,1,2,3,0,0,0,0.1\n"),
              HasSubstr("(arrival_s): got"));
}

TEST(HcTrajectoryTest, BomAndQuotedHeadersAreRead) {
  const HcTrajectory t = ReadHcCsv(WriteTemp(
      "bom.csv", "\xEF\xBB\xBF\"time_s\",\"x_mm\",y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\r\n0,1,2,3,0,0,0\r\n0.1,\"2\",2,3,0,0,0\r\n"));
  ASSERT_EQ(t.records.size(), 2u);
  EXPECT_DOUBLE_EQ(t.clean_records[1].pose_mm_deg[0], 2.0);
}

TEST(HcTrajectoryTest, Fig8ScenarioHasTheBreakage) {
  const HcTrajectory t = MakeScenario("fig8");
  EXPECT_LT(t.records.size(), t.clean_records.size());  // dropouts
  bool stalled = false, late = false;
  for (std::size_t i = 1; i < t.records.size(); ++i) {
    stalled = stalled || t.records[i].arrival_s - t.records[i].time_s > 0.1;
    late = late || t.records[i].time_s < t.records[i - 1].time_s;
  }
  EXPECT_TRUE(stalled);
  EXPECT_TRUE(late);
  EXPECT_THROW(MakeScenario("nope"), std::invalid_argument);
}

TEST(TransferConfigTest, DefaultYamlLoadsAndBadValuesAreNamed) {
  const std::filesystem::path dir = DefaultDataDir() / "config";
  const TransferConfig c = TransferConfig::FromYaml(dir / "transfer.yaml");
  EXPECT_DOUBLE_EQ(c.caps.max_linear_speed_m_s, 0.010);  // [paper] 10 mm/s
  std::ifstream in(dir / "transfer.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string bad = text.replace(text.find("moving_average_window: 50"), 25, "moving_average_window: 0");
  try {
    TransferConfig::FromYaml(WriteTemp("bad.yaml", bad));
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("filter.moving_average_window"));
  }
}

}  // namespace
}  // namespace robossis::transfer
