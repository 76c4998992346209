#include "haptics/rendering/method_names.h"

#include <algorithm>
#include <stdexcept>

namespace robossis::haptics {

std::vector<std::string> KnownMethods() {
  return {"pointcloud", "pointcloud-safe", "pointcloud-pc", "mesh", "mesh-live",
          "mesh-proxy", "mesh-proxy-safe", "proxy", "proxy-safe", "proxy-pc"};
}

std::string KnownMethodsText() {
  std::string list;
  for (const std::string& m : KnownMethods()) list += (list.empty() ? "" : ", ") + m;
  return list;
}

std::string ParseMethodName(const std::string& text, const std::string& input) {
  if (text.empty()) {
    throw std::invalid_argument(input + ": expected a rendering method, got an empty name; known: " +
                                KnownMethodsText());
  }
  const std::vector<std::string> known = KnownMethods();
  if (std::find(known.begin(), known.end(), text) == known.end()) {
    throw std::invalid_argument(input + ": unknown method '" + text + "'; known: " + KnownMethodsText());
  }
  return text;
}

std::vector<std::string> ParseMethodList(const std::string& text, const std::string& input) {
  if (text.empty()) {
    throw std::invalid_argument(input + ": expected a comma-separated list of methods, got nothing; known: " +
                                KnownMethodsText());
  }
  std::vector<std::string> methods;
  std::size_t begin = 0;
  while (true) {  // every entry between commas, the one after a trailing comma included
    const std::size_t comma = text.find(',', begin);
    const std::string item = text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    if (item.empty()) {
      throw std::invalid_argument(input + ": empty entry " + std::to_string(methods.size() + 1) + " in '" + text +
                                  "' (a leading, trailing or doubled comma); known: " + KnownMethodsText());
    }
    const std::string method = ParseMethodName(item, input);
    if (std::find(methods.begin(), methods.end(), method) != methods.end()) {
      throw std::invalid_argument(input + ": '" + method + "' is listed twice in '" + text + "'");
    }
    methods.push_back(method);
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  return methods;
}

}  // namespace robossis::haptics
