// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the CARMEN scan-log reader (plain or gzip: zlib detects which). Every scan
// it returns must be whole: finite time and geometry, non-negative finite ranges, a beam count
// in range; a malformed line is skipped and counted, a corrupt gzip stream throws InputError.
// Skimming (NextStamp, then ParseCurrent on every other scan) must give the same whole scans.

#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "fuzz_util.h"
#include "io/text/carmen_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = wallcal::fuzz::Scratch().Write("scans.clf", data, size);
  try {
    wallcal::io::CarmenReader reader(path);
    wallcal::io::ScanRecord scan;
    int64_t scans = 0;
    while (reader.Next(&scan)) {
      ++scans;
      if (!std::isfinite(scan.stamp_s) || !std::isfinite(scan.start_angle_rad) ||
          !std::isfinite(scan.angular_step_rad) || !std::isfinite(scan.max_range_m) ||
          scan.ranges_m.empty() || scan.line < 1 || scan.line > reader.lines_read()) {
        std::abort();
      }
      for (float r : scan.ranges_m) {
        if (!(std::isfinite(r) && r >= 0.0f)) std::abort();
      }
    }
    if (scans != reader.scans_read()) std::abort();
  } catch (const wallcal::io::InputError&) {
  }
  try {
    wallcal::io::CarmenReader skim(path);
    wallcal::io::ScanRecord scan;
    double stamp_s = 0.0;
    int line = 0;
    for (int64_t k = 0; skim.NextStamp(&stamp_s, &line); ++k) {
      if (!std::isfinite(stamp_s) || line < 1 || line > skim.lines_read()) std::abort();
      if (k % 2 == 0 && skim.ParseCurrent(&scan)) {
        if (scan.stamp_s != stamp_s || scan.line != line || scan.ranges_m.empty()) std::abort();
        for (float r : scan.ranges_m) {
          if (!(std::isfinite(r) && r >= 0.0f)) std::abort();
        }
      }
    }
  } catch (const wallcal::io::InputError&) {
  }
  return 0;
}
