// SPDX-License-Identifier: Apache-2.0
// GNSS epochs mapped onto the logger clock (calib/gnss_epoch_time.h) and the reader's UTC of
// each logger-stamped GGA (io/nmea_reader.h).
#include "calib/gnss_epoch_time.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "io/text/nmea_reader.h"
#include "io/writers/writers.h"

namespace wallcal::calib {
namespace {

// n fixes at 10 Hz from utc0; arrival = epoch + latency + jitter·u_k (u_k a fixed uniform-like
// sequence in [0, 1)) + drift·(epoch − utc0).
std::vector<io::GnssFix> Fixes(int n, double utc0_s, double latency_s, double jitter_s,
                               double drift = 0.0) {
  std::vector<io::GnssFix> fixes;
  for (int k = 0; k < n; ++k) {
    io::GnssFix fix;
    fix.utc_epoch_s = utc0_s + 0.1 * k;
    const double u = std::fmod(0.6180339887 * (k + 1), 1.0);  // equidistributed in [0, 1)
    fix.stamp_s = fix.utc_epoch_s + latency_s + jitter_s * u + drift * 0.1 * k;
    fixes.push_back(fix);
  }
  return fixes;
}

TEST(GnssEpochTimeTest, MapsEpochsAtTheMeanLatencyWithoutTheJitter) {
  std::vector<io::GnssFix> fixes = Fixes(600, 1.7e9, 0.035, 0.010);
  const GnssEpochMapping m = MapGnssEpochs(&fixes, true);
  ASSERT_EQ(m.status, EpochMappingStatus::kMapped);
  EXPECT_EQ(m.fixes, 600);
  // Mean of U(0, 10 ms) is 5 ms; the sequence's mean over 600 values is within 0.1 ms of it.
  EXPECT_NEAR(m.offset_s, 0.040, 2e-4);
  // Robust σ of U(0, w): 1.4826 · w/4 = 3.7 ms.
  EXPECT_NEAR(m.jitter_s, 0.0037, 5e-4);
  EXPECT_NEAR(m.drift, 0.0, 1e-5);
  // Each fix at its epoch + the mean latency: the jitter (up to 10 ms) is gone; what is left is
  // the fitted drift's noise over the minute (~1e-7 · 60 s).
  for (const io::GnssFix& fix : fixes) {
    EXPECT_NEAR(fix.stamp_s - fix.utc_epoch_s, m.offset_s, 5e-5);
  }
}

TEST(GnssEpochTimeTest, FindsALoggerClockDrift) {
  std::vector<io::GnssFix> fixes = Fixes(3000, 1.7e9, 0.035, 0.002, 50e-6);
  const GnssEpochMapping m = MapGnssEpochs(&fixes, true);
  ASSERT_EQ(m.status, EpochMappingStatus::kMapped);
  EXPECT_NEAR(m.drift, 50e-6, 2e-6);
  EXPECT_NEAR(fixes.back().stamp_s - fixes.back().utc_epoch_s, 0.036 + 50e-6 * 299.9, 2e-4);
}

TEST(GnssEpochTimeTest, KeepsArrivalStampsWhenTheDifferenceIsNotOneLatency) {
  std::vector<io::GnssFix> fixes = Fixes(100, 1.7e9, 0.035, 0.0);
  for (size_t k = 0; k < fixes.size(); k += 3) fixes[k].stamp_s += 0.5 + 0.01 * k;  // a third wild
  const std::vector<io::GnssFix> before = fixes;
  const GnssEpochMapping m = MapGnssEpochs(&fixes, true);
  EXPECT_EQ(m.status, EpochMappingStatus::kInconsistent);
  for (size_t k = 0; k < fixes.size(); ++k) EXPECT_EQ(fixes[k].stamp_s, before[k].stamp_s);
}

TEST(GnssEpochTimeTest, SaysWhyNothingWasMapped) {
  std::vector<io::GnssFix> plain(20);
  EXPECT_EQ(MapGnssEpochs(&plain, true).status, EpochMappingStatus::kNoLoggerStamp);
  std::vector<io::GnssFix> few = Fixes(kMinEpochFixes - 1, 1.7e9, 0.035, 0.0);
  EXPECT_EQ(MapGnssEpochs(&few, true).status, EpochMappingStatus::kTooFew);
  std::vector<io::GnssFix> off = Fixes(50, 1.7e9, 0.035, 0.005);
  const double arrival_s = off[7].stamp_s;
  EXPECT_EQ(MapGnssEpochs(&off, false).status, EpochMappingStatus::kDisabled);
  EXPECT_EQ(off[7].stamp_s, arrival_s);
}

std::string Line(const std::string& body) { return "$" + body + "*" + io::NmeaChecksum(body); }

TEST(NmeaEpochTest, ReaderKeepsTheEpochAcrossMidnightWithAndWithoutADate) {
  // 2025-05-12 23:59:59.8 .. 2025-05-13 00:00:00.2 UTC, each arriving 35 ms later.
  const double midnight_s = 1747094400.0;  // 2025-05-13T00:00:00Z
  for (bool dated : {false, true}) {
    std::string text;
    if (dated) {
      text += "1747094399.700 " +
              Line("GNRMC,235959.70,A,4304.2720,N,14120.3940,E,0.0,0.0,120525,,,A") + "\n";
    }
    for (int k = -2; k <= 2; ++k) {
      io::GnssFix fix;
      fix.utc_epoch_s = midnight_s + 0.1 * k;
      fix.stamp_s = fix.utc_epoch_s + 0.035;
      fix.lat_deg = 43.07;
      fix.lon_deg = 141.34;
      fix.quality = 4;
      fix.satellites = 12;
      fix.hdop = 0.7;
      text += io::FormatGgaLine(fix) + "\n";
    }
    std::istringstream in(text);
    const io::NmeaLog log = io::ParseNmea(in, "epoch.nmea");
    ASSERT_EQ(log.fixes.size(), 5u) << "dated " << dated;
    for (int k = 0; k < 5; ++k) {
      EXPECT_NEAR(log.fixes[k].utc_epoch_s, midnight_s + 0.1 * (k - 2), 1e-6) << dated << k;
      EXPECT_NEAR(log.fixes[k].stamp_s, midnight_s + 0.1 * (k - 2) + 0.035, 1e-6);
    }
  }
}

}  // namespace
}  // namespace wallcal::calib
