// SPDX-License-Identifier: Apache-2.0
#pragma once
// Number formatting for people and for the YAML/HTML writers: one printf-style helper, so that
// every program prints a number the same way.

#include <cstdio>
#include <string>

namespace wallcal {

// printf-style formatting into a std::string ("%.4f", x). The format is a literal of the caller.
template <typename... Args>
std::string Format(const char* format, Args... args) {
  char buffer[256];
  const int n = std::snprintf(buffer, sizeof(buffer), format, args...);
  if (n < 0) return std::string();
  if (static_cast<size_t>(n) < sizeof(buffer)) return std::string(buffer, static_cast<size_t>(n));
  std::string out(static_cast<size_t>(n) + 1, '\0');
  std::snprintf(out.data(), out.size(), format, args...);
  out.resize(static_cast<size_t>(n));
  return out;
}

}  // namespace wallcal
