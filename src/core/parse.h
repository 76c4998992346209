#pragma once
// Parsing of command-line values such as "--pose 10,0,284,0,5,0" into numbers, with errors that name the option.

#include <string>
#include <string_view>
#include <vector>

namespace robossis {

// Bounds of a position or an angle given at the edges (a command-line pose, a hand or trajectory CSV row)
// [assumed: the paper gives none]: far outside any workspace of the system (the sigma.7's is ~190 mm across, the
// RSR's strokes 214-354 mm) and ten turns of any angle, so that only a corrupt or hostile value is refused; what is
// reachable is the kinematics' answer, not the parser's.
inline constexpr double kMaxEdgePositionMm = 1000.0;
inline constexpr double kMaxEdgeAngleDeg = 3600.0;

// `value` as printf's `printf_format` (one double conversion) prints it: the numbers of error messages and reports.
std::string FormatNumber(double value, const char* printf_format = "%g");

// What bounds the fields of a list: finiteness alone (a tracker's room, forces), or the system's workspaces (a
// pose, a joint, a move of the robot or the hand): there `format_hint`'s unit bounds each field, a field named
// *_MM within +-kMaxEdgePositionMm and *_DEG within +-kMaxEdgeAngleDeg.
enum class FieldBounds { kFinite, kWorkspace };

// Parses a comma-separated list of exactly `count` finite numbers; `format_hint` names the fields with their unit
// ("X_MM,Y_MM,Z_MM,ROLL_DEG,PITCH_DEG,YAW_DEG"). Throws std::invalid_argument:
// "--pose: expected 6 comma-separated numbers (X_MM,Y_MM,Z_MM,ROLL_DEG,PITCH_DEG,YAW_DEG), got 5 in '1,2,3,4,5'";
// "--pose: X_MM is '1e300'; expected a position within +-1000 mm".
std::vector<double> ParseNumberList(std::string_view text, std::size_t count, const std::string& option_name,
                                    const std::string& format_hint, FieldBounds bounds = FieldBounds::kFinite);

// Parses one finite number; throws std::invalid_argument naming the option.
double ParseNumber(std::string_view text, const std::string& option_name);

// A text field without surrounding spaces, tabs or double quotes, nor a trailing carriage return (CSV fields,
// command-line values).
std::string_view TrimField(std::string_view field);

// Parses one finite number from a field (trimmed as above; a leading '+' allowed). False if it is not exactly one.
bool TryParseNumber(std::string_view field, double* out);

}  // namespace robossis
