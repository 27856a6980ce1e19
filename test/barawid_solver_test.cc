// Tests of seed 002's closed-form mount estimate (solvers/barawid_solver.cc), on wall
// observations synthesised here from a known mount, a known wall and known poses.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "calib/wall_geometry.h"
#include "solvers/mount_solver.h"
#include "common/angles.h"

namespace wallcal::solvers {
namespace {
const Mount kTruth{2.57, 0.056, 2.8 * kDegToRad};  // seed 002: a = −0.056, b = 2.57, δ = 2.8°

struct Noise {
  double rho_m = 0.0;
  double theta_rad = 0.0;
  double gnss_white_m = 0.0;
  double gnss_bias_m = 0.0;  // per station
  double heading_rad = 0.0;
};

calib::WallGeometry NorthWall() {
  calib::WallGeometry wall;
  wall.id = "north";
  wall.normal_local = Eigen::Vector2d(0.0, 1.0);
  wall.offset_m = 10.0;
  wall.end_a_local = Eigen::Vector2d(-10.0, 10.0);
  wall.end_b_local = Eigen::Vector2d(10.0, 10.0);
  wall.sigma_offset_m = 0.005;
  wall.sigma_angle_rad = 0.001;
  return wall;
}

Eigen::Vector2d Rotate(double angle_rad, const Eigen::Vector2d& v) {
  const double c = std::cos(angle_rad);
  const double s = std::sin(angle_rad);
  return Eigen::Vector2d(c * v.x() - s * v.y(), s * v.x() + c * v.y());
}

// `stations` stations 7.5-8.5 m south of the wall y = 10, facing it within ±35°, with
// `scans` scans each. The wall is exactly where it was surveyed.
std::vector<calib::WallObservation> Simulate(int stations, int scans, const Noise& noise,
                                             std::mt19937& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const calib::WallGeometry wall = NorthWall();
  std::vector<calib::WallObservation> observations;
  for (int k = 0; k < stations; ++k) {
    const double t = static_cast<double>(k) / (stations - 1);
    const double heading_rad = 0.5 * kPi + 35.0 * kDegToRad * (2 * t - 1);
    const double u = static_cast<double>((k * 7) % stations) / (stations - 1);
    const Eigen::Vector2d antenna(-4.0 + 8.0 * u, 1.5 + 0.5 * (k % 3));
    const Eigen::Vector2d bias = noise.gnss_bias_m * Eigen::Vector2d(unit(rng), unit(rng));
    const Eigen::Vector2d scanner = antenna + Rotate(heading_rad, {kTruth.x_m, kTruth.y_m});
    for (int j = 0; j < scans; ++j) {
      calib::WallObservation o;
      o.scan_index = k * scans + j;
      o.wall_index = 0;
      o.rho_m = wall.offset_m - wall.normal_local.dot(scanner) + noise.rho_m * unit(rng);
      o.theta_rad =
          WrapAngle(0.5 * kPi - heading_rad - kTruth.yaw_rad + noise.theta_rad * unit(rng));
      o.sigma_rho_m = 0.003;
      o.sigma_theta_rad = 0.002;
      o.pose.antenna_local_m =
          antenna + bias + noise.gnss_white_m * Eigen::Vector2d(unit(rng), unit(rng));
      o.pose.yaw_rad = heading_rad + noise.heading_rad * unit(rng);
      o.pose.stationary = true;
      o.pose.segment = k;
      observations.push_back(o);
    }
  }
  return observations;
}

TEST(SolveMountBarawidTest, RecoversMountExactlyOnNoiseFreeData) {
  std::mt19937 rng(1);
  const auto observations = Simulate(8, 5, Noise{}, rng);
  const MountEstimate estimate =
      SolveMountBarawid(observations, {NorthWall()}, io::SolverOptions{});
  ASSERT_TRUE(estimate.usable) << estimate.message;
  EXPECT_EQ(estimate.method, "barawid");
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
      SolveMountBarawid(observations, {NorthWall()}, io::SolverOptions{});
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
  const MountEstimate a = SolveMountBarawid(few, {NorthWall()}, io::SolverOptions{});
  const MountEstimate b = SolveMountBarawid(many, {NorthWall()}, io::SolverOptions{});
  ASSERT_TRUE(a.usable && b.usable);
  EXPECT_LT(std::sqrt(b.covariance(0, 0) / a.covariance(0, 0)), 0.5);
}

TEST(SolveMountBarawidTest, AgreesWithCeresOnCleanData) {
  std::mt19937 rng(4);
  const auto observations = Simulate(10, 10, Noise{}, rng);
  const std::vector<calib::WallGeometry> walls = {NorthWall()};
  const io::SolverOptions options;
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
      SolveMountBarawid(observations, {NorthWall()}, io::SolverOptions{});
  EXPECT_FALSE(estimate.usable);
  EXPECT_NE(estimate.message.find("only 15 wall observations; need at least 30"), std::string::npos)
      << estimate.message;
}

}  // namespace
}  // namespace wallcal::solvers
