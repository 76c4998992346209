#pragma once
// Unit conversions. Everything inside the project is SI (m, rad, s, N); mm, degrees and Hz appear only at the
// edges (config keys, command-line values, reports), always in suffixed names.

#include <numbers>

namespace robossis {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDegToRad = kPi / 180.0;
inline constexpr double kRadToDeg = 180.0 / kPi;
inline constexpr double kMmToM = 1e-3;
inline constexpr double kMToMm = 1e3;

constexpr double DegToRad(double deg) { return deg * kDegToRad; }
constexpr double RadToDeg(double rad) { return rad * kRadToDeg; }
constexpr double MmToM(double mm) { return mm * kMmToM; }
constexpr double MToMm(double m) { return m * kMToMm; }

}  // namespace robossis
