// SPDX-License-Identifier: Apache-2.0
#pragma once
// Number formatting for people and for the YAML/HTML writers: one printf-style helper, so that
// every program prints a number the same way.

#include <cstdio>
#include <ctime>
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

// The wall-clock time now, UTC, as ISO 8601 to the second ("2026-11-26T19:00:00Z"): the stamp
// written into offsets.yaml and the scanner presets.
inline std::string NowUtcIso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace wallcal
