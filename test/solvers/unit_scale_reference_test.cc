// SPDX-License-Identifier: Apache-2.0
// The rho a unit's scale error multiplies (solvers/unit_scale_reference.h): never the scan's own
// measured rho where other scans of its dwell, or moving scans on its wall close in time, can
// stand for it.
#include "solvers/unit_scale_reference.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <vector>

#include "common/angles.h"

namespace wallcal::solvers {
namespace {

// A wall along the local x axis at y = 10 m, seen from below (its normal +y).
WallLineMeasurement Facing(const Eigen::Vector2d& antenna_m, double rho_m) {
  WallLineMeasurement m;
  m.antenna_local_m = antenna_m;
  m.vehicle_yaw_rad = 0.5 * kPi;  // the vehicle's x axis towards the wall
  m.wall_normal_local = Eigen::Vector2d(0.0, 1.0);
  m.wall_centre_local_m = Eigen::Vector2d(3.0, 10.0);
  m.sign = 1.0;
  m.rho_m = rho_m;
  return m;
}

calib::WallObservation At(double stamp_s, bool standing, int dwell, int wall = 0) {
  calib::WallObservation o;
  o.pose.stamp_s = stamp_s;
  o.pose.stationary = standing;
  o.pose.segment = dwell;
  o.wall_index = wall;
  return o;
}

const calib::Mount kMount{0.5, 0.2, 0.0};

TEST(UnitScaleReferenceTest, PredictedRhoIsTheScannersDistanceToTheSurveyedWall) {
  // The vehicle faces +y: the mount's x is along +y, its y along −x. Scanner at (0.8, 2.5).
  const WallLineMeasurement m = Facing(Eigen::Vector2d(1.0, 2.0), 0.0);
  EXPECT_NEAR(PredictedRho(m, kMount), 10.0 - 2.5, 1e-12);
  WallLineMeasurement other_side = m;
  other_side.sign = -1.0;
  EXPECT_NEAR(PredictedRho(other_side, kMount), -(10.0 - 2.5), 1e-12);
}

TEST(UnitScaleReferenceTest, StandingScanTakesTheMeanOfTheOtherScansOfItsDwellOnItsWall) {
  const Eigen::Vector2d p(1.0, 2.0);
  const std::vector<WallLineMeasurement> lines = {Facing(p, 7.0), Facing(p, 7.1), Facing(p, 7.3),
                                                  Facing(p, 6.0), Facing(p, 4.0)};
  const std::vector<calib::WallObservation> scans = {
      At(0.0, true, 3), At(0.1, true, 3), At(0.2, true, 3), At(0.2, true, 3, 1), At(9.0, true, 4)};
  const std::vector<double> reference = UnitScaleReferences(scans, lines, kMount, 0.5);
  ASSERT_EQ(reference.size(), 5u);
  EXPECT_NEAR(reference[0], 7.2, 1e-12);
  EXPECT_NEAR(reference[1], 7.15, 1e-12);
  EXPECT_NEAR(reference[2], 7.05, 1e-12);
  // Alone in its group (another wall of the dwell; a dwell of one scan): its own rho.
  EXPECT_EQ(reference[3], 6.0);
  EXPECT_EQ(reference[4], 4.0);
}

TEST(UnitScaleReferenceTest, MovingScanTakesItsPredictionPlusTheOthersMeasuredMinusPredicted) {
  // Driving towards the wall: the predicted rho falls with the antenna's y. The measured lines
  // sit 10, 20, 60 mm beyond the prediction (the pose's error and the lines' noise).
  const double ys[] = {2.0, 2.15, 2.3, 3.0};
  const double beyond[] = {0.010, 0.020, 0.060, 0.0};
  std::vector<WallLineMeasurement> lines;
  std::vector<calib::WallObservation> scans;
  const double stamps[] = {0.0, 0.3, 0.6, 2.0};
  for (int i = 0; i < 4; ++i) {
    WallLineMeasurement m = Facing(Eigen::Vector2d(1.0, ys[i]), 0.0);
    m.rho_m = PredictedRho(m, kMount) + beyond[i];
    lines.push_back(m);
    scans.push_back(At(stamps[i], false, 7));
  }
  const std::vector<double> reference = UnitScaleReferences(scans, lines, kMount, 0.5);
  ASSERT_EQ(reference.size(), 4u);
  const auto predicted = [&](int i) { return PredictedRho(lines[i], kMount); };
  EXPECT_NEAR(reference[0], predicted(0) + 0.020, 1e-12);  // the scan at 0.3 s only
  EXPECT_NEAR(reference[1], predicted(1) + 0.035, 1e-12);  // those at 0 and 0.6 s
  EXPECT_NEAR(reference[2], predicted(2) + 0.020, 1e-12);
  EXPECT_EQ(reference[3], lines[3].rho_m);  // nothing within 0.5 s: its own
}

TEST(UnitScaleReferenceTest, StandingAndMovingScansAreNeverEachOthersReference) {
  const Eigen::Vector2d p(1.0, 2.0);
  const std::vector<WallLineMeasurement> lines = {Facing(p, 7.0), Facing(p, 7.4)};
  const std::vector<calib::WallObservation> scans = {At(0.0, true, 2), At(0.1, false, 2)};
  const std::vector<double> reference = UnitScaleReferences(scans, lines, kMount, 0.5);
  EXPECT_EQ(reference[0], 7.0);
  EXPECT_EQ(reference[1], 7.4);
}

}  // namespace
}  // namespace wallcal::solvers
