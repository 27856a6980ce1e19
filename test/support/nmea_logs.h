// SPDX-License-Identifier: Apache-2.0
#pragma once
// Two GNSS or heading logs (io::NmeaLog) expected to be the same record for record: a log read
// on in pieces against a whole read of the same bytes or messages.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "io/types.h"

namespace wallcal::testing_support {

// Equal as doubles, NaN equal to NaN (a fix without its GST).
inline bool SameValue(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

// The fixes, headings, counts and skipped lines (with their first line numbers) alike.
inline void ExpectSameLog(const io::NmeaLog& pieces, const io::NmeaLog& whole,
                          const std::string& where) {
  SCOPED_TRACE(where);
  ASSERT_EQ(pieces.fixes.size(), whole.fixes.size());
  for (size_t i = 0; i < whole.fixes.size(); ++i) {
    const io::GnssFix& a = pieces.fixes[i];
    const io::GnssFix& b = whole.fixes[i];
    EXPECT_TRUE(SameValue(a.stamp_s, b.stamp_s) && SameValue(a.lat_deg, b.lat_deg) &&
                SameValue(a.lon_deg, b.lon_deg) && SameValue(a.height_m, b.height_m) &&
                a.quality == b.quality && a.satellites == b.satellites &&
                SameValue(a.hdop, b.hdop) && SameValue(a.sigma_lat_m, b.sigma_lat_m) &&
                SameValue(a.sigma_lon_m, b.sigma_lon_m) &&
                SameValue(a.utc_epoch_s, b.utc_epoch_s) && a.line == b.line)
        << "fix " << i << " (line " << b.line << ")";
  }
  ASSERT_EQ(pieces.headings.size(), whole.headings.size());
  for (size_t i = 0; i < whole.headings.size(); ++i) {
    const io::HeadingSample& a = pieces.headings[i];
    const io::HeadingSample& b = whole.headings[i];
    EXPECT_TRUE(a.stamp_s == b.stamp_s && a.heading_rad == b.heading_rad && a.line == b.line)
        << "heading " << i << " (line " << b.line << ")";
  }
  EXPECT_EQ(pieces.fixes_by_quality, whole.fixes_by_quality);
  EXPECT_EQ(pieces.skipped.by_reason, whole.skipped.by_reason);
  EXPECT_EQ(pieces.skipped.first_line, whole.skipped.first_line);
  EXPECT_EQ(pieces.skipped.severity, whole.skipped.severity);
  EXPECT_EQ(pieces.lines_read, whole.lines_read);
}

}  // namespace wallcal::testing_support
