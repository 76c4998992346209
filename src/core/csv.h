#pragma once
// The one strict CSV reader for the project's numeric files (trajectories, HC tracks, references, calibration):
// a UTF-8 byte-order mark is skipped, fields may be quoted ("a,b", "" for a quote), the header must be exactly the
// expected one with no name twice, every row has exactly as many cells as the header, every cell is one finite
// number, and an optional time column increases strictly and stays within a bound. Every error names the file,
// the line, the column, the value and what was expected. Files and row counts are bounded before any work starts.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "src/core/files.h"  // ReadBoundedFile, the one opener of input files

namespace robossis {

// Splits one CSV record (no line break inside) into its fields: quotes removed, "" inside quotes is a quote,
// blanks around a field removed. Throws std::invalid_argument on an unterminated quote or text after a closing
// quote; `where` prefixes the message ("file line 3").
std::vector<std::string> SplitCsvRecord(std::string_view line, const std::string& where);

struct CsvSpec {
  std::vector<std::string> columns;           // required header names (in this order unless any_order)
  std::vector<std::string> optional_columns;  // may appear (anywhere after the required ones, or anywhere if any_order)
  bool any_order = false;                     // header names in any order; every name must still be known
  std::string what = "CSV file";              // for messages: "trajectory CSV"
  std::uintmax_t max_bytes = 64u << 20;       // file size bound (64 MiB)
  std::size_t max_rows = 1'000'000;           // data rows bound
  std::size_t min_rows = 0;                   // fewer data rows is an error
  std::string time_column;                    // if set: increasing, within [min_time, max_time]
  bool allow_equal_times = false;             // a repeated time stamp (a repeated sample) is allowed
  double min_time = 0.0;
  double max_time = 86'400.0;                 // one day, in the unit of the column
  bool comment_lines = false;                 // lines starting with '#' (after blanks) are skipped, header included
  // Columns whose values are bounded, |value| <= bound (name, bound in the column's unit); absent columns ignored.
  std::vector<std::pair<std::string, double>> max_abs;
};

// The bounds of a pose's columns x_mm, y_mm, z_mm, roll_deg, pitch_deg, yaw_deg (kMaxEdgePositionMm,
// kMaxEdgeAngleDeg), for CsvSpec::max_abs.
std::vector<std::pair<std::string, double>> PoseColumnBounds();

struct CsvRow {
  int line = 0;                // 1-based line in the file
  std::vector<double> values;  // one per header column, in the file's order
};

struct NumericCsv {
  std::vector<std::string> header;  // as in the file
  std::vector<CsvRow> rows;
  // Index of a header name in the file, or -1 if the (optional) column is absent.
  int Column(const std::string& name) const;
};

// Reads a numeric CSV as `spec` describes. Blank lines are skipped. Throws std::runtime_error:
// "traj.csv line 5, column 1 (t_s): got '0.1'; expected a time greater than 0.2 (the previous row's)".
NumericCsv ReadNumericCsv(const std::filesystem::path& file, const CsvSpec& spec);

// The same checks on text already read (a reader that looks at the file before choosing its spec, fuzzing);
// `source_name` names the input in messages. A UTF-8 byte-order mark at the start is skipped.
NumericCsv ParseNumericCsv(std::string_view text, const std::string& source_name, const CsvSpec& spec);

}  // namespace robossis
