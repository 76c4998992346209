#pragma once
// The rendering methods' names (haptics/rendering/renderer_factory.h makes them) and the one parser of every input
// that names them: `robossis teleop|leader --method`, `robossis render-compare --methods`, haptics.yaml
// `hardware_default_method`. A name is one of KnownMethods() exactly: never empty, no blanks, no other spelling.

#include <string>
#include <vector>

namespace robossis::haptics {

// Every method, in the order the comparison lists them.
std::vector<std::string> KnownMethods();
// "pointcloud, pointcloud-safe, ...": the list an error names.
std::string KnownMethodsText();

// `text` as a method name. Throws std::invalid_argument naming `input`, the text and the known methods:
// "--method: expected a rendering method, got an empty name; known: pointcloud, ...".
std::string ParseMethodName(const std::string& text, const std::string& input);

// "a,b,c": at least one method, each by ParseMethodName, none empty (a leading, trailing or doubled comma is an
// error, not a skipped entry) and none twice. Throws std::invalid_argument naming `input`.
std::vector<std::string> ParseMethodList(const std::string& text, const std::string& input);

}  // namespace robossis::haptics
