// SPDX-License-Identifier: Apache-2.0
#include "calib/gnss_slices.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace wallcal::calib {
namespace {

WallObservation At(double stamp_s, double start_s, double slice_s) {
  WallObservation o;
  o.pose.stamp_s = stamp_s;
  o.pose.gnss_segment = static_cast<int>(std::floor((stamp_s - start_s) / slice_s));
  return o;
}

TEST(GnssSlicesTest, PartsAreTheFewestNoLongerThanTheLimit) {
  EXPECT_EQ(SliceParts(0.25, 0.05), 5);   // 0.25 / 0.05 is a hair over 5 in floating point
  EXPECT_EQ(SliceParts(0.25, 0.06), 5);
  EXPECT_EQ(SliceParts(0.25, 0.1), 3);
  EXPECT_EQ(SliceParts(0.25, 0.25), 1);
  EXPECT_EQ(SliceParts(0.25, 1.0), 1);
  EXPECT_EQ(SliceParts(0.25, 0.0), 1);
  EXPECT_EQ(SliceParts(0.0, 0.05), 1);
}

TEST(GnssSlicesTest, SubSlicesNestAndFollowTheTimeGrid) {
  const double start_s = 1000.3, slice_s = 0.25;
  const int parts = 5;
  std::vector<WallObservation> observations;
  for (int k = 0; k < 400; ++k) observations.push_back(At(start_s + 0.0123 + 0.0137 * k, start_s, slice_s));
  WallObservation none;
  none.pose.stamp_s = start_s + 2.0;
  none.pose.gnss_segment = -1;
  observations.push_back(none);
  const std::vector<WallObservation> before = observations;
  RefineGnssSlices(start_s, slice_s, parts, &observations);
  for (size_t i = 0; i + 1 < observations.size(); ++i) {
    const int fine = observations[i].pose.gnss_segment;
    EXPECT_EQ(fine / parts, before[i].pose.gnss_segment) << i;  // nested in its own slice
    // On the grid of slice_s / parts (away from the boundaries, where rounding may go either way).
    const double position = (observations[i].pose.stamp_s - start_s) / (slice_s / parts);
    if (std::abs(position - std::round(position)) > 1e-6) {
      EXPECT_EQ(fine, static_cast<int>(std::floor(position))) << i;
    }
  }
  EXPECT_EQ(observations.back().pose.gnss_segment, -1);  // no slice: left alone
}

TEST(GnssSlicesTest, OnePartLeavesTheSlicesAlone) {
  std::vector<WallObservation> observations = {At(10.4, 10.0, 0.25), At(10.9, 10.0, 0.25)};
  RefineGnssSlices(10.0, 0.25, 1, &observations);
  EXPECT_EQ(observations[0].pose.gnss_segment, 1);
  EXPECT_EQ(observations[1].pose.gnss_segment, 3);
}

}  // namespace
}  // namespace wallcal::calib
