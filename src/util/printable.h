// Text a user gave (a file name, a URI, a token of a script, a JSON key)
// made safe to put in a one-line message on a terminal. A glTF URI may hold
// escape sequences that retitle the terminal or clear it, a NUL byte cuts a
// printf("%s") short, and a megabyte token would make a megabyte error line.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace bounce::util {

// A run of non-blank bytes longer than this is shortened in messages.
inline constexpr std::size_t kLongestPrintedToken = 256;

// `text` with every control byte (below 0x20, and 0x7f) written as \xNN, so
// that the message stays one line and the terminal shows, and never obeys,
// what the user wrote; and every run of non-blank bytes longer than
// kLongestPrintedToken cut to its head and tail with the number of bytes
// left out between them. Bytes 0x80 and up are kept: UTF-8 names print as
// they are.
inline std::string printable(std::string_view text) {
  constexpr std::size_t kHead = 200, kTail = 40;
  static_assert(kHead + kTail < kLongestPrintedToken);
  const auto escaped = [](std::string& out, unsigned char c) {
    if (c >= 0x20 && c != 0x7f) {
      out += char(c);
      return;
    }
    constexpr char kHex[] = "0123456789abcdef";
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 15];
  };
  std::string out;
  out.reserve(text.size() < 4096 ? text.size() : 4096);
  std::size_t at = 0;
  while (at < text.size()) {
    if (text[at] == ' ') {
      out += ' ';
      ++at;
      continue;
    }
    std::size_t end = text.find(' ', at);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view token = text.substr(at, end - at);
    if (token.size() <= kLongestPrintedToken) {
      for (const char c : token) escaped(out, static_cast<unsigned char>(c));
    } else {
      for (const char c : token.substr(0, kHead)) escaped(out, static_cast<unsigned char>(c));
      out += "...[" + std::to_string(token.size() - kHead - kTail) + " bytes]...";
      for (const char c : token.substr(token.size() - kTail)) escaped(out, static_cast<unsigned char>(c));
    }
    at = end;
  }
  return out;
}

}  // namespace bounce::util
