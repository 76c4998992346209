#pragma once
// JSON views of the RSR model and its kinematics results, in the edge units (mm, deg, N, N·m).

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "robot/rsr_kinematics.h"

namespace robossis::apps {

nlohmann::ordered_json RsrInfoJson(const robot::RsrModel& model);
nlohmann::ordered_json RsrIkJson(const robot::RsrIkResult& ik);
nlohmann::ordered_json RsrFkJson(const robot::RsrFkResult& fk);
// {"feasible": ..., "violations": ["arm 1 stroke = ...", ...]}: whether a pose the result was computed at is inside the
// joint limits (cones included), for the results that are defined outside them as well (FK, Jacobian, statics).
nlohmann::ordered_json RsrFeasibilityJson(const robot::RsrIkResult& ik);
nlohmann::ordered_json RsrJacobianJson(const Matrix6d& J);
nlohmann::ordered_json RsrStaticsJson(const robot::RsrStaticsResult& statics);

// "arm 2 stroke = 360.000 mm beyond its limit 354.000 mm by 6.000 mm"
std::string ViolationText(const robot::RsrLimitCheck& check);

// Throws std::runtime_error "WHAT: not finite at this pose ('KEY' is nan): ..." if any number in `document` is NaN
// or infinite (a singular pose), so no command prints NaN/inf with exit 0.
void RequireFiniteResult(const nlohmann::ordered_json& document, const std::string& what);

// Human-readable form of a flat JSON object: one "key: value" line per member.
void PrintKeyValues(const nlohmann::ordered_json& document);

}  // namespace robossis::apps
