#include "src/core/csv.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "src/core/parse.h"

namespace robossis {

namespace fs = std::filesystem;

namespace {

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::string Joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ",") + n;
  return out;
}

std::string Number(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

}  // namespace

std::vector<std::string> SplitCsvRecord(std::string_view line, const std::string& where) {
  std::vector<std::string> fields;
  std::size_t i = 0;
  while (true) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::string field;
    if (i < line.size() && line[i] == '"') {
      ++i;
      bool closed = false;
      while (i < line.size()) {
        if (line[i] == '"') {
          if (i + 1 < line.size() && line[i + 1] == '"') {
            field += '"';
            i += 2;
            continue;
          }
          closed = true;
          ++i;
          break;
        }
        field += line[i++];
      }
      if (!closed) {
        throw std::invalid_argument(where + ", field " + std::to_string(fields.size() + 1) +
                                    ": unterminated quote; expected a closing '\"'");
      }
      const std::size_t comma = line.find(',', i);
      const std::string_view rest = Trim(line.substr(i, comma == std::string_view::npos ? line.npos : comma - i));
      if (!rest.empty()) {
        throw std::invalid_argument(where + ", field " + std::to_string(fields.size() + 1) + ": text '" +
                                    std::string(rest) + "' after a closing quote; expected ',' or the end of the line");
      }
      i = comma;
    } else {
      const std::size_t comma = line.find(',', i);
      field = std::string(Trim(line.substr(i, comma == std::string_view::npos ? line.npos : comma - i)));
      i = comma;
    }
    fields.push_back(std::move(field));
    if (i == std::string_view::npos || i >= line.size()) break;
    ++i;  // past the comma
    if (i == line.size()) {
      fields.emplace_back();  // a trailing comma ends with an empty field
      break;
    }
  }
  return fields;
}

NumericCsv ReadNumericCsv(const fs::path& file, const CsvSpec& spec) {
  return ParseNumericCsv(ReadBoundedFile(file, spec.max_bytes, spec.what), file.string(), spec);
}

