// SPDX-License-Identifier: Apache-2.0
#include "io/scanner_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/angles.h"

namespace wallcal::io {
namespace {

std::string Fixed(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace

int BeamSlack(const ScannerPreset& preset) { return std::max(2, preset.num_beams / 100); }

bool BeamCountFits(int64_t beams, const ScannerPreset& preset) {
  return std::abs(beams - static_cast<int64_t>(preset.num_beams)) <= BeamSlack(preset);
}

GeometryCheck CheckScanGeometry(int64_t beams, double step_rad, double range_max_m,
                                const ScannerPreset& preset) {
  GeometryCheck check;
  const double preset_step_rad = std::abs(preset.angular_step_rad);
  const double scan_step_rad = std::abs(step_rad);
  const double field_deg = scan_step_rad * static_cast<double>(std::max<int64_t>(0, beams - 1)) *
                           kRadToDeg;
  const double preset_field_deg =
      preset_step_rad * static_cast<double>(std::max(0, preset.num_beams - 1)) * kRadToDeg;
  const std::string scanner =
      std::to_string(beams) + " beams " + Fixed("%.4f", scan_step_rad * kRadToDeg) +
      "° apart (a " + Fixed("%.1f", field_deg) + "° field); the preset " + preset.name +
      " has " + std::to_string(preset.num_beams) + " beams " +
      Fixed("%.4f", preset_step_rad * kRadToDeg) + "° apart (" + Fixed("%.1f", preset_field_deg) +
      "°)";
  if (scan_step_rad > 0.0 && std::abs(scan_step_rad - preset_step_rad) > kStepTolerance * preset_step_rad) {
    return {GeometryFit::kOtherScanner, scanner + ": another scanner"};
  }
  const int64_t beam_difference = beams - preset.num_beams;
  if (!BeamCountFits(beams, preset)) {
    return {GeometryFit::kOtherScanner, scanner + ": another scanner (or a field cropped by the "
                                                  "driver)"};
  }
  if (range_max_m > 0.0 &&
      (range_max_m > kDriverRangeFactor * preset.max_range_m || range_max_m <= preset.min_range_m)) {
    return {GeometryFit::kOtherScanner,
            "range_max " + Fixed("%.2f", range_max_m) + " m; the preset " + preset.name +
                " reaches " + Fixed("%.2f", preset.max_range_m) + " m (a driver may report up to " +
                Fixed("%.2f", kDriverRangeFactor * preset.max_range_m) + " m): another scanner"};
  }
  std::string taken;
  if (beam_difference != 0) {
    taken = std::to_string(beams) + " beams (preset " + std::to_string(preset.num_beams) + ")";
  }
  if (range_max_m > 0.0 && std::abs(range_max_m - preset.max_range_m) > 1e-3 * preset.max_range_m) {
    taken += (taken.empty() ? "" : ", ") + std::string("range_max ") + Fixed("%.3f", range_max_m) +
             " m (preset " + Fixed("%.3f", preset.max_range_m) + " m)";
  }
  if (!taken.empty()) check = {GeometryFit::kFromData, taken};
  return check;
}

}  // namespace wallcal::io
