#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "src/core/csv.h"

namespace robossis {
namespace {

using ::testing::HasSubstr;

std::filesystem::path WriteCsv(const std::string& name, const std::string& text) {
  // One file per process: CTest runs these tests in parallel processes.
  const auto path = std::filesystem::temp_directory_path() /
                    ("robossis_csv_test_" + name + "_" + std::to_string(::getpid()) + ".csv");
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

CsvSpec TimedSpec() {
  CsvSpec spec;
  spec.columns = {"t_s", "x_mm"};
  spec.what = "test CSV";
  spec.time_column = "t_s";
  spec.max_time = 100;
  return spec;
}

std::string ErrorOf(const std::string& text, const CsvSpec& spec = TimedSpec()) {
  try {
    ReadNumericCsv(WriteCsv("case", text), spec);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(SplitCsvRecordTest, HandlesQuotesEscapesBlanksAndTrailingComma) {
  EXPECT_EQ(SplitCsvRecord(" a , \"b,c\" ,\"d\"\"e\",", "x"), (std::vector<std::string>{"a", "b,c", "d\"e", ""}));
  EXPECT_THROW(SplitCsvRecord("\"open", "x"), std::invalid_argument);
  EXPECT_THROW(SplitCsvRecord("\"a\"b,c", "x"), std::invalid_argument);
}

TEST(NumericCsvTest, ReadsBomQuotedHeaderAndCrLf) {
  const NumericCsv csv = ReadNumericCsv(WriteCsv("bom", "\xEF\xBB\xBF\"t_s\",x_mm\r\n0,1\r\n\r\n0.5,\"2\"\r\n"), TimedSpec());
  ASSERT_EQ(csv.rows.size(), 2u);
  EXPECT_EQ(csv.rows[1].line, 4);
  EXPECT_DOUBLE_EQ(csv.rows[1].values[1], 2.0);
}

TEST(NumericCsvTest, ErrorsNameFileLineColumnValueAndExpectation) {
  const std::string extra = ErrorOf("t_s,x_mm\n0,1\n1,2,3\n");
  EXPECT_THAT(extra, HasSubstr(".csv line 3: 3 cells; expected exactly 2"));
  EXPECT_THAT(ErrorOf("t_s,x_mm\n0,abc\n"), HasSubstr("line 2, column 2 (x_mm): got 'abc'; expected a finite number"));
  EXPECT_THAT(ErrorOf("t_s,x_mm\n0,nan\n"), HasSubstr("got 'nan'; expected a finite number"));
  EXPECT_THAT(ErrorOf("t_s,x_mm\n0,inf\n"), HasSubstr("got 'inf'; expected a finite number"));
  EXPECT_THAT(ErrorOf("t_s,x_mm\n1,0\n1,0\n"), HasSubstr("line 3, column 1 (t_s): got '1'; expected a time greater than 1"));
  EXPECT_THAT(ErrorOf("t_s,x_mm\n0,0\n1e9,0\n"), HasSubstr("got '1e9'; expected a time in [0, 100]"));
  EXPECT_THAT(ErrorOf("t_s,t_s\n0,0\n"), HasSubstr("'t_s' appears twice (columns 1 and 2)"));
  EXPECT_THAT(ErrorOf("x_mm,t_s\n0,0\n"), HasSubstr("line 1, column 1: header name 'x_mm'; expected 't_s'"));
  EXPECT_THAT(ErrorOf("t_s\n0\n"), HasSubstr("missing column 'x_mm'"));
  EXPECT_THAT(ErrorOf(""), HasSubstr("is empty"));
  EXPECT_THAT(ErrorOf("\"t_s,x_mm\n"), HasSubstr("unterminated quote"));
}

TEST(NumericCsvTest, OptionalColumnsInAnyOrderAndEqualTimes) {
  CsvSpec spec = TimedSpec();
  spec.optional_columns = {"clutch"};
  spec.any_order = true;
  spec.allow_equal_times = true;
  const NumericCsv csv = ReadNumericCsv(WriteCsv("any", "clutch,x_mm,t_s\n1,2,0\n0,3,0\n"), spec);
  EXPECT_EQ(csv.Column("t_s"), 2);
  EXPECT_EQ(csv.Column("missing"), -1);
  EXPECT_EQ(csv.rows.size(), 2u);
  EXPECT_THAT(ErrorOf("t_s,x_mm,bogus\n0,1,2\n", spec), HasSubstr("header name 'bogus'; expected a known column"));
}

TEST(NumericCsvTest, SizeAndRowBoundsAreCheckedBeforeWork) {
  CsvSpec spec = TimedSpec();
  spec.max_bytes = 10;
  EXPECT_THAT(ErrorOf("t_s,x_mm\n0,1\n1,2\n", spec), HasSubstr("bytes; expected a test CSV of at most 10 bytes"));
  spec = TimedSpec();
  spec.max_rows = 1;
  EXPECT_THAT(ErrorOf("t_s,x_mm\n0,1\n1,2\n", spec), HasSubstr("more than 1 data rows"));
  spec = TimedSpec();
  spec.min_rows = 2;
  EXPECT_THAT(ErrorOf("t_s,x_mm\n0,1\n", spec), HasSubstr("1 data rows; expected at least 2"));
}

TEST(NumericCsvTest, DirectoryAndDeviceAreNotCalledEmpty) {
  EXPECT_THAT(ErrorOf("", TimedSpec()), HasSubstr("is empty"));
  try {
    ReadNumericCsv(std::filesystem::temp_directory_path(), TimedSpec());
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("expected a regular file (test CSV); it is a directory"));
  }
  EXPECT_THROW(ReadNumericCsv("/dev/zero", TimedSpec()), std::runtime_error);
  EXPECT_THROW(ReadNumericCsv("/nonexistent.csv", TimedSpec()), std::runtime_error);
}

}  // namespace
}  // namespace robossis
