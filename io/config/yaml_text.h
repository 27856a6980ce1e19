// SPDX-License-Identifier: Apache-2.0
#pragma once
// Scalars for the YAML files wallcal writes (offsets.yaml, presets, session.yaml, truth.yaml):
// the one escaper, so that whatever text a run carries (a folder name in Latin-1, a warning with
// ':' or '#', a control character) reads back as the same text.

#include <string>

namespace wallcal::io {

// printf-style number; NaN and infinities as YAML's .nan, .inf, -.inf.
std::string YamlNumber(const char* format, double value);

// The shortest text that reads back to the same double; an exponent always has a '.'
// ("8.0e-04"), which YAML 1.1 readers need to see a float.
std::string ShortestNumber(double value);

// A value held in one unit written in another (radians as degrees: file_per_unit = kRadToDeg):
// the shortest text d with d / file_per_unit == value exactly, i.e. what the option readers
// (io/config/options_map.h Scaled) read back to the same double. 30° read as radians is
// written "30", not the "29.999999999999996" the product value · file_per_unit gives.
std::string ShortestScaled(double value, double file_per_unit);

// `text` as a YAML scalar: plain where that reads back as the same string (not a boolean or null
// word), else double-quoted with '"', '\\', control characters and bytes that are not UTF-8
// escaped (\n, \t, \r, \xNN). Valid UTF-8 goes through unchanged.
std::string YamlText(const std::string& text);

// Always double-quoted, escaped as YamlText escapes (free text: paths, warnings, times).
std::string YamlQuoted(const std::string& text);

}  // namespace wallcal::io
