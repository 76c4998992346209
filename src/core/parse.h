#pragma once
// Parsing of command-line values such as "--pose 10,0,284,0,5,0" into numbers, with errors that name the option.

#include <string>
#include <string_view>
#include <vector>

namespace robossis {

// `value` as printf's `printf_format` (one double conversion) prints it: the numbers of error messages and reports.
std::string FormatNumber(double value, const char* printf_format = "%g");

// Parses a comma-separated list of exactly `count` finite numbers. Throws std::invalid_argument:
// "--pose: expected 6 comma-separated numbers (X_MM,Y_MM,Z_MM,ROLL_DEG,PITCH_DEG,YAW_DEG), got 5 in '1,2,3,4,5'".
std::vector<double> ParseNumberList(std::string_view text, std::size_t count, const std::string& option_name,
                                    const std::string& format_hint);

// Parses one finite number; throws std::invalid_argument naming the option.
double ParseNumber(std::string_view text, const std::string& option_name);

// A text field without surrounding spaces, tabs or double quotes, nor a trailing carriage return (CSV fields,
// command-line values).
std::string_view TrimField(std::string_view field);

// Parses one finite number from a field (trimmed as above; a leading '+' allowed). False if it is not exactly one.
bool TryParseNumber(std::string_view field, double* out);

}  // namespace robossis
