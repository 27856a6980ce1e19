// SPDX-License-Identifier: Apache-2.0
// The checks both solvers run before a solve (solvers/observability.h), on hand-made
// observations of one north wall: counts, stations and the spread of vehicle-to-wall angles.

#include "solvers/observability.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "common/angles.h"
#include "test/support/synthetic_fixtures.h"

namespace wallcal::solvers {
namespace {

using testing_support::NorthWall;

// `per_station` observations at each of the yaws (rad), one station per yaw, the vehicle at the
// origin (in front of the wall): φ = π/2 − yaw.
std::vector<calib::WallObservation> Stations(const std::vector<double>& yaws_rad, int per_station) {
  std::vector<calib::WallObservation> observations;
  for (size_t s = 0; s < yaws_rad.size(); ++s) {
    for (int k = 0; k < per_station; ++k) {
      calib::WallObservation o;
      o.wall_index = 0;
      o.scan_index = static_cast<int>(s) * per_station + k;
      o.pose.yaw_rad = yaws_rad[s];
      o.pose.antenna_local_m = Eigen::Vector2d::Zero();
      o.pose.stationary = true;
      o.pose.segment = static_cast<int>(s);
      observations.push_back(o);
    }
  }
  return observations;
}

SolverOptions Options() {
  SolverOptions options;
  options.min_observations = 10;
  options.min_stations = 3;
  options.min_heading_spread_rad = 20.0 * kDegToRad;
  return options;
}

TEST(ObservabilityTest, NoObservationsCannotBeSolvedNorForced) {
  const ObservabilityReport report = CheckObservability({}, {NorthWall()}, Options());
  EXPECT_FALSE(report.ok);
  EXPECT_FALSE(report.solvable);
  EXPECT_FALSE(report.message.empty());
}

TEST(ObservabilityTest, AWallIndexOutsideTheWallsIsReportedNotCrashedOn) {
  std::vector<calib::WallObservation> observations =
      Stations({-0.3, 0.0, 0.3}, 5);
  observations[4].wall_index = 3;
  const ObservabilityReport report = CheckObservability(observations, {NorthWall()}, Options());
  EXPECT_FALSE(report.ok);
  EXPECT_FALSE(report.solvable);
}

TEST(ObservabilityTest, EnoughStationsOverAWideArcPass) {
  const ObservabilityReport report =
      CheckObservability(Stations({-0.4, 0.0, 0.4}, 5), {NorthWall()}, Options());
  EXPECT_TRUE(report.ok) << report.message;
  EXPECT_TRUE(report.message.empty());
  EXPECT_EQ(report.num_observations, 15);
  EXPECT_EQ(report.num_stations, 3);
  // φ = π/2 − yaw: from π/2 − 0.4 to π/2 + 0.4.
  EXPECT_NEAR(report.angle_spread_rad, 0.8, 1e-12);
}

TEST(ObservabilityTest, TooFewObservationsOrStationsCanBeForced) {
  const ObservabilityReport few = CheckObservability(Stations({-0.4, 0.0, 0.4}, 3),
                                                     {NorthWall()}, Options());
  EXPECT_FALSE(few.ok);
  EXPECT_TRUE(few.solvable);
  EXPECT_EQ(few.num_observations, 9);
  const ObservabilityReport two = CheckObservability(Stations({-0.4, 0.4}, 10),
                                                     {NorthWall()}, Options());
  EXPECT_FALSE(two.ok);
  EXPECT_TRUE(two.solvable);
  EXPECT_EQ(two.num_stations, 2);
  EXPECT_NE(few.message, two.message);
}

TEST(ObservabilityTest, ANarrowArcNamesTheAxisItLeavesOpen) {
  // Every station square to the north wall: φ spans 10°, below the 20° asked for. The wall's
  // normal lies along the vehicle's y (lateral) axis; x (forward) is not determined.
  const ObservabilityReport report = CheckObservability(
      Stations({-5.0 * kDegToRad, 0.0, 5.0 * kDegToRad}, 5), {NorthWall()}, Options());
  EXPECT_FALSE(report.ok);
  EXPECT_TRUE(report.solvable);
  EXPECT_NEAR(report.angle_spread_rad, 10.0 * kDegToRad, 1e-12);
  EXPECT_EQ(report.message.rfind("forward offset x is not determined", 0), 0u) << report.message;
}

TEST(ObservabilityTest, OppositeNormalsAreTheSameAxis) {
  // Facing the wall and facing away from it (yaw + π) constrain the same mount component: the
  // spread is taken modulo π.
  const ObservabilityReport report =
      CheckObservability(Stations({0.0, kPi, 0.05}, 5), {NorthWall()}, Options());
  EXPECT_NEAR(report.angle_spread_rad, 0.05, 1e-9);
  EXPECT_FALSE(report.ok);
}

}  // namespace
}  // namespace wallcal::solvers
