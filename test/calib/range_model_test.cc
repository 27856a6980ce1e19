// SPDX-License-Identifier: Apache-2.0
#include "calib/range_model.h"
#include "test/support/shipped_presets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include "common/angles.h"

namespace wallcal::calib {
namespace {
io::ScanRecord ScanFor(const io::ScannerPreset& preset, std::vector<float> ranges) {
  io::ScanRecord scan;
  scan.stamp_s = 100.0;
  scan.start_angle_rad = preset.start_angle_rad;
  scan.angular_step_rad = preset.angular_step_rad;
  scan.max_range_m = preset.max_range_is_no_return ? preset.max_range_m : 0.0;
  scan.ranges_m = std::move(ranges);
  return scan;
}

// Index of beam `beam` in the output, -1 when dropped.
int IndexOfBeam(const ScanPoints& pts, int beam) {
  for (size_t i = 0; i < pts.beam.size(); ++i) {
    if (pts.beam[i] == beam) return static_cast<int>(i);
  }
  return -1;
}

TEST(RangeModelTest, UrgErrorCodesAreDroppedAndCounted) {
  const io::ScannerPreset urg = testing_support::ShippedPreset("hokuyo_urg04lx");
  std::vector<float> r(urg.num_beams, 2.0f);
  r[10] = 0.0f;  // URG error codes are small integers in mm (Okubo, Ye & Borenstein 2009)
  r[11] = 0.006f;
  r[12] = 0.019f;
  r[13] = 0.020f;  // the smallest real range: kept
  RangeCounts counts;
  const ScanPoints pts = ToScanPoints(ScanFor(urg, r), urg, 0.0, 0.15, &counts);
  EXPECT_EQ(counts.error_code, 3);
  EXPECT_EQ(counts.valid, urg.num_beams - 3);
  EXPECT_EQ(counts.no_return + counts.too_close + counts.non_finite, 0);
  EXPECT_EQ(IndexOfBeam(pts, 10), -1);
  EXPECT_EQ(IndexOfBeam(pts, 12), -1);
  EXPECT_GE(IndexOfBeam(pts, 13), 0);
  EXPECT_EQ(static_cast<int64_t>(pts.p_scanner_m.size()), counts.valid);
}

TEST(RangeModelTest, SickNoReturnsAtMaximumAreDroppedAndCounted) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  std::vector<float> r(sick.num_beams, 8.0f);
  r[0] = 80.0f;  // the LMS reports "no echo" as its maximum
  r[1] = 81.9f;
  r[90] = 79.99f;  // just below: a real (far) return
  RangeCounts counts;
  const ScanPoints pts = ToScanPoints(ScanFor(sick, r), sick, 0.5, 0.15, &counts);
  EXPECT_EQ(counts.no_return, 2);
  EXPECT_EQ(counts.valid, sick.num_beams - 2);
  EXPECT_GE(IndexOfBeam(pts, 90), 0);

  // The log's own maximum_range counts too, even when the preset does not use its maximum.
  io::ScannerPreset no_max = sick;
  no_max.max_range_is_no_return = false;
  io::ScanRecord scan = ScanFor(sick, r);
  scan.max_range_m = 8.183;
  scan.ranges_m[5] = 8.183f;  // 8.18299961f: below the double 8.183, yet the logged maximum
  scan.ranges_m[6] = 8.182f;  // a real return
  RangeCounts counts2;
  ToScanPoints(scan, no_max, 0.5, 0.15, &counts2);
  EXPECT_EQ(counts2.no_return, 4);  // 80, 81.9, 79.99 and 8.183
}

TEST(RangeModelTest, AppliesRangeCorrectionAndLogBearings) {
  const io::ScannerPreset urg = testing_support::ShippedPreset("hokuyo_urg04lx");
  std::vector<float> r(urg.num_beams, 1.0f);
  io::ScanRecord scan = ScanFor(urg, r);
  // Bearings come from the record, not the preset.
  scan.start_angle_rad = -100.0 * kDegToRad;
  scan.angular_step_rad = 0.25 * kDegToRad;
  const ScanPoints pts = ToScanPoints(scan, urg, 0.1, 0.15, nullptr);
  ASSERT_EQ(static_cast<int>(pts.range_m.size()), urg.num_beams);
  // Okubo, Ye & Borenstein 2009: ŷ = 1.0102 μ − 7.0 mm.
  const double expected = 1.0102 * 1.0 - 0.007;
  for (int i : {0, 200, 681}) {
    EXPECT_NEAR(pts.range_m[i], expected, 1e-6);
    const double bearing = (-100.0 + 0.25 * i) * kDegToRad;
    EXPECT_NEAR(pts.bearing_rad[i], bearing, 1e-6);
    EXPECT_NEAR(pts.p_scanner_m[i].x(), expected * std::cos(bearing), 1e-6);
    EXPECT_NEAR(pts.p_scanner_m[i].y(), expected * std::sin(bearing), 1e-6);
    EXPECT_EQ(pts.beam[i], i);
  }
}

TEST(RangeModelTest, NonFiniteNegativeAndTooCloseAreDroppedAndCounted) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  std::vector<float> r(sick.num_beams, 6.0f);
  r[3] = std::numeric_limits<float>::quiet_NaN();
  r[4] = std::numeric_limits<float>::infinity();
  r[5] = -1.0f;
  r[6] = 0.3f;  // closer than the 0.5 m option: the vehicle's own bumper
  r[7] = 0.0f;
  RangeCounts counts;
  const ScanPoints pts = ToScanPoints(ScanFor(sick, r), sick, 0.5, 0.15, &counts);
  EXPECT_EQ(counts.non_finite, 3);
  EXPECT_EQ(counts.too_close, 2);
  EXPECT_EQ(counts.valid, sick.num_beams - 5);
  for (float range : pts.range_m) EXPECT_TRUE(std::isfinite(range) && range >= 0.5f);
}

