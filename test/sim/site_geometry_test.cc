// SPDX-License-Identifier: Apache-2.0
// The simulated site in three dimensions (sim/site_geometry.h): the vehicle's attitude on a
// graded yard, the beams of a tilted scanner against upright and leaning walls and the ground,
// worked out by hand.
#include "sim/site_geometry.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "common/angles.h"
#include "sim/simulator.h"
#include "test/support/sim_fixtures.h"

namespace wallcal::sim {
namespace {
using namespace testing_fixtures;  // NOLINT: the shared fixtures

// A level yard with the antenna antenna_height_m above it, the scanner under the antenna
// (mount x, y, yaw 0) at mount_z_m, pitched scanner_pitch_deg; one long wall across the north
// at y = wall_y_m, wall_height_m tall.
SimulationConfig LevelYard(double antenna_height_m, double mount_z_m, double scanner_pitch_deg,
                           double wall_y_m, double wall_height_m) {
  SimulationConfig config = NoiseFreeConfig();
  config.antenna_height_m = antenna_height_m;
  config.mount_x_m = 0.0;
  config.mount_y_m = 0.0;
  config.mount_yaw_rad = 0.0;
  config.mount_z_m = mount_z_m;
  config.scanner_pitch_rad = scanner_pitch_deg * kDegToRad;
  config.walls = {Wall("north", "N1", -100.0, wall_y_m, 100.0, wall_y_m, wall_height_m)};
  return config;
}

// The vehicle's antenna at the site origin, facing north, standing on the level yard.
SimTruthPose FacingNorth(const SimulationConfig& config) {
  SimTruthPose pose = PoseAt(config, Eigen::Vector2d::Zero(), kPi / 2.0);
  pose.antenna_up_m = SiteOf(config).AntennaUpM(pose.antenna_enu_m);
  return pose;
}

TEST(SiteGeometryTest, PitchedScannerMeetsAVerticalWallAtDOverCosPitchCosBearing) {
  const double d_m = 5.0;
  const double pitch_rad = -3.0 * kDegToRad;
  const SimulationConfig config = LevelYard(3.0, -1.0, -3.0, d_m, 5.0);
  ASSERT_TRUE(config.IsThreeDSite());
  const SimTruthPose pose = FacingNorth(config);
  EXPECT_DOUBLE_EQ(pose.antenna_up_m, 3.0);
  const io::ScannerPreset preset = PerfectPreset();
  const std::vector<SimBeamHit> hits = TrueBeamHits(config, preset, pose);
  ASSERT_EQ(hits.size(), 181u);
  int checked = 0;
  for (const SimBeamHit& hit : hits) {
    // The scanner 2 m above the ground: every beam meets the wall's plane 2 − d·tan 3° = 1.74 m
    // above its foot, on its face.
    if (std::abs(hit.bearing_rad) > 60.5 * kDegToRad) continue;
    const double expected_m = d_m / (std::cos(pitch_rad) * std::cos(hit.bearing_rad));
    EXPECT_EQ(hit.wall_index, 0) << hit.bearing_rad;
    EXPECT_FALSE(hit.ground);
    EXPECT_NEAR(hit.range_m, expected_m, 1e-9) << hit.bearing_rad;
    EXPECT_NEAR(hit.cos_incidence, std::cos(pitch_rad) * std::cos(hit.bearing_rad), 1e-12);
    ++checked;
  }
  EXPECT_EQ(checked, 121);

  // The scanner's pose: 1 m below the antenna, its x axis north and 3° down.
  const SimScannerPose scanner = TrueScannerPose(config, pose);
  EXPECT_NEAR((scanner.origin_enu_m - Eigen::Vector3d(0.0, 0.0, 2.0)).norm(), 0.0, 1e-12);
  const Eigen::Vector3d ahead = scanner.BeamEnu(0.0);
  EXPECT_NEAR((ahead - Eigen::Vector3d(0.0, std::cos(pitch_rad), std::sin(pitch_rad))).norm(),
              0.0, 1e-12);
}

TEST(SiteGeometryTest, BeamsPassOverAWallsTopAndMeetTheGround) {
  // The scanner 3 m above the ground pitched 3° down; at 5 m the centre beam is at
  // 3 − 5·tan 3° = 2.738 m, above a 2.7 m wall: it returns from the ground at 3/sin 3°.
  const double pitch_rad = -3.0 * kDegToRad;
  const SimulationConfig config = LevelYard(3.0, 0.0, -3.0, 5.0, 2.7);
  const std::vector<SimBeamHit> hits = TrueBeamHits(config, PerfectPreset(), FacingNorth(config));
  const SimBeamHit& ahead = hits[90];
  ASSERT_DOUBLE_EQ(ahead.bearing_rad, 0.0);
  EXPECT_TRUE(ahead.ground);
  EXPECT_EQ(ahead.wall_index, -1);
  EXPECT_NEAR(ahead.range_m, 3.0 / std::sin(-pitch_rad), 1e-9);
  EXPECT_NEAR(ahead.cos_incidence, std::sin(-pitch_rad), 1e-12);
  // 57 m is within the LMS 291's 80 m, but the ground is met at 87° incidence, beyond its 75°.
  EXPECT_FALSE(ahead.returned);
  // Every beam crosses the wall's plane at the same 2.738 m (it drops d·tan 3° over the
  // horizontal distance d): none meets the wall.
  for (const SimBeamHit& hit : hits) EXPECT_NE(hit.wall_index, 0) << hit.bearing_rad;
  // A wall 0.1 m taller stops them all.
  const SimulationConfig taller = LevelYard(3.0, 0.0, -3.0, 5.0, 2.8);
  const std::vector<SimBeamHit> stopped =
      TrueBeamHits(taller, PerfectPreset(), FacingNorth(taller));
  EXPECT_EQ(stopped[90].wall_index, 0);
  EXPECT_NEAR(stopped[90].range_m, 5.0 / std::cos(pitch_rad), 1e-9);
}

TEST(SiteGeometryTest, TheVehicleTakesTheGradeUnderItsHeading) {
  SimulationConfig config = NoiseFreeConfig();
  config.yard_grade_pct = 5.0;
  config.yard_grade_dir_rad = 0.0;  // rising towards true north
  const Site site = SiteOf(config);
  ASSERT_TRUE(site.has_ground);
  const double grade_rad = std::atan(0.05);
  // Facing up the slope (north, yaw π/2 ccw from east): nose up by atan(grade), level across.
  VehicleAttitude a = site.AttitudeAt(kPi / 2.0);
  EXPECT_NEAR(a.pitch_rad, grade_rad, 1e-12);
  EXPECT_NEAR(a.roll_rad, 0.0, 1e-12);
  // Facing down it: nose down.
  a = site.AttitudeAt(-kPi / 2.0);
  EXPECT_NEAR(a.pitch_rad, -grade_rad, 1e-12);
  EXPECT_NEAR(a.roll_rad, 0.0, 1e-12);
  // Side-on facing east: the ground rises to the left (north), the right side is low: roll > 0.
  a = site.AttitudeAt(0.0);
  EXPECT_NEAR(a.pitch_rad, 0.0, 1e-12);
  EXPECT_NEAR(a.roll_rad, grade_rad, 1e-12);
  // Facing west: the ground rises to the right, roll < 0.
  a = site.AttitudeAt(kPi);
  EXPECT_NEAR(a.roll_rad, -grade_rad, 1e-12);

  // Any heading: the vehicle's x and y axes lie in the ground, its z axis is the ground's normal.
  for (double yaw_deg : {0.0, 17.0, 60.0, 135.0, 200.0, 301.0}) {
    const double yaw_rad = yaw_deg * kDegToRad;
    const VehicleAttitude att = site.AttitudeAt(yaw_rad);
    const Eigen::Matrix3d r = EnuRotation(yaw_rad, att.pitch_rad, att.roll_rad);
    const Eigen::Vector3d normal = site.GroundNormalEnu();
    EXPECT_NEAR(r.col(0).dot(normal), 0.0, 1e-12) << yaw_deg;
    EXPECT_NEAR(r.col(1).dot(normal), 0.0, 1e-12) << yaw_deg;
    EXPECT_NEAR((r.col(2) - normal).norm(), 0.0, 1e-12) << yaw_deg;
  }
}

TEST(SiteGeometryTest, RotationConventionsMatchTheEngine) {
  // R_v = Rz(ψ)·Ry(−pitch)·Rx(roll): pitch up lifts the nose, roll positive lowers the right side.
  const double p = 0.1, r = 0.2;
  const Eigen::Matrix3d pitched = EnuRotation(0.0, p, 0.0);
  EXPECT_NEAR(pitched(2, 0), std::sin(p), 1e-15);  // x axis (forward) rises
  const Eigen::Matrix3d rolled = EnuRotation(0.0, 0.0, r);
  EXPECT_NEAR(rolled(2, 1), std::sin(r), 1e-15);  // y axis (left) rises: the right side drops
  const Eigen::Matrix3d yawed = EnuRotation(kPi / 2.0, 0.0, 0.0);
  EXPECT_NEAR(yawed(1, 0), 1.0, 1e-15);  // x axis north at ψ = 90° ccw from east
}

TEST(SiteGeometryTest, ATiltedScannerOnATiltedVehicleComposes) {
  // The scanner pitched on a vehicle that rolls on a side slope, mount yaw 90° (looking left):
  // the beam's ENU direction is R_v·Rz(mount_yaw)·Ry(−pitch)·Rx(roll)·(cos b, sin b, 0).
  ScannerMount mount;
  mount.lever_m = {1.0, 0.5, -2.0};
  mount.yaw_rad = kPi / 2.0;
  mount.pitch_rad = -0.05;
  mount.roll_rad = 0.02;
  const VehicleAttitude vehicle{0.03, -0.01};
  const double yaw_rad = 0.7;
  const SimScannerPose pose =
      ScannerPoseOf(mount, Eigen::Vector2d(10.0, 20.0), 5.0, yaw_rad, vehicle);
  const Eigen::Matrix3d r_v = EnuRotation(yaw_rad, vehicle.pitch_rad, vehicle.roll_rad);
  const Eigen::Matrix3d r_s =
      r_v * EnuRotation(mount.yaw_rad, mount.pitch_rad, mount.roll_rad);
  EXPECT_NEAR((pose.EnuRScanner() - r_s).norm(), 0.0, 1e-12);
  const Eigen::Vector3d origin = Eigen::Vector3d(10.0, 20.0, 5.0) + r_v * mount.lever_m;
  EXPECT_NEAR((pose.origin_enu_m - origin).norm(), 0.0, 1e-12);
  for (double b : {-1.2, 0.0, 0.4}) {
    const Eigen::Vector3d expected = r_s * Eigen::Vector3d(std::cos(b), std::sin(b), 0.0);
    EXPECT_NEAR((pose.BeamEnu(b) - expected).norm(), 0.0, 1e-12);
  }
}

TEST(SiteGeometryTest, ALeaningWallIsMetWhereItsFaceIs) {
  // The wall's top leans 2° away (north) from a scanner 0.8 m above a level ground, 6 m south of
  // the wall's foot: the level centre beam meets the face 0.8·tan 2° beyond the foot line.
  const double lean_rad = 2.0 * kDegToRad;
  SimulationConfig config = LevelYard(3.0, -2.2, 0.0, 6.0, 3.0);
  config.walls[0].lean_rad = lean_rad;  // (−100, 6) → (100, 6): its left is north
  const std::vector<SimBeamHit> hits = TrueBeamHits(config, PerfectPreset(), FacingNorth(config));
  const double face_m = 6.0 + 0.8 * std::tan(lean_rad);
  for (int i : {60, 90, 120}) {
    const SimBeamHit& hit = hits[i];
    EXPECT_EQ(hit.wall_index, 0);
    EXPECT_NEAR(hit.range_m, face_m / std::cos(hit.bearing_rad), 1e-9);
    EXPECT_NEAR(hit.cos_incidence, std::cos(lean_rad) * std::cos(hit.bearing_rad), 1e-12);
  }
  // The face point of WallFacePoint lies where the beams meet it.
  const Eigen::Vector3d q = WallFacePoint(SiteOf(config), config.walls[0], {0.0, 6.0}, 0.8);
  EXPECT_NEAR((q - Eigen::Vector3d(0.0, face_m, 0.8)).norm(), 0.0, 1e-12);
}

TEST(SiteGeometryTest, TheAntennaStandsItsHeightAboveTheGroundAlongTheNormal) {
  SimulationConfig config = NoiseFreeConfig();
  config.yard_grade_pct = 4.0;
  config.yard_grade_dir_rad = 30.0 * kDegToRad;  // rising towards N30°E
  config.antenna_height_m = 2.5;
  const Site site = SiteOf(config);
  const Eigen::Vector2d rise(std::sin(30.0 * kDegToRad), std::cos(30.0 * kDegToRad));
  const Eigen::Vector2d p(7.0, -3.0);
  EXPECT_NEAR(site.GroundUpM(p), 0.04 * rise.dot(p), 1e-12);
  const Eigen::Vector3d antenna(p.x(), p.y(), site.AntennaUpM(p));
  // Its distance from the ground plane (through the site origin) is the height.
  EXPECT_NEAR(site.GroundNormalEnu().dot(antenna), 2.5, 1e-12);
}

TEST(SiteGeometryTest, TheTwoDimensionalModelHasNoGround) {
  const SimulationConfig config = NoiseFreeConfig();
  ASSERT_FALSE(config.IsThreeDSite());
  const Site site = SiteOf(config);
  EXPECT_FALSE(site.has_ground);
  EXPECT_EQ(site.AntennaUpM({5.0, 5.0}), 0.0);
  const VehicleAttitude a = site.AttitudeAt(1.0);
  EXPECT_EQ(a.roll_rad, 0.0);
  EXPECT_EQ(a.pitch_rad, 0.0);
  // A beam that would dip below a 3-D site's ground meets the wall, endless in height.
  const SimTruthPose pose = PoseAt(config, Eigen::Vector2d(0.0, 0.0), kPi / 2.0);
  const std::vector<SimBeamHit> hits = TrueBeamHits(config, PerfectPreset(), pose);
  for (const SimBeamHit& hit : hits) EXPECT_FALSE(hit.ground);
}

}  // namespace
}  // namespace wallcal::sim
