// SPDX-License-Identifier: Apache-2.0
#pragma once
// Numbers in the JSON that --emit json prints (one scanner or several).

#include <cmath>
#include <cstdio>
#include <string>

#include "common/json_text.h"  // JsonString

namespace wallcal::outputs {

// 9 significant digits: well below a micrometre / microradian for mounts of a few metres, and
// short enough to read. -0 is printed as 0 so a zero never looks signed.
inline std::string Num(double value) {
  if (value == 0.0) value = 0.0;
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.9g", value);
  return buffer;
}

// Num, with a non-finite number as JSON null (a σ the method does not give).
inline std::string JsonNum(double value) { return std::isfinite(value) ? Num(value) : "null"; }

}  // namespace wallcal::outputs
