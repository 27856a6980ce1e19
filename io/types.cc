// SPDX-License-Identifier: Apache-2.0
#include "io/types.h"

namespace wallcal::io {

std::string SkipCounts::ListReasons(bool problems_only, size_t max_reasons) const {
  std::string out;
  size_t shown = 0;
  for (const auto& [reason, count] : by_reason) {
    if (problems_only && IsInformational(reason)) continue;
    if (shown == max_reasons) {
      out += "; ...";
      break;
    }
    out += (shown++ > 0 ? "; " : "") + reason + ": " + std::to_string(count);
    const auto line = first_line.find(reason);
    if (line != first_line.end() && line->second > 0) {
      out += ", first at line " + std::to_string(line->second);
    }
  }
  return out;
}

std::string Where(const std::string& file, int line, const std::string& message) {
  std::string text = file;
  if (line > 0) text += ":" + std::to_string(line);
  text += ": ";
  text += message;
  return text;
}

const char* FixQualityName(int quality) {
  switch (quality) {
    case 0: return "invalid";
    case 1: return "GPS";
    case 2: return "DGPS";
    case 3: return "PPS";
    case 4: return "RTK fixed";
    case 5: return "RTK float";
    case 6: return "dead reckoning";
    case 7: return "manual";
    case 8: return "simulator";
    case 9: return "SBAS";
    default: return "unknown";
  }
}

namespace {
int FixQualityRank(int quality) {
  switch (quality) {
    case 4: return 6;
    case 5: return 5;
    case 2: case 9: return 4;
    case 3: return 3;
    case 1: return 2;
    default: return 0;
  }
}
}  // namespace

bool FixQualityAccepted(int quality, int min_fix_quality) {
  const int rank = FixQualityRank(quality);
  return rank > 0 && rank >= FixQualityRank(min_fix_quality);
}

}  // namespace wallcal::io
