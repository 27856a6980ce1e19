// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the NMEA reader (GNSS, heading and attitude logs). Any input must either parse
// into records that keep the reader's promises or throw io::InputError; anything else (a crash, a
// sanitizer report, another exception) is a bug.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "io/text/nmea_reader.h"
#include "common/angles.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  wallcal::io::NmeaLog log;
  try {
    log = wallcal::io::ParseNmea(in, "fuzz.nmea");
  } catch (const wallcal::io::InputError&) {
    return 0;
  }
  // The header's promises: sorted by time, finite values in range, a line for every record.
  for (size_t i = 0; i < log.fixes.size(); ++i) {
    const wallcal::io::GnssFix& fix = log.fixes[i];
    if (!std::isfinite(fix.stamp_s) || !std::isfinite(fix.lat_deg) || !std::isfinite(fix.lon_deg) ||
        !std::isfinite(fix.height_m) || std::abs(fix.lat_deg) > 90.0 ||
        std::abs(fix.lon_deg) > 180.0 || fix.line < 1 || fix.line > log.lines_read) {
      std::abort();
    }
    if (i > 0 && !(fix.stamp_s > log.fixes[i - 1].stamp_s)) std::abort();
  }
  for (size_t i = 0; i < log.headings.size(); ++i) {
    const wallcal::io::HeadingSample& h = log.headings[i];
    if (!std::isfinite(h.stamp_s) || !(h.heading_rad >= 0.0 && h.heading_rad < wallcal::kTwoPi) ||
        h.line < 1 || h.line > log.lines_read) {
      std::abort();
    }
    if (i > 0 && !(h.stamp_s > log.headings[i - 1].stamp_s)) std::abort();
  }
  // Attitudes: roll and pitch within ±io::kMaxVehicleTiltRad, or NaN for the axis an AVR does
  // not give (at least one given); σ positive or NaN.
  for (size_t i = 0; i < log.attitudes.size(); ++i) {
    const wallcal::io::AttitudeSample& a = log.attitudes[i];
    const auto angle_ok = [](double angle_rad) {
      return std::isnan(angle_rad) || std::abs(angle_rad) <= wallcal::io::kMaxVehicleTiltRad;
    };
    const auto sigma_ok = [](double sigma_rad) { return std::isnan(sigma_rad) || sigma_rad > 0.0; };
    if (!std::isfinite(a.stamp_s) || !angle_ok(a.roll_rad) || !angle_ok(a.pitch_rad) ||
        (std::isnan(a.roll_rad) && std::isnan(a.pitch_rad)) || !sigma_ok(a.roll_sigma_rad) ||
        !sigma_ok(a.pitch_sigma_rad) || a.line < 1 || a.line > log.lines_read) {
      std::abort();
    }
    if (i > 0 && !(a.stamp_s > log.attitudes[i - 1].stamp_s)) std::abort();
  }
  return 0;
}
