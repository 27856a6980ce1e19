// SPDX-License-Identifier: Apache-2.0
#pragma once
// Expectations on a survey point a reader returned: the fields a test's file spells out,
// checked in one call (a failure names the point).

#include <gtest/gtest.h>

#include <array>
#include <string>

#include "io/types.h"

namespace wallcal::testing_support {

// A point as the test's file writes it: its frame, id and code, its coordinates (x, y, z in a
// local frame; latitude, longitude and ellipsoidal height for a rover point), the horizontal
// 1σ the file gives (0: none) and its line (0: not checked).
struct ExpectedPoint {
  io::SurveyFrame frame;
  std::string id, code;
  std::array<double, 3> coordinates;
  double sigma_m = 0.0;
  int line = 0;
};

inline void ExpectPoint(const io::SurveyPoint& point, const ExpectedPoint& expected) {
  SCOPED_TRACE("point " + expected.id);
  const bool local = expected.frame == io::SurveyFrame::kLocal;
  EXPECT_EQ(point.frame, expected.frame);
  EXPECT_EQ(point.id, expected.id);
  EXPECT_EQ(point.code, expected.code);
  EXPECT_DOUBLE_EQ(local ? point.x_m : point.lat_deg, expected.coordinates[0]);
  EXPECT_DOUBLE_EQ(local ? point.y_m : point.lon_deg, expected.coordinates[1]);
  EXPECT_DOUBLE_EQ(point.z_m, expected.coordinates[2]);
  EXPECT_DOUBLE_EQ(point.sigma_m, expected.sigma_m);
  if (expected.line != 0) {
    EXPECT_EQ(point.line, expected.line);
  }
}

}  // namespace wallcal::testing_support
