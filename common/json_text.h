// SPDX-License-Identifier: Apache-2.0
#pragma once
// A string as JSON writes it: one home for the escaping that every JSON writer (the emitted
// transforms, the guide's --json) uses.

#include <cstdio>
#include <string>

namespace wallcal {

// A JSON string: quotes and backslashes escaped, control characters as \u00XX.
inline std::string JsonString(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof(buffer), "\\u%04x", static_cast<unsigned>(c));
      out += buffer;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace wallcal
