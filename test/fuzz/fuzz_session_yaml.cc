// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: session.yaml. ReadSession must give a complete spec (the keys docs/session-format.md
// requires) or throw io::InputError: a yaml-cpp exception escaping, a crash or a sanitizer
// report is a bug.

#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "fuzz_util.h"
#include "io/config/session_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = wallcal::fuzz::Scratch().Write("session.yaml", data, size);
  try {
    const wallcal::io::SessionSpec spec = wallcal::io::ReadSession(path);
    // One `scanner:` or a `scanners:` list, each with its model and log. The control points may
    // be absent: a rover survey has none (the survey file, read later, decides which it is).
    bool scanners_complete = spec.scanners.empty()
                                 ? !spec.scanner_model.empty() && !spec.scanner_log.empty()
                                 : true;
    for (const wallcal::io::ScannerSpec& scanner : spec.scanners) {
      scanners_complete = scanners_complete && !scanner.model.empty() && !scanner.log.empty();
    }
    if (!scanners_complete || spec.gnss_log.empty() || spec.heading_log.empty() ||
        spec.survey_points.empty() || spec.walls.empty()) {
      std::abort();
    }
    for (const wallcal::io::ControlPoint& c : spec.control) {
      if (!std::isfinite(c.lat_deg) || !std::isfinite(c.lon_deg) || !std::isfinite(c.h_m)) {
        std::abort();
      }
    }
  } catch (const wallcal::io::InputError&) {
  }
  return 0;
}
