// SPDX-License-Identifier: Apache-2.0
// The site in 3-D (calib/site_geometry.h, calib/attitude_model.h): the level model where the site
// is level, the geometry worked by hand where it is not, the yard's plane from antenna heights.

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "calib/attitude_model.h"
#include "calib/site_geometry.h"
#include "calib/wall_geometry.h"

namespace wallcal::calib {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A wall along local x at y = 12 m, its normal pointing north.
WallGeometry NorthWall() {
  WallGeometry wall;
  wall.normal_local = Eigen::Vector2d(0.0, 1.0);
  wall.offset_m = 12.0;
  return wall;
}

WallObservation At(double x_m, double y_m, double yaw_rad) {
  WallObservation o;
  o.pose.antenna_local_m = Eigen::Vector2d(x_m, y_m);
  o.pose.yaw_rad = yaw_rad;
  return o;
}

TEST(SiteGeometryTest, LevelSiteIsTheLevelModel) {
  const WallGeometry wall = NorthWall();
  const Mount mount{2.57, 0.056, 2.8 * kDeg};
  for (double yaw_deg : {60.0, 90.0, 125.0}) {
    const WallObservation o = At(1.0, 3.0, yaw_deg * kDeg);
    const Eigen::Vector2d c = LevelCorrection(o, wall, mount, Attitude{}, ScannerPlacement{}, {});
    EXPECT_NEAR(c.x(), 0.0, 1e-12) << yaw_deg;
    EXPECT_NEAR(c.y(), 0.0, 1e-12) << yaw_deg;
  }
}

// A scanner pitched by p facing a vertical wall straight on: its beam plane meets the wall
// d / cos p away along its own x axis (the range stretched by 1 / cos p), whatever its height.
TEST(SiteGeometryTest, PitchedScannerSeesTheWallStretched) {
  const WallGeometry wall = NorthWall();
  const Mount mount{0.0, 0.0, 0.0};
  ScannerPlacement placement;
  placement.pitch_rad = -3.0 * kDeg;
  placement.z_m = -2.5;
  const WallObservation o = At(0.0, 4.0, 90.0 * kDeg);  // facing north, 8 m from the wall
  const Eigen::Vector2d c = LevelCorrection(o, wall, mount, Attitude{}, placement, {});
  EXPECT_NEAR(c.x(), 8.0 / std::cos(3.0 * kDeg) - 8.0, 1e-9);  // 11 mm
  EXPECT_NEAR(c.y(), 0.0, 1e-12);
}

// A vehicle nose up by p with the scanner z below the antenna: the scanner sits −z sin p further
// forward than the level model puts it, and its beam plane is pitched by p.
TEST(SiteGeometryTest, VehiclePitchMovesAScannerBelowTheAntennaForward) {
  const WallGeometry wall = NorthWall();
  const Mount mount{2.0, 0.0, 0.0};
  ScannerPlacement placement;
  placement.z_m = -2.5;
  Attitude attitude;
  attitude.pitch_rad = 1.0 * kDeg;
  const WallObservation o = At(0.0, 0.0, 90.0 * kDeg);
  const Eigen::Vector2d c = LevelCorrection(o, wall, mount, attitude, placement, {});
  // The scanner origin: forward x cos p − z sin p (level: x); range (12 − y) / cos p.
  const double forward = 2.0 * std::cos(1.0 * kDeg) - (-2.5) * std::sin(1.0 * kDeg);
  EXPECT_NEAR(c.x(), (12.0 - forward) / std::cos(1.0 * kDeg) - (12.0 - 2.0), 1e-9);
  EXPECT_LT(c.x(), -0.04);  // 4.4 cm closer: the first-order term
}

// Roll positive right side down: a scanner below the antenna swings to the left (its y grows),
// so facing east with the wall to the north it is closer to the wall.
TEST(SiteGeometryTest, RollRightSideDownSwingsAScannerBelowTheAntennaLeft) {
  const WallGeometry wall = NorthWall();
  ScannerPlacement placement;
  placement.z_m = -2.0;
  Attitude attitude;
  attitude.roll_rad = 2.0 * kDeg;
  const Mount mount{0.0, 0.0, 90.0 * kDeg};  // the scanner looks left, at the wall
  const WallObservation o = At(0.0, 0.0, 0.0);  // the vehicle faces east
  const Eigen::Vector2d c = LevelCorrection(o, wall, mount, attitude, placement, {});
  // Scanner's origin moves to y = −z sin r = +0.0698 m; its beam plane rolls by r about the
  // vehicle's x axis, which is the beam plane's own y axis here: ranges stretch by 1 / cos r.
  const double left = 2.0 * std::sin(2.0 * kDeg);
  EXPECT_NEAR(c.x(), (12.0 - left) / std::cos(2.0 * kDeg) - 12.0, 1e-9);
}

TEST(SiteGeometryTest, VehicleOnAGradeFollowsTheGround) {
  const Eigen::Vector2d grade(0.0, 0.02);  // rising 2 % to the north
  const Attitude uphill = AttitudeOnGround(grade, 90.0 * kDeg);
  EXPECT_NEAR(uphill.pitch_rad, std::atan(0.02), 1e-12);
  EXPECT_NEAR(uphill.roll_rad, 0.0, 1e-12);
  // Facing east the ground rises to the left: the right side is down, roll positive.
  const Attitude across = AttitudeOnGround(grade, 0.0);
  EXPECT_NEAR(across.pitch_rad, 0.0, 1e-12);
  EXPECT_NEAR(across.roll_rad, std::atan(0.02), 1e-12);
  // The vehicle's z axis is the ground's normal at any heading.
  for (double yaw_deg : {-130.0, 20.0, 75.0}) {
    const Attitude a = AttitudeOnGround(grade, yaw_deg * kDeg);
    const Eigen::Vector3d up = VehicleRotation(yaw_deg * kDeg, a).col(2);
    EXPECT_NEAR((up - Eigen::Vector3d(0.0, -0.02, 1.0).normalized()).norm(), 0.0, 1e-12);
  }
}

// A wall leaning by λ (top towards +normal): at a height h above its surveyed trace it stands
// h tan λ further along the normal, so a level beam plane h above meets it that much further.
TEST(SiteGeometryTest, LeaningWallMovesWithTheBeamPlanesHeight) {
  WallGeometry wall = NorthWall();
  wall.lean_rad = 1.0 * kDeg;
  Heights heights;
  heights.antenna_m = 3.0;
  heights.wall_reference_m = 1.5;
  ScannerPlacement placement;
  placement.z_m = -0.5;  // the beam plane 1.0 m above the wall's reference height
  const WallObservation o = At(0.0, 0.0, 90.0 * kDeg);
  const Eigen::Vector2d c = LevelCorrection(o, wall, Mount{}, Attitude{}, placement, heights);
  EXPECT_NEAR(c.x(), 1.0 * std::tan(1.0 * kDeg), 1e-12);
}

TEST(AttitudeModelTest, YardPlaneFromAntennaHeights) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<HeightSample> samples;
  const Eigen::Vector2d grade(0.01, 0.03);
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector2d p(-6.0 + 12.0 * (i % 20) / 19.0, 2.0 + 6.0 * (i / 20) / 19.0);
    samples.push_back({p, 80.0 + grade.dot(p) + noise(rng), 0.5 * i});
  }
  HeightNoise white;
  white.white_sigma_m = 0.01;  // white only: the fit is ordinary least squares
  const YardPlane yard = FitYard(samples, white);
  ASSERT_TRUE(yard.fitted);
  const Eigen::Vector2d sigma = yard.grade_covariance.diagonal().cwiseSqrt();
  EXPECT_NEAR(yard.grade.x(), 0.01, 4.0 * sigma.x());
  EXPECT_NEAR(yard.grade.y(), 0.03, 4.0 * sigma.y());
  EXPECT_LT(sigma.maxCoeff(), 0.002);
  EXPECT_NEAR(yard.residual_rms_m, 0.01, 0.002);
  EXPECT_NEAR(yard.GradePercent(), 100.0 * grade.norm(), 0.5);
  EXPECT_NEAR(yard.RiseDirectionRad(), std::atan2(0.01, 0.03), 0.05);
  // Samples along one line do not make a plane.
  std::vector<HeightSample> line;
  for (int i = 0; i < 50; ++i) line.push_back({Eigen::Vector2d(0.2 * i, 0.0), 80.0, 1.0 * i});
  EXPECT_FALSE(FitYard(line, white).fitted);
}

