// SPDX-License-Identifier: Apache-2.0
// Tests of Barawid 2007's closed-form mount estimate (solvers/barawid_solver.cc), on wall
// observations synthesised here from a known mount, a known wall and known poses.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "calib/wall_geometry.h"
#include "sim/synthetic_observations.h"
#include "solvers/mount_solver.h"
#include "common/angles.h"

namespace wallcal::solvers {
namespace {
const Mount kTruth{2.57, 0.056, 2.8 * kDegToRad};  // Barawid 2007: a = −0.056, b = 2.57, δ = 2.8°

struct Noise {
  double rho_m = 0.0;
  double theta_rad = 0.0;
  double gnss_white_m = 0.0;
  double gnss_bias_m = 0.0;  // per station
  double heading_rad = 0.0;
};

// The shared fixture (sim/synthetic_observations.h) with this test's noise: one north wall,
// the first wall of the fixture.
sim::SimSettings SettingsFor(int stations, int scans, const Noise& noise) {
  sim::SimSettings s;
  s.truth = kTruth;
  s.stations = stations;
  s.scans_per_station = scans;
  s.noise = noise.rho_m > 0 || noise.theta_rad > 0 || noise.gnss_white_m > 0 ||
            noise.gnss_bias_m > 0 || noise.heading_rad > 0;
  s.fit_sigma_rho_m = noise.rho_m > 0 ? noise.rho_m : 0.003;
  s.fit_sigma_theta_rad = noise.theta_rad > 0 ? noise.theta_rad : 0.002;
  s.gnss_white_sigma_m = noise.gnss_white_m;
  s.gnss_bias_sigma_m = noise.gnss_bias_m;
  s.heading_sigma_rad = noise.heading_rad;
  return s;
}

calib::WallGeometry NorthWall() {
  std::mt19937 rng(0);
  return sim::SimulateObservations(SettingsFor(2, 1, Noise{}), rng).walls.front();
}

std::vector<calib::WallObservation> Simulate(int stations, int scans, const Noise& noise,
                                             std::mt19937& rng) {
  return sim::SimulateObservations(SettingsFor(stations, scans, noise), rng).observations;
}

TEST(SolveMountBarawidTest, RecoversMountExactlyOnNoiseFreeData) {
  std::mt19937 rng(1);
  const auto observations = Simulate(8, 5, Noise{}, rng);
  const MountEstimate estimate =
      SolveMountBarawid(observations, {NorthWall()}, solvers::SolverOptions{});
  ASSERT_TRUE(estimate.usable) << estimate.message;
  EXPECT_EQ(estimate.method, solvers::Method::kBarawid);
  EXPECT_NEAR(estimate.mount.x_m, kTruth.x_m, 1e-9);
  EXPECT_NEAR(estimate.mount.y_m, kTruth.y_m, 1e-9);
  EXPECT_NEAR(estimate.mount.yaw_rad, kTruth.yaw_rad, 1e-9);
  EXPECT_EQ(estimate.observations_used, 40);
  EXPECT_EQ(estimate.observations_rejected, 0);
  EXPECT_LT(estimate.residual_rms_m, 1e-9);
  ASSERT_EQ(estimate.residual_rho_m.size(), observations.size());
  for (double r : estimate.residual_rho_m) EXPECT_NEAR(r, 0.0, 1e-9);
}

TEST(SolveMountBarawidTest, RecoversMountWithinToleranceOnNoisyData) {
  std::mt19937 rng(2);
  Noise noise;
  noise.rho_m = 0.003;
  noise.theta_rad = 0.002;
  noise.gnss_white_m = 0.003;
  noise.gnss_bias_m = 0.015;
  noise.heading_rad = 0.0009;
  const auto observations = Simulate(10, 20, noise, rng);
  const MountEstimate estimate =
      SolveMountBarawid(observations, {NorthWall()}, solvers::SolverOptions{});
  ASSERT_TRUE(estimate.usable) << estimate.message;
  // 1.5 cm of GNSS error per station over 10 stations, seen at ±35°: a few cm at most sideways.
  EXPECT_NEAR(estimate.mount.x_m, kTruth.x_m, 0.03);
  EXPECT_NEAR(estimate.mount.y_m, kTruth.y_m, 0.05);
  EXPECT_NEAR(estimate.mount.yaw_rad, kTruth.yaw_rad, 0.2 * kDegToRad);
  EXPECT_GT(estimate.residual_rms_m, 0.002);
  EXPECT_LT(estimate.residual_rms_m, 0.03);
  EXPECT_GT(estimate.covariance(0, 0), 0.0);
  EXPECT_GT(estimate.covariance(2, 2), 0.0);
}

TEST(SolveMountBarawidTest, NaiveSigmaShrinksWithScansAsPublished) {
  // The method treats every scan as independent: ten times the scans per station gives about
  // 1/√10 of the σ, although the stations' GNSS errors are what dominates. Kept as published.
  Noise noise;
  noise.rho_m = 0.003;
  noise.gnss_bias_m = 0.015;
  std::mt19937 rng(3);
  const auto few = Simulate(10, 20, noise, rng);
  std::mt19937 same_rng(3);
  const auto many = Simulate(10, 200, noise, same_rng);
  const MountEstimate a = SolveMountBarawid(few, {NorthWall()}, solvers::SolverOptions{});
  const MountEstimate b = SolveMountBarawid(many, {NorthWall()}, solvers::SolverOptions{});
  ASSERT_TRUE(a.usable && b.usable);
  EXPECT_LT(std::sqrt(b.covariance(0, 0) / a.covariance(0, 0)), 0.5);
}

TEST(SolveMountBarawidTest, AgreesWithCeresOnCleanData) {
  std::mt19937 rng(4);
  const auto observations = Simulate(10, 10, Noise{}, rng);
  const std::vector<calib::WallGeometry> walls = {NorthWall()};
  const solvers::SolverOptions options;
  const MountEstimate closed = SolveMountBarawid(observations, walls, options);
  const MountEstimate joint = SolveMountCeres(observations, walls, options, Mount{});
  ASSERT_TRUE(closed.usable) << closed.message;
  ASSERT_TRUE(joint.usable) << joint.message;
  EXPECT_NEAR(closed.mount.x_m, joint.mount.x_m, 1e-6);
  EXPECT_NEAR(closed.mount.y_m, joint.mount.y_m, 1e-6);
  EXPECT_NEAR(closed.mount.yaw_rad, joint.mount.yaw_rad, 1e-7);
}

TEST(SolveMountBarawidTest, RefusesTooFewObservations) {
  std::mt19937 rng(5);
  const auto observations = Simulate(5, 3, Noise{}, rng);
  const MountEstimate estimate =
      SolveMountBarawid(observations, {NorthWall()}, solvers::SolverOptions{});
  EXPECT_FALSE(estimate.usable);
  EXPECT_NE(estimate.message.find("only 15 wall observations; need at least 30"), std::string::npos)
      << estimate.message;
}

}  // namespace
}  // namespace wallcal::solvers
