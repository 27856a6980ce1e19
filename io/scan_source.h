#pragma once
// A stream of scans, whatever holds them (a CARMEN text log today; a robot recording's
// LaserScan topic beside it). Downstream code reads scans through this and never knows the
// container.

#include <cstdint>
#include <memory>
#include <string>

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
};

}  // namespace wallcal::io