// A session's antenna heights: ten stations of 4 s at 6 and 10 m from a wall to the north,
// 4 s drives between them, 10 fixes a second; the RTK height wanders (Gauss–Markov, 3 cm,
// τ 60 s) with 6 mm of white noise on top: twice the horizontal noise the fit is told of, as
// RTK heights are. Over many sessions the grade's error over its σ is a unit normal.
std::vector<HeightSample> SessionHeights(const Eigen::Vector2d& grade, std::mt19937* rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  constexpr double kRateHz = 10.0, kTauS = 60.0, kBiasM = 0.03, kWhiteM = 0.006;
  std::vector<Eigen::Vector2d> stations;
  for (int i = 0; i < 10; ++i) stations.emplace_back(-3.0 + 6.0 * i / 9.0, i % 2 ? 6.0 : 10.0);
  std::vector<HeightSample> samples;
  double bias_m = kBiasM * unit(*rng);
  const double phi = std::exp(-1.0 / (kRateHz * kTauS));
  double t_s = 0.0;
  const auto add = [&](const Eigen::Vector2d& p) {
    bias_m = phi * bias_m + kBiasM * std::sqrt(1.0 - phi * phi) * unit(*rng);
    samples.push_back({p, 50.0 + grade.dot(p) + bias_m + kWhiteM * unit(*rng), t_s});
    t_s += 1.0 / kRateHz;
  };
  for (size_t i = 0; i < stations.size(); ++i) {
    for (int k = 0; k < 40; ++k) add(stations[i]);
    if (i + 1 == stations.size()) break;
    for (int k = 0; k < 40; ++k) add(stations[i] + (k / 40.0) * (stations[i + 1] - stations[i]));
  }
  return samples;
}

