// nlohmann::json's error messages for people: its exceptions start with a tag
// ("[json.exception.parse_error.101] ") that names the library's internals;
// the rest says where and what. Header-only, free of any Bounce type.
#pragma once

#include <string>

namespace bounce::util {

inline std::string withoutJsonExceptionTag(const std::string& message) {
  if (message.starts_with("[json.exception.")) {
    const std::size_t end = message.find("] ");
    if (end != std::string::npos) return message.substr(end + 2);
  }
  return message;
}

}  // namespace bounce::util
