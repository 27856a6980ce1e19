// SPDX-License-Identifier: Apache-2.0
#include "io/config/yaml_text.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

#include "common/format.h"
#include "io/input_file.h"

namespace wallcal::io {
namespace {

bool IsPlainYamlText(const std::string& text) {
  if (text.empty()) return false;
  if (!(std::isalpha(static_cast<unsigned char>(text[0])) || text[0] == '_')) return false;
  for (char c : text) {
    const bool ok =
        std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' || c == '/';
    if (!ok) return false;
  }
  // Words YAML would read as booleans or null.
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  static const char* const kReserved[] = {"true", "false", "yes", "no", "on",
                                          "off",  "null",  "y",   "n"};
  for (const char* word : kReserved) {
    if (lower == word) return false;
  }
  return true;
}

}  // namespace

std::string YamlNumber(const char* format, double value) {
  if (std::isnan(value)) return ".nan";
  if (std::isinf(value)) return value > 0 ? ".inf" : "-.inf";
  return Format(format, value);
}

// Shortest text that reads back to the same double (configs written for machines and people).
std::string ShortestScaled(double value, double file_per_unit) {
  const double product = value * file_per_unit;
  if (!std::isfinite(product) || !(file_per_unit != 0.0)) return ShortestNumber(product);
  for (int digits = 1; digits <= 17; ++digits) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof(buffer), product,
                                      std::chars_format::general, digits);
    double back = 0.0;
    std::from_chars(buffer, result.ptr, back);
    if (back / file_per_unit == value) return ShortestNumber(back);
  }
  return ShortestNumber(product);
}

std::string ShortestNumber(double value) {
  if (!std::isfinite(value)) return YamlNumber("%g", value);
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  std::string text(buffer, result.ptr);
  // "8e-04" is a float in YAML 1.2 but a string to YAML 1.1 readers (PyYAML): add the ".0".
  const size_t exponent = text.find('e');
  if (exponent != std::string::npos && text.find('.') == std::string::npos) {
    text.insert(exponent, ".0");
  }
  return text;
}

// A YAML scalar for `text`: plain when that reads back as the same text, else double-quoted.
std::string YamlText(const std::string& text) {
  if (IsPlainYamlText(text)) return text;
  std::string quoted = "\"";
  for (size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x80) {
      // offsets.yaml is UTF-8: a valid sequence goes as it is, any other byte (a folder name in
      // Latin-1) as \xNN, which a YAML reader turns into that code point.
      const size_t n = Utf8SequenceLength(text, i);
      if (n == 0) {
        quoted += Format("\\x%02X", static_cast<unsigned>(c));
      } else {
        quoted.append(text, i, n);
        i += n - 1;
      }
      continue;
    }
    switch (c) {
      case '"':
        quoted += "\\\"";
        break;
      case '\\':
        quoted += "\\\\";
        break;
      case '\n':
        quoted += "\\n";
        break;
      case '\t':
        quoted += "\\t";
        break;
      case '\r':
        quoted += "\\r";
        break;
      default:
        if (c < 0x20 || c == 0x7f) {
          quoted += Format("\\x%02X", static_cast<unsigned>(c));
        } else {
          quoted += static_cast<char>(c);
        }
    }
  }
  quoted += "\"";
  return quoted;
}

// Always a double-quoted YAML scalar (free text: paths, command-line words, times).
std::string YamlQuoted(const std::string& text) {
  // Always double-quoted, escaped as YamlText escapes (control characters, bytes that are not
  // UTF-8 as \xNN).
  const std::string quoted = YamlText(text);
  return quoted.front() == '"' ? quoted : "\"" + quoted + "\"";
}

}  // namespace wallcal::io