TEST(AttitudeModelTest, YardGradeSigmaIsHonestUnderAWanderingRtkHeight) {
  std::mt19937 rng(11);
  const Eigen::Vector2d grade(0.005, 0.02);
  HeightNoise assumed;  // the horizontal RTK error's shape: the level is the fit's to find
  assumed.bias_sigma_m = 0.015;
  assumed.bias_tau_s = 60.0;
  assumed.white_sigma_m = 0.003;
  constexpr int kSessions = 300;
  Eigen::Vector2d sum_sq = Eigen::Vector2d::Zero();
  double factor_sum = 0.0;
  for (int k = 0; k < kSessions; ++k) {
    const YardPlane yard = FitYard(SessionHeights(grade, &rng), assumed);
    ASSERT_TRUE(yard.fitted);
    const Eigen::Vector2d error = yard.grade - grade;
    sum_sq += error.cwiseProduct(error).cwiseQuotient(yard.grade_covariance.diagonal());
    factor_sum += yard.noise_factor;
  }
  // RMS(error/σ) over 300 sessions: 1 within about 4 of its standard errors (1/√600 ≈ 4 %);
  // the white noise (twice the assumed) sets the innovations' level.
  const Eigen::Vector2d rms = (sum_sq / kSessions).cwiseSqrt();
  EXPECT_GT(rms.minCoeff(), 0.85) << rms.transpose() << " factor " << factor_sum / kSessions;
  EXPECT_LT(rms.maxCoeff(), 1.18);
  EXPECT_NEAR(factor_sum / kSessions, 2.0, 0.15);
}

TEST(AttitudeModelTest, StreamGivesTheDwellMeanAtAStationAndInterpolatesWhileDriving) {
  std::vector<io::AttitudeSample> samples;
  for (int i = 0; i <= 100; ++i) {
    io::AttitudeSample s;
    s.stamp_s = 0.1 * i;
    s.roll_rad = (i % 2 ? 1.1 : 0.9) * kDeg;
    s.pitch_rad = 0.01 * i * kDeg;
    samples.push_back(s);
  }
  Dwell dwell;
  dwell.start_s = 0.0;
  dwell.end_s = 4.0;
  const AttitudeModel model = AttitudeModel::FromStream(samples, 0.1 * kDeg, {dwell});
  EXPECT_EQ(model.source(), AttitudeSource::kStream);
  WallObservation standing;
  standing.pose.stationary = true;
  standing.pose.segment = 0;
  standing.pose.stamp_s = 1.0;
  double var_roll = 0.0, var_pitch = 0.0;
  const Attitude mean = model.At(standing, 0.0, &var_roll, &var_pitch);
  EXPECT_NEAR(mean.roll_rad, (21 * 0.9 + 20 * 1.1) / 41.0 * kDeg, 1e-12);
  EXPECT_NEAR(var_roll, std::pow(0.1 * kDeg, 2) / 41.0, 1e-15);
  WallObservation moving;
  moving.pose.stamp_s = 7.25;
  const Attitude between = model.At(moving, 0.0, &var_roll, &var_pitch);
  EXPECT_NEAR(between.pitch_rad, 0.725 * kDeg, 1e-12);
  EXPECT_NEAR(var_pitch, std::pow(0.1 * kDeg, 2), 1e-15);
}

}  // namespace
}  // namespace wallcal::calib