NumericCsv ParseNumericCsv(std::string_view text, const std::string& name, const CsvSpec& spec) {
  if (text.size() > spec.max_bytes) {
    throw std::runtime_error(name + ": " + std::to_string(text.size()) + " bytes; expected a " + spec.what +
                             " of at most " + std::to_string(spec.max_bytes) + " bytes");
  }
  const std::string expected_header = Joined(spec.columns);
  std::string_view rest(text);
  if (rest.substr(0, 3) == "\xEF\xBB\xBF") rest.remove_prefix(3);  // UTF-8 byte-order mark (spreadsheet exports)
  NumericCsv out;
  int line_number = 0;
  bool have_header = false;
  int time_index = -1;
  double previous_time = 0.0;
  std::string previous_time_text;
  std::vector<double> bound;  // per column of the header: |value| <= bound
  while (!rest.empty()) {
    const std::size_t eol = rest.find('\n');
    std::string_view line = rest.substr(0, eol);
    rest = eol == std::string_view::npos ? std::string_view() : rest.substr(eol + 1);
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::string where = name + " line " + std::to_string(line_number);
    if (spec.comment_lines) {
      const std::string_view trimmed = Trim(line);
      if (trimmed.empty() || trimmed.front() == '#') continue;
    }
    if (!have_header) {
      if (line.empty()) {
        throw std::runtime_error(where + ": empty line; expected the header '" + expected_header + "'");
      }
      std::vector<std::string> header;
      try {
        header = SplitCsvRecord(line, where);
      } catch (const std::invalid_argument& e) {
        throw std::runtime_error(e.what());
      }
      std::map<std::string, std::size_t> seen;
      for (std::size_t c = 0; c < header.size(); ++c) {
        const auto [it, inserted] = seen.emplace(header[c], c);
        if (!inserted) {
          throw std::runtime_error(where + ": column name '" + header[c] + "' appears twice (columns " +
                                   std::to_string(it->second + 1) + " and " + std::to_string(c + 1) +
                                   "); expected the header '" + expected_header + "'");
        }
      }
      const std::string format =
          expected_header + (spec.optional_columns.empty() ? "" : "[," + Joined(spec.optional_columns) + "]");
      for (std::size_t c = 0; c < header.size(); ++c) {
        const bool required = std::find(spec.columns.begin(), spec.columns.end(), header[c]) != spec.columns.end();
        const bool optional = std::find(spec.optional_columns.begin(), spec.optional_columns.end(), header[c]) !=
                              spec.optional_columns.end();
        const bool in_place = spec.any_order || c >= spec.columns.size() ? (required || optional)
                                                                          : header[c] == spec.columns[c];
        if (!in_place) {
          throw std::runtime_error(where + ", column " + std::to_string(c + 1) + ": header name '" + header[c] +
                                   "'; expected " +
                                   (!spec.any_order && c < spec.columns.size() ? "'" + spec.columns[c] + "'"
                                                                               : std::string("a known column")) +
                                   " (the header is " + format + (spec.any_order ? ", in any order)" : ")"));
        }
      }
      for (const std::string& required : spec.columns) {
        if (seen.count(required) == 0) {
          throw std::runtime_error(where + ": missing column '" + required + "'; expected the header " + format);
        }
      }
      out.header = header;
      time_index = spec.time_column.empty() ? -1 : out.Column(spec.time_column);
      bound.assign(header.size(), std::numeric_limits<double>::infinity());
      for (const auto& [column, max_abs] : spec.max_abs) {
        if (const int i = out.Column(column); i >= 0) bound[static_cast<std::size_t>(i)] = max_abs;
      }
      have_header = true;
      continue;
    }
    if (Trim(line).empty()) continue;
    if (out.rows.size() >= spec.max_rows) {
      throw std::runtime_error(where + ": more than " + std::to_string(spec.max_rows) + " data rows; expected at most " +
                               std::to_string(spec.max_rows) + " in a " + spec.what);
    }
    std::vector<std::string> cells;
    try {
      cells = SplitCsvRecord(line, where);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(e.what());
    }
    if (cells.size() != out.header.size()) {
      throw std::runtime_error(where + ": " + std::to_string(cells.size()) + " cells; expected exactly " +
                               std::to_string(out.header.size()) + ", one per header column (" + Joined(out.header) +
                               ")");
    }
    CsvRow row;
    row.line = line_number;
    row.values.resize(cells.size());
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::string cell_where =
          where + ", column " + std::to_string(c + 1) + " (" + out.header[c] + "): got '" + cells[c] + "'";
      if (!TryParseNumber(cells[c], &row.values[c])) throw std::runtime_error(cell_where + "; expected a finite number");
      if (static_cast<int>(c) == time_index) {
        const double t = row.values[c];
        if (t < spec.min_time || t > spec.max_time) {
          throw std::runtime_error(cell_where + "; expected a time in [" + Number(spec.min_time) + ", " +
                                   Number(spec.max_time) + "]");
        }
        if (!out.rows.empty() && (spec.allow_equal_times ? t < previous_time : !(t > previous_time))) {
          throw std::runtime_error(cell_where + "; expected a time " +
                                   (spec.allow_equal_times ? "not before " : "greater than ") + previous_time_text +
                                   " (the previous row's): times must " +
                                   (spec.allow_equal_times ? "not decrease" : "increase strictly"));
        }
        previous_time = t;
        previous_time_text = std::string(TrimField(cells[c]));  // the bound as the file wrote it
      }
      if (!(std::fabs(row.values[c]) <= bound[c])) {
        const std::string& name = out.header[c];
        const auto unit = [&](const std::string& u) {
          return name.size() > u.size() && name.compare(name.size() - u.size(), u.size(), u) == 0;
        };
        throw std::runtime_error(cell_where + "; expected " +
                                 (unit("_mm")    ? "a position within +-" + Number(bound[c]) + " mm"
                                  : unit("_deg") ? "an angle within +-" + Number(bound[c]) + " deg"
                                                 : "a value within +-" + Number(bound[c])));
      }
    }
    out.rows.push_back(std::move(row));
  }
  if (!have_header) {
    const bool only_bom = text.size() == 3 && text.substr(0, 3) == "\xEF\xBB\xBF";
    const std::string content = text.empty() ? "0 bytes" : only_bom ? "0 bytes after the byte-order mark"
                                                                     : "only comments and blank lines";
    throw std::runtime_error(name + ": the " + spec.what + " is empty (" + content + "); expected the header '" +
                             expected_header + "'");
  }
  if (out.rows.size() < spec.min_rows) {
    throw std::runtime_error(name + ": " + std::to_string(out.rows.size()) + " data rows; expected at least " +
                             std::to_string(spec.min_rows) + " in a " + spec.what);
  }
  return out;
}

std::vector<std::pair<std::string, double>> PoseColumnBounds() {
  return {{"x_mm", kMaxEdgePositionMm},   {"y_mm", kMaxEdgePositionMm},    {"z_mm", kMaxEdgePositionMm},
          {"roll_deg", kMaxEdgeAngleDeg}, {"pitch_deg", kMaxEdgeAngleDeg}, {"yaw_deg", kMaxEdgeAngleDeg}};
}

int NumericCsv::Column(const std::string& name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  return it == header.end() ? -1 : static_cast<int>(it - header.begin());
}

}  // namespace robossis
