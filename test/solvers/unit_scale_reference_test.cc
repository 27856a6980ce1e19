// SPDX-License-Identifier: Apache-2.0
// The rho a unit's scale error multiplies (solvers/unit_scale_reference.h): never the scan's own
// measured rho where other scans of its dwell, or moving scans on its wall close in time, can
// stand for it.
#include "solvers/unit_scale_reference.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <vector>

#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "test/support/synthetic_fixtures.h"

namespace wallcal::solvers {
namespace {

// A scan from the antenna at (1, y), the vehicle's x axis towards the wall.
calib::WallObservation At(double stamp_s, bool standing, int dwell, int wall = 0,
                          double antenna_y_m = 2.0) {
  calib::WallObservation o;
  o.pose.stamp_s = stamp_s;
  o.pose.stationary = standing;
  o.pose.segment = dwell;
  o.pose.antenna_local_m = Eigen::Vector2d(1.0, antenna_y_m);
  o.pose.yaw_rad = 0.5 * kPi;
  o.wall_index = wall;
  return o;
}

WallLineMeasurement Line(double rho_m) {
  WallLineMeasurement m;
  m.rho_m = rho_m;
  return m;
}

const calib::Mount kMount{0.5, 0.2, 0.0};
// The wall y = 10 m, twice (walls 0 and 1).
const std::vector<calib::WallGeometry> kWalls = {testing_support::NorthWall(),
                                                 testing_support::NorthWall()};

TEST(UnitScaleReferenceTest, StandingScanTakesTheMeanOfTheOtherScansOfItsDwellOnItsWall) {
  const std::vector<WallLineMeasurement> lines = {Line(7.0), Line(7.1), Line(7.3), Line(6.0),
                                                  Line(4.0)};
  const std::vector<calib::WallObservation> scans = {
      At(0.0, true, 3), At(0.1, true, 3), At(0.2, true, 3), At(0.2, true, 3, 1), At(9.0, true, 4)};
  const std::vector<double> reference = UnitScaleReferences(scans, lines, kWalls, kMount, 0.5);
  ASSERT_EQ(reference.size(), 5u);
  EXPECT_NEAR(reference[0], 7.2, 1e-12);
  EXPECT_NEAR(reference[1], 7.15, 1e-12);
  EXPECT_NEAR(reference[2], 7.05, 1e-12);
  // Alone in its group (another wall of the dwell; a dwell of one scan): its own rho.
  EXPECT_EQ(reference[3], 6.0);
  EXPECT_EQ(reference[4], 4.0);
}

TEST(UnitScaleReferenceTest, MovingScanTakesItsPredictionPlusTheOthersMeasuredMinusPredicted) {
  // Driving towards the wall: the predicted rho falls with the antenna's y (the scanner sits
  // 0.5 m ahead of it, so at y it is 10 − 0.5 − y from the wall). The measured lines sit 10, 20,
  // 60 mm beyond the prediction (the pose's error and the lines' noise).
  const double ys[] = {2.0, 2.15, 2.3, 3.0};
  const double beyond[] = {0.010, 0.020, 0.060, 0.0};
  const double stamps[] = {0.0, 0.3, 0.6, 2.0};
  std::vector<WallLineMeasurement> lines;
  std::vector<calib::WallObservation> scans;
  std::vector<double> predicted;
  for (int i = 0; i < 4; ++i) {
    scans.push_back(At(stamps[i], false, 7, 0, ys[i]));
    predicted.push_back(calib::PredictRho(scans.back(), kWalls[0], kMount));
    EXPECT_NEAR(predicted.back(), 10.0 - 0.5 - ys[i], 1e-12);
    lines.push_back(Line(predicted.back() + beyond[i]));
  }
  const std::vector<double> reference = UnitScaleReferences(scans, lines, kWalls, kMount, 0.5);
  ASSERT_EQ(reference.size(), 4u);
  EXPECT_NEAR(reference[0], predicted[0] + 0.020, 1e-12);  // the scan at 0.3 s only
  EXPECT_NEAR(reference[1], predicted[1] + 0.035, 1e-12);  // those at 0 and 0.6 s
  EXPECT_NEAR(reference[2], predicted[2] + 0.020, 1e-12);
  EXPECT_EQ(reference[3], lines[3].rho_m);  // nothing within 0.5 s: its own
}

TEST(UnitScaleReferenceTest, StandingAndMovingScansAreNeverEachOthersReference) {
  const std::vector<WallLineMeasurement> lines = {Line(7.0), Line(7.4)};
  const std::vector<calib::WallObservation> scans = {At(0.0, true, 2), At(0.1, false, 2)};
  const std::vector<double> reference = UnitScaleReferences(scans, lines, kWalls, kMount, 0.5);
  EXPECT_EQ(reference[0], 7.0);
  EXPECT_EQ(reference[1], 7.4);
}

}  // namespace
}  // namespace wallcal::solvers
