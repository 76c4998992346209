#include "calibration/motive_csv.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

#include "src/core/csv.h"
#include "src/core/parse.h"
#include "src/core/units.h"

namespace robossis::calibration {

namespace {

std::string Lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
  return out;
}

bool AllEmpty(const std::vector<std::string>& fields) {
  return std::all_of(fields.begin(), fields.end(), [](std::string_view f) { return TrimField(f).empty(); });
}

// One line's cells through the strict splitter; `where` is "take.csv line 7" (an unterminated quote names it).
void SplitCells(std::string_view line, const std::string& where, std::vector<std::string>& fields) {
  try {
    fields = SplitCsvRecord(line, where);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
}

struct AxisMap {
  static int Index(std::string_view axis) {
    const std::string a = Lower(TrimField(axis));
    if (a == "x") return 0;
    if (a == "y") return 1;
    if (a == "z") return 2;
    if (a == "w") return 3;
    return -1;
  }
};

constexpr std::array<std::pair<std::string_view, MotiveRotationType>, 7> kRotationTypes = {{
    {"Quaternion", MotiveRotationType::kQuaternion},
    {"XYZ", MotiveRotationType::kXYZ},
    {"XZY", MotiveRotationType::kXZY},
    {"YXZ", MotiveRotationType::kYXZ},
    {"YZX", MotiveRotationType::kYZX},
    {"ZXY", MotiveRotationType::kZXY},
    {"ZYX", MotiveRotationType::kZYX},
}};

// The three axis indices of an Euler order, e.g. XYZ → {0, 1, 2}.
std::array<int, 3> EulerAxes(MotiveRotationType type) {
  switch (type) {
    case MotiveRotationType::kXYZ: return {0, 1, 2};
    case MotiveRotationType::kXZY: return {0, 2, 1};
    case MotiveRotationType::kYXZ: return {1, 0, 2};
    case MotiveRotationType::kYZX: return {1, 2, 0};
    case MotiveRotationType::kZXY: return {2, 0, 1};
    case MotiveRotationType::kZYX: return {2, 1, 0};
    case MotiveRotationType::kQuaternion: break;
  }
  throw std::invalid_argument("RotationFromMotiveEuler: not an Euler rotation type");
}

}  // namespace

std::string_view RotationTypeName(MotiveRotationType type) {
  for (const auto& [name, t] : kRotationTypes) {
    if (t == type) return name;
  }
  return "?";
}

Eigen::Matrix3d RotationFromMotiveEuler(MotiveRotationType type, const Eigen::Vector3d& xyz_rad) {
  const std::array<int, 3> axes = EulerAxes(type);
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  for (int k = 0; k < 3; ++k) {
    R = R * Eigen::AngleAxisd(xyz_rad[axes[k]], Eigen::Vector3d::Unit(axes[k])).toRotationMatrix();
  }
  return R;
}

Eigen::Vector3d MotiveEulerFromRotation(MotiveRotationType type, const Eigen::Matrix3d& R) {
  const std::array<int, 3> axes = EulerAxes(type);
  // Eigen's eulerAngles(a0, a1, a2) returns angles with R = R_a0 · R_a1 · R_a2 (intrinsic), a0 in [0, pi].
  const Eigen::Vector3d angles = R.eulerAngles(axes[0], axes[1], axes[2]);
  Eigen::Vector3d xyz;
  for (int k = 0; k < 3; ++k) xyz[axes[k]] = std::remainder(angles[k], 2 * kPi);
  return xyz;
}

int MotiveLayout::FindRigidBody(std::string_view name) const {
  for (std::size_t i = 0; i < rigid_bodies.size(); ++i) {
    if (rigid_bodies[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::string MotiveLayout::RigidBodyNames() const {
  std::string names;
  for (const auto& rb : rigid_bodies) names += (names.empty() ? "'" : ", '") + rb.name + "'";
  return names.empty() ? "(none)" : names;
}

double MotiveRow::Number(int column) const {
  if (column < 0 || column >= static_cast<int>(fields_.size())) return kMissing;
  if (TrimField(fields_[column]).empty()) return kMissing;  // Motive's occlusion: an empty cell
  double value = 0;
  if (!TryParseNumber(fields_[column], &value)) {
    // 'nan', 'abc' or 'inf' is not an occlusion: the file was edited or is not what it claims.
    throw std::runtime_error(source_name_ + " line " + std::to_string(line_number) + ", column " +
                             std::to_string(column + 1) + ": got '" + std::string(fields_[column].substr(0, 40)) +
                             "'; expected a finite number, or an empty cell for an occlusion");
  }
  return value;
}

bool MotiveRow::Empty(int column) const {
  return column < 0 || column >= static_cast<int>(fields_.size()) || TrimField(fields_[column]).empty();
}

MotiveReader::MotiveReader(const std::filesystem::path& path)
    : MotiveReader(ReadBoundedFile(path, kMaxMotiveFileBytes, "Motive CSV export"), path.string()) {}

MotiveReader::MotiveReader(std::string text, std::string source_name)
    : source_name_(std::move(source_name)), memory_(std::move(text)) {
  ParseHeader();
}

bool MotiveReader::NextLine(std::string& line) {
  {
    if (memory_pos_ >= memory_.size()) return false;
    std::size_t end = memory_.find('\n', memory_pos_);
    line_unterminated_ = end == std::string::npos;
    if (end == std::string::npos) end = memory_.size();
    line.assign(memory_, memory_pos_, end - memory_pos_);
    memory_pos_ = end + 1;
  }
  ++line_number_;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line_number_ == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 byte-order mark
  return true;
}

void MotiveReader::ParseHeader() {
  const std::string& src = source_name_;
  auto where = [&](std::size_t line) { return src + " line " + std::to_string(line) + ": "; };
  std::string line;
  std::vector<std::string> fields;
  auto at = [&](std::size_t line) { return src + " line " + std::to_string(line); };
  if (!NextLine(line)) throw std::runtime_error(src + ": the file is empty; expected a Motive CSV export");
  SplitCells(line, at(1), fields);
  if (fields.size() >= 2 && Lower(TrimField(fields[0])) == "format version") {
    // key/value pairs
  } else if (line.find("Motive") != std::string::npos || line.rfind("comment", 0) == 0 ||
             line.rfind("info", 0) == 0) {
    throw std::runtime_error(where(1) + "this is a legacy Motive/Arena CSV (format 1.1 or older, row-typed layout); "
                             "re-export the take from Motive with CSV format 1.2x (Motive 1.7 or newer)");
  } else {
    throw std::runtime_error(where(1) + "expected 'Format Version,1.2x,...' (an OptiTrack Motive CSV export), got '" +
                             line.substr(0, 60) + "'");
  }
  // Key/value pairs. A take's name (or notes) is free text that Motive writes unquoted, commas included: its value
  // runs on to the next key this reader knows, so that "Take Name,Knee, left,Capture Frame Rate,120" is read as
  // written.
  std::map<std::string, std::string> meta;
  const auto known_key = [](const std::string& k) {
    for (const char* key : {"format version", "take name", "take notes", "capture frame rate", "export frame rate",
                            "capture start time", "capture start frame", "total frames in take",
                            "total exported frames", "rotation type", "length units", "coordinate space"}) {
      if (k == key) return true;
    }
    return false;
  };
  for (std::size_t i = 0; i + 1 < fields.size(); i += 2) {
    const std::string key = Lower(std::string(TrimField(fields[i])));
    std::string value(TrimField(fields[i + 1]));
    if (key == "take name" || key == "take notes") {
      while (i + 2 < fields.size() && !known_key(Lower(std::string(TrimField(fields[i + 2]))))) {
        value += "," + fields[i + 2];
        ++i;
      }
    }
    if (!key.empty()) meta[key] = value;
  }
  header_.format_version = meta["format version"];
  double version = 0;
  if (!TryParseNumber(header_.format_version, &version)) {
    throw std::runtime_error(where(1) + "'Format Version' is '" + header_.format_version + "'; expected a number such as 1.23");
  }
  if (version < 1.195) {
    throw std::runtime_error(where(1) + "'Format Version' is " + header_.format_version +
                             ": legacy format 1.1 and older use a different row-typed layout and are not supported; "
                             "re-export the take with CSV format 1.2x");
  }
  if (version >= 2.0) {
    // The 1.2x layout is all this reader knows; a 2.x or 9.9 header may mean anything.
    throw std::runtime_error(where(1) + "'Format Version' is " + header_.format_version +
                             ": not a Motive CSV format this reader knows; expected 1.2x (1.21 to 1.25, or a newer "
                             "1.x of the same layout)");
  }
  header_.take_name = meta["take name"];
  auto rate = [&](const std::string& key, double& out) {
    if (meta.count(key) && !meta[key].empty() && !TryParseNumber(meta[key], &out)) {
      throw std::runtime_error(where(1) + "'" + key + "' is '" + meta[key] + "'; expected a number in Hz");
    }
  };
  rate("capture frame rate", header_.capture_rate_hz);
  rate("export frame rate", header_.export_rate_hz);
  // The export rate builds the time axis: a stated rate must be plausible; only an absent one falls back to the
  // capture rate (never a stated 0 or -120 replaced silently).
  // The plausible rates [assumed]: no optical tracker records slower than 1 Hz or faster than 100 kHz.
  constexpr double kMinRateHz = 1.0, kMaxRateHz = 100000.0;
  const bool export_stated = meta.count("export frame rate") && !meta["export frame rate"].empty();
  if (!export_stated) header_.export_rate_hz = header_.capture_rate_hz;
  if (!(header_.export_rate_hz >= kMinRateHz && header_.export_rate_hz <= kMaxRateHz)) {
    const std::string key = export_stated ? "export frame rate" : "capture frame rate";
    const std::string stated = meta.count(key) && !meta[key].empty() ? "'" + meta[key] + "'" : "missing";
    throw std::runtime_error(where(1) + "'" + (export_stated ? "Export" : "Capture") + " Frame Rate' is " + stated +
                             "; expected a rate in [1, 100000] Hz to build the time axis");
  }
  if (meta.count("total exported frames") && !meta["total exported frames"].empty()) {
    const std::string& stated = meta["total exported frames"];
    double n = 0;
    if (!TryParseNumber(stated, &n) || n != std::floor(n) || n < 0 || n > kMaxMotiveFrame) {
      throw std::runtime_error(where(1) + "'Total Exported Frames' is '" + stated.substr(0, 40) +
                               "'; expected a whole number of frames from 0 to 9e15");
    }
    header_.total_exported_frames = static_cast<std::int64_t>(n);
  }
  const std::string rotation = meta.count("rotation type") ? meta["rotation type"] : "Quaternion";
  bool known_rotation = false;
  for (const auto& [name, type] : kRotationTypes) {
    if (Lower(name) == Lower(rotation)) {
      header_.rotation_type = type;
      known_rotation = true;
    }
  }
  if (!known_rotation) {
    throw std::runtime_error(where(1) + "'Rotation Type' is '" + rotation +
                             "'; expected Quaternion, XYZ, XZY, YXZ, YZX, ZXY or ZYX");
  }
  header_.length_units = meta.count("length units") ? meta["length units"] : "Meters";
  const std::string units = Lower(header_.length_units);
  if (units == "meters" || units == "metres") {
    header_.length_scale_to_m = 1.0;
  } else if (units == "millimeters" || units == "millimetres") {
    header_.length_scale_to_m = 1e-3;
  } else if (units == "centimeters" || units == "centimetres") {
    header_.length_scale_to_m = 1e-2;
  } else {
    throw std::runtime_error(where(1) + "'Length Units' is '" + header_.length_units +
                             "'; expected Meters, Centimeters or Millimeters");
  }

  // Header rows up to the one starting with "Frame".
  std::vector<std::string> rows;
  std::vector<std::size_t> row_lines;
  for (;;) {
    if (!NextLine(line)) {
      throw std::runtime_error(src + ": the file ends inside the header (no row starting with 'Frame'); it is "
                               "truncated or not a Motive export");
    }
    SplitCells(line, at(line_number_), fields);
    if (AllEmpty(fields)) continue;  // the blank row (a spreadsheet may write it as commas)
    if (Lower(TrimField(fields[0])) == "frame") break;
    rows.push_back(line);
    row_lines.push_back(line_number_);
    if (rows.size() > 16) {
      throw std::runtime_error(where(line_number_) + "no row starting with 'Frame' within the header; not a Motive "
                               "CSV export");
    }
  }
  header_.header_lines = static_cast<int>(line_number_);
  const std::string axis_line = line;
  std::vector<std::string> axis;
  SplitCells(axis_line, at(line_number_), axis);
  if (rows.size() < 3) {
    throw std::runtime_error(where(line_number_) + "expected the Type, Name, ID and quantity header rows above "
                             "the 'Frame' row; found " + std::to_string(rows.size()));
  }
  std::vector<std::string> type_row, name_row, id_row, quantity_row;
  SplitCells(rows[0], at(row_lines[0]), type_row);
  SplitCells(rows[1], at(row_lines[1]), name_row);
  SplitCells(rows[2], at(row_lines[2]), id_row);
  if (rows.size() >= 4) SplitCells(rows.back(), at(row_lines.back()), quantity_row);
  // Spreadsheets add trailing empty cells: the number of columns is the last non-empty axis or type cell.
  std::size_t ncols = 0;
  for (std::size_t c = 0; c < std::max(axis.size(), type_row.size()); ++c) {
    const bool has_axis = c < axis.size() && !TrimField(axis[c]).empty();
    const bool has_type = c < type_row.size() && !TrimField(type_row[c]).empty();
    if (has_axis || (c >= 2 && has_type)) ncols = c + 1;
  }
  layout_.num_columns = static_cast<int>(ncols);
  // Any header row may be shorter than the columns counted (a Type row longer than the axis row): read through cell.
  auto cell = [](const std::vector<std::string>& r, std::size_t c) {
    return c < r.size() ? std::string(TrimField(r[c])) : std::string();
  };
  if (ncols >= 2 && Lower(cell(axis, 1)).rfind("time", 0) == 0) layout_.time_column = 1;
  // The Type row names Motive asset types only; anything else there means the row is missing (the Name row moved
  // up), which would otherwise read as a take with no rigid bodies.
  for (std::size_t c = 2; c < ncols; ++c) {
    const std::string type = Lower(cell(type_row, c));
    static const char* const kKnownTypes[] = {"rigid body", "rigid body marker", "marker", "bone", "bone marker",
                                              "skeleton", "force plate", "device", "unlabeled marker"};
    if (type.empty()) continue;
    if (std::none_of(std::begin(kKnownTypes), std::end(kKnownTypes), [&](const char* k) { return type == k; })) {
      throw std::runtime_error(where(row_lines[0]) + "column " + std::to_string(c + 1) + " of the Type row is '" +
                               cell(type_row, c) + "'; expected a Motive asset type (Rigid Body, Rigid Body Marker, "
                               "Marker, Bone, ...): is the Type row missing?");
    }
  }
  std::map<std::string, int> rb_index, rbm_index, m_index;
  std::map<std::string, std::size_t> column_names;
  int asset_columns = 0;
  for (std::size_t c = 2; c < ncols; ++c) {
    const std::string type = Lower(cell(type_row, c));
    const std::string name = cell(name_row, c);
    const std::string id = cell(id_row, c);
    const std::string quantity = Lower(cell(quantity_row, c));
    const int ax = AxisMap::Index(cell(axis, c));
    const int col = static_cast<int>(c);
    if (type.empty()) continue;
    ++asset_columns;
    if (!quantity_row.empty()) {
      // Motive writes each (type, name, ID, quantity, axis) once; a second one would silently replace the first.
      const std::string column_key = type + "\x1f" + name + "\x1f" + id + "\x1f" + quantity + "\x1f" + Lower(cell(axis, c));
      const auto [first, unique] = column_names.try_emplace(column_key, c);
      if (!unique) {
        throw std::runtime_error(where(header_.header_lines) + "column " + std::to_string(c + 1) + " (" +
                                 cell(type_row, c) + " '" + name + "' " + cell(quantity_row, c) + " " + cell(axis, c) +
                                 ") repeats column " + std::to_string(first->second + 1) +
                                 "; expected each type, name, ID, quantity and axis once");
      }
    }
    const std::string key = name + "\x1f" + id;
    if (type == "rigid body") {
      auto [it, inserted] = rb_index.try_emplace(key, static_cast<int>(layout_.rigid_bodies.size()));
      if (inserted) layout_.rigid_bodies.push_back({name, id, {-1, -1, -1, -1}, {-1, -1, -1}, -1, {}});
      MotiveRigidBodyColumns& rb = layout_.rigid_bodies[it->second];
      if (quantity == "rotation" && ax >= 0) {
        rb.rotation[ax] = col;
      } else if (quantity == "position" && ax >= 0 && ax < 3) {
        rb.position[ax] = col;
      } else if (quantity == "mean marker error" || quantity == "error per marker") {
        rb.mean_marker_error = col;
      }
    } else if (type == "rigid body marker" || type == "marker") {
      auto& index = type == "marker" ? m_index : rbm_index;
      auto& list = type == "marker" ? layout_.markers : layout_.rigid_body_markers;
      auto [it, inserted] = index.try_emplace(key, static_cast<int>(list.size()));
      if (inserted) list.push_back({name, id, {-1, -1, -1}, -1});
      MotiveMarkerColumns& m = list[it->second];
      if (quantity == "position" && ax >= 0 && ax < 3) {
        m.position[ax] = col;
      } else if (quantity == "marker quality") {
        m.marker_quality = col;
      }
    } else {
      ++layout_.other_asset_columns;  // bones, bone markers, force plates...: not used here
    }
  }
  if (asset_columns == 0) {
    throw std::runtime_error(src + ": the take was exported with no assets (only Frame and Time columns); there is "
                             "nothing to evaluate. Re-export with the rigid bodies and/or markers enabled");
  }
  const bool quaternion = header_.rotation_type == MotiveRotationType::kQuaternion;
  for (MotiveRigidBodyColumns& rb : layout_.rigid_bodies) {
    const int needed = quaternion ? 4 : 3;
    for (int k = 0; k < needed; ++k) {
      if (rb.rotation[k] < 0) {
        throw std::runtime_error(where(header_.header_lines) + "rigid body '" + rb.name + "' has no Rotation " +
                                 "XYZW"[k] + " column, but 'Rotation Type' is " +
                                 std::string(RotationTypeName(header_.rotation_type)));
      }
    }
    for (int k = 0; k < 3; ++k) {
      if (rb.position[k] < 0) {
        throw std::runtime_error(where(header_.header_lines) + "rigid body '" + rb.name + "' has no Position " +
                                 "XYZ"[k] + " column");
      }
    }
  }
  // Rigid-body markers belong to the rigid body whose name prefixes theirs ("RB:Marker1" in 1.23, "RB_1" in 1.21)
  // or, failing that, with the same ID (1.21 writes the rigid body's ID on its markers).
  for (std::size_t m = 0; m < layout_.rigid_body_markers.size(); ++m) {
    const MotiveMarkerColumns& marker = layout_.rigid_body_markers[m];
    int owner = -1;
    for (std::size_t r = 0; r < layout_.rigid_bodies.size() && owner < 0; ++r) {
      const std::string& n = layout_.rigid_bodies[r].name;
      if (marker.name.size() > n.size() && marker.name.compare(0, n.size(), n) == 0 &&
          (marker.name[n.size()] == ':' || marker.name[n.size()] == '_')) {
        owner = static_cast<int>(r);
      }
    }
    for (std::size_t r = 0; r < layout_.rigid_bodies.size() && owner < 0; ++r) {
      if (!marker.id.empty() && layout_.rigid_bodies[r].id == marker.id) owner = static_cast<int>(r);
    }
    if (owner >= 0) layout_.rigid_bodies[owner].marker_indices.push_back(static_cast<int>(m));
  }
}

bool MotiveReader::ReadFrame(MotiveRow& row) {
  for (;;) {
    if (!NextLine(row.line_)) {
      // Fewer rows than the header's count is an excerpt (the first frames of a take, the header left as it was),
      // read as it is: complete() says so. A row cut mid-line is refused where it is read (below).
      if (header_.total_exported_frames >= 0 && frames_read_ > header_.total_exported_frames) {
        throw std::runtime_error(source_name_ + ": " + std::to_string(frames_read_) + " frames; the header's "
                                 "'Total Exported Frames' is " + std::to_string(header_.total_exported_frames) +
                                 " (more rows than the export wrote: the file was edited or spliced)");
      }
      return false;
    }
    if (row.line_.empty()) continue;  // a trailing empty line
    SplitCells(row.line_, source_name_ + " line " + std::to_string(line_number_), row.fields_);
    if (AllEmpty(row.fields_)) continue;  // spreadsheet padding rows
    break;
  }
  row.line_number = line_number_;
  row.source_name_ = source_name_;
  row.length_scale_ = header_.length_scale_to_m;
  double frame = 0;
  if (!TryParseNumber(row.fields_[0], &frame) || frame != std::floor(frame) || frame < 0 || frame > kMaxMotiveFrame) {
    throw std::runtime_error(source_name_ + " line " + std::to_string(line_number_) + ": the Frame cell is '" +
                             std::string(row.fields_[0].substr(0, 40)) + "'; expected a non-negative whole number");
  }
  row.frame = static_cast<std::int64_t>(frame);
  if (row.frame <= previous_frame_) {
    throw std::runtime_error(source_name_ + " line " + std::to_string(line_number_) + ": frame " +
                             std::to_string(row.frame) + " does not follow frame " + std::to_string(previous_frame_) +
                             "; frames must increase");
  }
  previous_frame_ = row.frame;
  row.time_s = static_cast<double>(row.frame) / header_.export_rate_hz;
  // A row cut short by truncation: fewer fields than the header announced, at the unterminated end of the file
  // (Motive writes every cell of every row, and ends each row with a newline).
  const int nfields = static_cast<int>(row.fields_.size());
  if (nfields < layout_.num_columns && line_unterminated_) {
    throw std::runtime_error(source_name_ + " line " + std::to_string(line_number_) + ": the last row has " +
                             std::to_string(nfields) + " of " + std::to_string(layout_.num_columns) +
                             " cells and no line end: the file is truncated");
  }
  // An extra cell: a value beyond the header's columns (a spreadsheet's trailing empty cells are not values).
  for (int c = layout_.num_columns; c < nfields; ++c) {
    if (!TrimField(row.fields_[c]).empty()) {
      throw std::runtime_error(source_name_ + " line " + std::to_string(line_number_) + ", column " +
                               std::to_string(c + 1) + ": got '" + row.fields_[c].substr(0, 40) + "'; expected at most " +
                               std::to_string(layout_.num_columns) + " cells, one per header column (an extra cell)");
    }
  }
  // The Time cell, when written, must increase with the frames: time_s is built from the frame number, and a Time
  // column that disagrees means an edited or spliced file.
  if (layout_.time_column >= 0 && !row.Empty(layout_.time_column)) {
    const double t = row.Number(layout_.time_column);
    if (!(t > previous_time_cell_)) {
      throw std::runtime_error(source_name_ + " line " + std::to_string(line_number_) + ", column " +
                               std::to_string(layout_.time_column + 1) + " (Time): got '" +
                               row.fields_[layout_.time_column].substr(0, 40) + "'; expected a time greater than " +
                               std::to_string(previous_time_cell_) + " s (the previous row's): times must increase");
    }
    previous_time_cell_ = t;
  }
  if (layout_.time_column >= 0 && !row.Empty(layout_.time_column)) {
    const double t = row.Number(layout_.time_column);
    const double tolerance = std::max(kMotiveTimeToleranceFrames / header_.export_rate_hz, kMotiveTimeRoundingS);
    if (!(std::fabs(t - row.time_s) <= tolerance)) {
      throw std::runtime_error(source_name_ + " line " + std::to_string(line_number_) + ", column " +
                               std::to_string(layout_.time_column + 1) + " (Time): got '" +
                               row.fields_[layout_.time_column].substr(0, 40) + "'; expected " +
                               std::to_string(row.time_s) + " s (frame " + std::to_string(row.frame) +
                               " at the export rate of " + std::to_string(header_.export_rate_hz) + " Hz, within " +
                               std::to_string(tolerance) + " s)");
    }
  }
  if (nfields < layout_.num_columns) {
    // Motive writes every cell of every row (an occlusion is an empty cell, not a missing one).
    throw std::runtime_error(source_name_ + " line " + std::to_string(line_number_) + ", column " +
                             std::to_string(nfields + 1) + ": the row ends after " + std::to_string(nfields) +
                             " cells; expected " + std::to_string(layout_.num_columns) +
                             ", one per header column (a short row: the file is truncated or was edited)");
  }
  ++frames_read_;
  return true;
}

double MotiveReader::CheckedLength(const MotiveRow& row, int column) const {
  const double v = row.Length(column);
  if (!std::isnan(v) && !(std::fabs(v) <= kMaxMotivePositionM)) {
    throw std::runtime_error(source_name_ + " line " + std::to_string(row.line_number) + ", column " +
                             std::to_string(column + 1) + ": got '" + row.fields_[column].substr(0, 40) +
                             "'; expected a position within +-" + std::to_string(kMaxMotivePositionM) +
                             " m of the origin");
  }
  return v;
}

std::optional<Eigen::Isometry3d> MotiveReader::RigidBodyPose(const MotiveRow& row, int rigid_body) const {
  const MotiveRigidBodyColumns& rb = layout_.rigid_bodies[rigid_body];
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  for (int k = 0; k < 3; ++k) {
    const double v = CheckedLength(row, rb.position[k]);
    if (std::isnan(v)) return std::nullopt;
    X.translation()[k] = v;
  }
  if (header_.rotation_type == MotiveRotationType::kQuaternion) {
    double q[4];
    for (int k = 0; k < 4; ++k) {
      q[k] = row.Number(rb.rotation[k]);
      if (std::isnan(q[k])) return std::nullopt;
    }
    Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);  // Motive writes X, Y, Z, W (scalar last)
    const double norm = quat.norm();
    if (!(std::fabs(norm - 1.0) <= kMotiveQuaternionNormTolerance)) {
      throw std::runtime_error(source_name_ + " line " + std::to_string(row.line_number) + ", columns " +
                               std::to_string(rb.rotation[0] + 1) + "-" + std::to_string(rb.rotation[3] + 1) +
                               " (rigid body '" + rb.name + "' Rotation X, Y, Z, W): quaternion norm " +
                               std::to_string(norm) + "; expected 1 within " +
                               std::to_string(kMotiveQuaternionNormTolerance));
    }
    X.linear() = quat.normalized().toRotationMatrix();
  } else {
    Eigen::Vector3d a;
    for (int k = 0; k < 3; ++k) {
      a[k] = row.Number(rb.rotation[k]);
      if (std::isnan(a[k])) return std::nullopt;
    }
    X.linear() = RotationFromMotiveEuler(header_.rotation_type, a * kDegToRad);
  }
  return X;
}

std::optional<Eigen::Vector3d> MotiveReader::MarkerPosition(const MotiveRow& row,
                                                            const MotiveMarkerColumns& marker) const {
  Eigen::Vector3d p;
  for (int k = 0; k < 3; ++k) {
    p[k] = CheckedLength(row, marker.position[k]);
    if (std::isnan(p[k])) return std::nullopt;
  }
  return p;
}

}  // namespace robossis::calibration
