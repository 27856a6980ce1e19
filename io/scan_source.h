// SPDX-License-Identifier: Apache-2.0
#pragma once
// A stream of scans, whatever holds them (a CARMEN text log today; a robot recording's
// LaserScan topic beside it). Downstream code reads scans through this and never knows the
// container.

#include <cstdint>
#include <memory>
#include <string>
#include <utility>

#include "io/types.h"

namespace wallcal::io {

class ScanSource {
 public:
  virtual ~ScanSource() = default;
  // The next scan in file order; false at the end. Throws InputError on a damaged file.
  virtual bool Next(ScanRecord* scan) = 0;
  // What was passed over, by reason (lines of a text log, messages of a recording).
  virtual const SkipCounts& skipped() const = 0;
  virtual int64_t scans_read() const = 0;
  virtual const std::string& path() const = 0;

  // Skimming: a pass that examines only some scans (the first, wide-gate pass) asks for each
  // scan's stamp first and parses the ranges of the scans it keeps. NextStamp returns the next
  // scan's stamp (s) and line, or false at the end; ParseCurrent then fills *scan with that
  // scan, or returns false (counted in skipped()) when it turns out malformed. A source may
  // check a scan's ranges only when it is parsed: scans_read() then counts the scans whose
  // stamps were read. The default reads every scan whole.
  virtual bool NextStamp(double* stamp_s, int* line) {
    if (!Next(&held_)) return false;
    *stamp_s = held_.stamp_s;
    *line = held_.line;
    return true;
  }
  virtual bool ParseCurrent(ScanRecord* scan) {
    std::swap(*scan, held_);
    return true;
  }

 private:
  ScanRecord held_;  // the scan NextStamp read (default skimming)
};

}  // namespace wallcal::io
