// SPDX-License-Identifier: Apache-2.0
// The simulated site: the survey and control points the surveyor would hand over, the walls
// placed when none are given, and which surface each beam meets (occlusions, mixed-pixel edges).
#include <gtest/gtest.h>

#include <GeographicLib/LocalCartesian.hpp>
#include <cmath>
#include <vector>

#include "common/angles.h"
#include "sim/simulator.h"
#include "test/support/sim_fixtures.h"

namespace wallcal::sim {
namespace {
using namespace testing_fixtures;  // NOLINT: the shared fixtures

// Total-station point back in local ENU.
Eigen::Vector2d StationToEnu(const sim::SimulationConfig& c, const io::SurveyPoint& p) {
  const double r = c.survey_rotation_rad;
  return {c.survey_origin_x_m + std::cos(r) * p.x_m - std::sin(r) * p.y_m,
          c.survey_origin_y_m + std::sin(r) * p.x_m + std::cos(r) * p.y_m};
}

TEST(SimulatorTest, SurveyPointsLieOnTheWall) {
  sim::SimulationConfig config = NoiseFreeConfig();
  // A distractor wall without a code is not surveyed.
  config.walls.push_back(Wall("shed", "", 20.0, -5.0, 20.0, 5.0, 2.5));
  const Collected exact = RunSim(config, CheapPreset(), 71);
  ASSERT_EQ(exact.session.walls.size(), 1u);
  EXPECT_EQ(exact.session.walls[0].id, "north_wall");
  EXPECT_EQ(exact.session.walls[0].code, "WALL1");
  int wall_points = 0;
  for (const auto& p : exact.session.survey) {
    if (p.code != "WALL1") continue;
    ++wall_points;
    const Eigen::Vector2d q = StationToEnu(config, p);
    EXPECT_NEAR(q.y(), 12.0, 1e-9) << p.id;
    EXPECT_LE(std::abs(q.x()), 15.0 + 1e-9) << p.id;
    EXPECT_NEAR(q.x() - std::round(q.x()), 0.0, 1e-9) << p.id;  // every 1 m from x = −15
    EXPECT_TRUE(p.z_m == 0.5 || p.z_m == 2.5) << p.id;
  }
  EXPECT_EQ(wall_points, 2 * 31);
  EXPECT_EQ(exact.session.survey[2].id, "W001");

  config.total_station_sigma_m = 0.003;
  const Collected noisy = RunSim(config, CheapPreset(), 71);
  double sq = 0.0, worst = 0.0;
  for (const auto& p : noisy.session.survey) {
    if (p.code != "WALL1") continue;
    const double d = StationToEnu(config, p).y() - 12.0;
    sq += d * d;
    worst = std::max(worst, std::abs(d));
  }
  const double rms = std::sqrt(sq / wall_points);
  EXPECT_NEAR(rms, config.total_station_sigma_m, 0.3 * config.total_station_sigma_m);
  EXPECT_LT(worst, 5.0 * config.total_station_sigma_m);
  EXPECT_GT(worst, 0.0);
}

TEST(SimulatorTest, ControlPointsScatterByControlSigma) {
  sim::SimulationConfig config = NoiseFreeConfig();  // exact total station: the reference
  config.control_sigma_m = 0.015;
  const Collected run = RunSim(config, CheapPreset(), 81);
  const GeographicLib::LocalCartesian enu(config.site_lat_deg, config.site_lon_deg,
                                          config.site_height_m);
  ASSERT_EQ(run.session.control.size(), 2u);
  double sq = 0.0;
  int n = 0;
  for (const auto& c : run.session.control) {
    const auto it = std::find_if(run.session.survey.begin(), run.session.survey.end(),
                                 [&c](const io::SurveyPoint& p) { return p.id == c.id; });
    ASSERT_NE(it, run.session.survey.end()) << c.id;
    EXPECT_EQ(it->code, "CTRL");
    const Eigen::Vector2d truth = StationToEnu(config, *it);
    EXPECT_NEAR(12.0 - truth.y(), 2.0, 1e-9);  // 2 m in front of the wall, on the vehicle side
    EXPECT_GT(std::abs(truth.x()), 10.0);      // near an end
    double e, nn, u;
    enu.Forward(c.lat_deg, c.lon_deg, c.h_m, e, nn, u);
    for (double d : {e - truth.x(), nn - truth.y(), u}) {
      EXPECT_LT(std::abs(d), 5.0 * config.control_sigma_m);
      sq += d * d;
      ++n;
    }
  }
  const double rms = std::sqrt(sq / n);
  EXPECT_GT(rms, 0.2 * config.control_sigma_m);
  EXPECT_LT(rms, 2.0 * config.control_sigma_m);

  config.control_sigma_m = 0.0;
  const Collected exact = RunSim(config, CheapPreset(), 81);
  double e, nn, u;
  enu.Forward(exact.session.control[0].lat_deg, exact.session.control[0].lon_deg,
              exact.session.control[0].h_m, e, nn, u);
  EXPECT_NEAR(nn, 12.0 - 2.0, 1e-6);
}

TEST(SimulatorTest, DefaultWallsOnlyWhenNoneGiven) {
  const sim::SimulationConfig with_default = WithDefaultWalls(sim::SimulationConfig{});
  ASSERT_EQ(with_default.walls.size(), 1u);
  EXPECT_EQ(with_default.walls[0].id, "north_wall");
  EXPECT_EQ(with_default.walls[0].code, "WALL1");
  EXPECT_DOUBLE_EQ(with_default.walls[0].y0_m, 12.0);
  EXPECT_DOUBLE_EQ(with_default.walls[0].y1_m, 12.0);
  EXPECT_DOUBLE_EQ(std::abs(with_default.walls[0].x1_m - with_default.walls[0].x0_m), 30.0);

  sim::SimulationConfig own;
  own.walls.push_back(Wall("east", "E1", 10.0, -5.0, 10.0, 5.0));
  const sim::SimulationConfig kept = WithDefaultWalls(own);
  ASSERT_EQ(kept.walls.size(), 1u);
  EXPECT_EQ(kept.walls[0].id, "east");
}

TEST(SimulatorTest, TrueBeamHitsNameTheSurfaceAndSeeOcclusions) {
  sim::SimulationConfig config = NoiseFreeConfig();
  sim::SimWall second;
  second.id = "east";
  second.code = "WALL2";
  second.x0_m = 14.0;
  second.y0_m = 12.0;
  second.x1_m = 14.0;
  second.y1_m = -4.0;
  config.walls.push_back(second);
  // A post right in front of the scanner when facing the wall (heading north).
  config.obstacles.push_back({0.0, 11.0, 0.3});
  const io::ScannerPreset preset = PerfectPreset();
  // The scanner at (0, 6.5) facing due north: the vehicle turned back by the mount yaw, the
  // antenna behind the scanner by the rotated lever arm.
  const double yaw = kPi / 2.0 - config.mount_yaw_rad;
  const Eigen::Vector2d lever(std::cos(yaw) * config.mount_x_m - std::sin(yaw) * config.mount_y_m,
                              std::sin(yaw) * config.mount_x_m + std::cos(yaw) * config.mount_y_m);
  const SimTruthPose pose = PoseAt(config, Eigen::Vector2d(0.0, 6.5) - lever, yaw);
  const std::vector<SimBeamHit> hits = TrueBeamHits(config, preset, pose);
  ASSERT_EQ(hits.size(), 181u);
  const SimBeamHit& ahead = hits[90];  // bearing 0: the post's near side
  EXPECT_NEAR(ahead.bearing_rad, 0.0, 1e-12);
  EXPECT_EQ(ahead.wall_index, -1);
  EXPECT_NEAR(ahead.range_m, 11.0 - 0.3 - 6.5, 1e-9);
  const SimBeamHit& left = hits[90 + 30];  // bearing +30°: the first wall, 5.5 m north
  EXPECT_EQ(left.wall_index, 0);
  EXPECT_NEAR(left.range_m, 5.5 / std::cos(30.0 * kDegToRad), 1e-9);
  EXPECT_TRUE(left.returned);
  const SimBeamHit& right = hits[90 - 80];  // bearing −80°: the second wall, 14 m east
  EXPECT_EQ(right.wall_index, 1);
  EXPECT_NEAR(right.range_m, 14.0 / std::cos(10.0 * kDegToRad), 1e-9);
  // The post's silhouette edges are mixed-pixel candidates, the middle of a wall is not.
  int edges = 0;
  for (const SimBeamHit& h : hits) edges += h.footprint_edge;
  EXPECT_GE(edges, 2);
  EXPECT_FALSE(left.footprint_edge);
  // Nor is a wall seen obliquely: bearing +65°, 13 m along the beam, whose footprint's edges lie
  // 0.39 m apart in range on the first wall.
  const SimBeamHit& oblique = hits[90 + 65];
  ASSERT_EQ(oblique.wall_index, 0);
  EXPECT_TRUE(oblique.returned);
  EXPECT_FALSE(oblique.footprint_edge);
}

}  // namespace
}  // namespace wallcal::sim