TEST(RangeModelTest, CountsAccumulateOverScans) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  std::vector<float> r(sick.num_beams, 6.0f);
  r[0] = 80.0f;
  RangeCounts counts;
  ToScanPoints(ScanFor(sick, r), sick, 0.5, 0.15, &counts);
  ToScanPoints(ScanFor(sick, r), sick, 0.5, 0.15, &counts);
  EXPECT_EQ(counts.no_return, 2);
  EXPECT_EQ(counts.valid, 2 * (sick.num_beams - 1));
}

TEST(RangeModelTest, FlagsBothSidesOfARangeJumpAndAMixedPixel) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  std::vector<float> r(sick.num_beams, 8.0f);
  // A trunk at 5 m on beams 60..63 in front of the 8 m wall, and a mixed pixel (Ye & Borenstein 2002 §4.5)
  // between trunk and wall on beam 64.
  for (int i = 60; i <= 63; ++i) r[i] = 5.0f;
  r[64] = 6.6f;
  // A no-return on beam 120: its neighbours lose their partner.
  r[120] = 80.0f;
  const ScanPoints pts = ToScanPoints(ScanFor(sick, r), sick, 0.5, 0.15, nullptr);
  auto suspect = [&](int beam) {
    const int i = IndexOfBeam(pts, beam);
    EXPECT_GE(i, 0) << "beam " << beam;
    return i >= 0 && pts.mixed_suspect[i] != 0;
  };
  EXPECT_TRUE(suspect(59));   // wall point before the trunk
  EXPECT_TRUE(suspect(60));   // trunk edge
  EXPECT_FALSE(suspect(61));  // trunk interior
  EXPECT_FALSE(suspect(62));
  EXPECT_TRUE(suspect(63));  // trunk edge
  EXPECT_TRUE(suspect(64));  // the mixed pixel
  EXPECT_TRUE(suspect(65));  // wall point after it
  EXPECT_FALSE(suspect(66));
  EXPECT_FALSE(suspect(58));
  EXPECT_TRUE(suspect(119));
  EXPECT_TRUE(suspect(121));
  EXPECT_FALSE(suspect(117));
  int flagged = 0;
  for (uint8_t f : pts.mixed_suspect) flagged += f;
  EXPECT_EQ(flagged, 7);
}

TEST(RangeModelTest, SmoothWallIsNotFlaggedEvenAtHighIncidence) {
  // A flat wall 8 m ahead seen from −65° to +65°: the range grows by up to 0.7 m a beam at the
  // sides, yet there is no depth edge. Noise as the LMS 291 (1 cm, cm mode).
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, sick.range_sigma_m);
  std::vector<float> r(sick.num_beams, 80.0f);
  for (int i = 0; i < sick.num_beams; ++i) {
    const double bearing = sick.start_angle_rad + i * sick.angular_step_rad;
    if (std::abs(bearing) > 65.0 * kDegToRad + 1e-9) continue;
    const double range = 8.0 / std::cos(bearing) + noise(rng);
    r[i] = static_cast<float>(std::round(range / 0.01) * 0.01);
  }
  const ScanPoints pts = ToScanPoints(ScanFor(sick, r), sick, 0.5, 0.15, nullptr);
  ASSERT_EQ(pts.range_m.size(), 131u);
  for (size_t i = 0; i < pts.range_m.size(); ++i) {
    const bool at_end = pts.beam[i] == 25 || pts.beam[i] == 155;  // next to the no-returns
    EXPECT_EQ(pts.mixed_suspect[i] != 0, at_end) << "beam " << pts.beam[i];
  }
}

TEST(RangeModelTest, EmptyScanGivesNoPoints) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  RangeCounts counts;
  const ScanPoints pts = ToScanPoints(ScanFor(sick, {}), sick, 0.5, 0.15, &counts);
  EXPECT_TRUE(pts.p_scanner_m.empty());
  EXPECT_EQ(counts.valid, 0);
}

}  // namespace
}  // namespace wallcal::calib
