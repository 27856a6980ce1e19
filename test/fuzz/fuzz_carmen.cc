// libFuzzer target: the CARMEN scan-log reader (plain or gzip: zlib detects which). Every scan
// it returns must be whole: finite time and geometry, non-negative finite ranges, a beam count
// in range; a malformed line is skipped and counted, a corrupt gzip stream throws InputError.

#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "fuzz_util.h"
#include "io/carmen_reader.h"

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
  return 0;
}
