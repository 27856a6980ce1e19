// SPDX-License-Identifier: Apache-2.0
// Tests of the mount adjustment's cost functors: the wall-line cost (hand-worked values, the
// heading delay, offsets and drift, the wall's orientation, Jacobians against numeric and
// automatic differentiation), the Gaussian prior, the Gauss–Markov step, and the observation
// covariance through the lever arm.

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "solvers/information.h"
#include "solvers/mount_problem.h"
#include "solvers/mount_solver.h"
#include "solvers/prior_cost.h"
#include "solvers/wall_line_cost.h"

namespace wallcal::solvers {
namespace {

WallLineMeasurement HandMeasurement() {
  WallLineMeasurement m;
  m.antenna_local_m = Eigen::Vector2d(1.0, 2.0);
  m.vehicle_yaw_rad = 0.5 * kPi;  // facing north
  m.sign = 1.0;
  m.wall_normal_local = Eigen::Vector2d(0.0, 1.0);  // wall y = 10
  m.wall_centre_local_m = Eigen::Vector2d(0.0, 10.0);
  m.wall_normal_angle_rad = 0.5 * kPi;
  m.rho_m = 5.0;
  m.theta_rad = 0.1;
  m.sqrt_information << 100.0, 0.0, 30.0, 500.0;
  return m;
}

// The hand-worked parameters: mount (x, y, yaw) = (2, 0.5, 0.05), wall (δd, δα) = (0.02, 0),
// GNSS bias b = (0.1, −0.2).
const double kHandMount[3] = {2.0, 0.5, 0.05};
const double kHandWall[2] = {0.02, 0.0};
const double kHandBias[2] = {0.1, -0.2};

// The rho error of HandMeasurement() with the vehicle's true yaw `yaw_rad` (the lever arm turns
// with it): s_y = 2.2 + sin(ψ)·2 + cos(ψ)·0.5, rho_pred = 10.02 − s_y, measured 5 m.
double HandRhoError(double yaw_rad) {
  return 10.02 - (2.2 + std::sin(yaw_rad) * 2.0 + std::cos(yaw_rad) * 0.5) - 5.0;
}

// The (rho, theta) errors of `m` at the hand-worked parameters with time offsets (dt, δh), a
// heading offset and a heading drift.
Eigen::Vector2d HandErrors(const WallLineMeasurement& m, const std::array<double, 2>& time_offsets,
                           double heading_offset_rad, double heading_drift_rad_per_s) {
  const double heading_offset[1] = {heading_offset_rad};
  const double heading_drift[1] = {heading_drift_rad_per_s};
  double error[2];
  WallLineCost(m).Errors(kHandMount, kHandWall, kHandBias, time_offsets.data(), heading_offset,
                         heading_drift, error);
  return Eigen::Vector2d(error[0], error[1]);
}

TEST(WallLineCostTest, EvaluatesHandWorkedValue) {
  // mount (x, y, yaw) = (2, 0.5, 0.05); wall (δd, δα) = (0.02, 0); bias b = (0.1, −0.2).
  //   n' = (0, 1), d' = n'·c + δd = 10 + 0.02 = 10.02 (σ = +1)
  //   s = p − b + R(90°)(2, 0.5) = (1 − 0.1, 2 + 0.2) + (−0.5, 2) = (0.4, 4.2)
  //   rho_pred = 10.02 − 4.2 = 5.82            → rho error 5.82 − 5.0 = 0.82 m
  //   theta_pred = π/2 + 0 − π/2 − 0.05 = −0.05 → theta error −0.05 − 0.1 = −0.15 rad
  //   e = W [0.82; −0.15] = [100·0.82; 30·0.82 + 500·(−0.15)] = [82; 24.6 − 75] = [82; −50.4]
  std::unique_ptr<ceres::CostFunction> cost(WallLineCost::Create(HandMeasurement()));
  const double time_offset[2] = {0.0, 0.0};
  const double heading_offset[1] = {0.0};
  const double heading_drift[1] = {0.0};
  const double* parameters[6] = {kHandMount, kHandWall,      kHandBias,
                                 time_offset, heading_offset, heading_drift};
  double residual[2];
  ASSERT_TRUE(cost->Evaluate(parameters, residual, nullptr));
  EXPECT_NEAR(residual[0], 82.0, 1e-9);
  EXPECT_NEAR(residual[1], -50.4, 1e-9);
}

TEST(WallLineCostTest, HeadingDelayTurnsTheYawByRateTimesDelay) {
  // A turning scan (ω = 0.2 rad/s) with the heading stream 0.1 s late: the true yaw is
  // ψ + ω·(dt + δh) = π/2 + 0.02, so theta_pred = π/2 − (π/2 + 0.02) − 0.05 = −0.07 and the
  // theta error −0.17; the same as a clock offset dt = 0.1 would give for the yaw alone.
  WallLineMeasurement m = HandMeasurement();
  m.yaw_rate_rps = 0.2;
  const Eigen::Vector2d error = HandErrors(m, {0.0, 0.1}, 0.0, 0.0);
  EXPECT_NEAR(error[1], -0.17, 1e-12);
  EXPECT_NEAR(error[0], HandRhoError(0.5 * kPi + 0.02), 1e-12);
}

TEST(WallLineCostTest, HeadingOffsetAndDriftTurnTheLeverArmAndTheta) {
  // The same scan with a heading offset h = 0.01 and a drift r = 1e-4 rad/s at τ = 100 s: the
  // true yaw is ψ − h − r·τ = π/2 − 0.02. The lever arm turns with it:
  //   s = (0.9, 2.2) + R(π/2 − 0.02)(2, 0.5),  rho_pred = 10.02 − s_y
  //   theta_pred = π/2 − (π/2 − 0.02) − 0.05 = −0.03 → theta error −0.13
  WallLineMeasurement m = HandMeasurement();
  m.drift_time_s = 100.0;
  const Eigen::Vector2d error = HandErrors(m, {0.0, 0.0}, 0.01, 1e-4);
  EXPECT_NEAR(error[0], HandRhoError(0.5 * kPi - 0.02), 1e-12);
  EXPECT_NEAR(error[1], -0.13, 1e-12);
  // A heading offset and the same drift contribution are one and the same thing.
  const Eigen::Vector2d same = HandErrors(m, {0.0, 0.0}, 0.02, 0.0);
  EXPECT_NEAR(same[0], error[0], 1e-12);
  EXPECT_NEAR(same[1], error[1], 1e-12);
}

TEST(WallLineCostTest, OrientsTheWallTowardsAnAntennaOnItsPositiveSide) {
  // Wall y = 10 seen from the north: antenna (0, 15) facing south (ψ = −90°), σ = −1, so
  // n = (0, −1), d = −10, atan2(n) = −π/2. Mount (2, 0, 0): s = (0, 15) + R(−90°)(2, 0) = (0, 13).
  //   rho_pred = −10 − (−1)(13) = 3, theta_pred = −π/2 − (−π/2) − 0 = 0.
  // Moving the wall north by δd = 0.1 (along the surveyed normal): d = −10.1, rho_pred = 2.9.
  calib::WallGeometry wall;
  wall.normal_local = Eigen::Vector2d(0.0, 1.0);
  wall.offset_m = 10.0;
  wall.end_a_local = Eigen::Vector2d(-5.0, 10.0);
  wall.end_b_local = Eigen::Vector2d(5.0, 10.0);
  const calib::OrientedWall oriented = calib::OrientWall(wall, Eigen::Vector2d(0.0, 15.0));
  EXPECT_EQ(oriented.sign, -1.0);
  EXPECT_NEAR(oriented.normal_angle_rad, -0.5 * kPi, 1e-12);

  WallLineMeasurement m;
  m.antenna_local_m = Eigen::Vector2d(0.0, 15.0);
  m.vehicle_yaw_rad = -0.5 * kPi;
  m.sign = oriented.sign;
  m.wall_normal_local = wall.normal_local;
  m.wall_centre_local_m = Eigen::Vector2d(0.0, 10.0);
  m.wall_normal_angle_rad = oriented.normal_angle_rad;
  m.rho_m = 3.0;
  m.theta_rad = 0.0;
  const WallLineCost cost(m);
  const double mount[3] = {2.0, 0.0, 0.0};
  const double bias[2] = {0.0, 0.0};
  const double still[2] = {0.0, 0.0};
  const double moved[2] = {0.1, 0.0};
  const double no_offset[1] = {0.0};
  const double no_delays[2] = {0.0, 0.0};  // [scanner clock offset, heading delay] (s)
  double error[2];
  cost.Errors(mount, still, bias, no_delays, no_offset, no_offset, error);
  EXPECT_NEAR(error[0], 0.0, 1e-12);
  EXPECT_NEAR(error[1], 0.0, 1e-12);
  cost.Errors(mount, moved, bias, no_delays, no_offset, no_offset, error);
  EXPECT_NEAR(error[0], -0.1, 1e-12);

  calib::WallObservation observation;
  observation.pose.antenna_local_m = m.antenna_local_m;
  observation.pose.yaw_rad = m.vehicle_yaw_rad;
  EXPECT_NEAR(calib::PredictRho(observation, wall, Mount{2.0, 0.0, 0.0}), 3.0, 1e-12);
  EXPECT_NEAR(calib::PredictTheta(observation, wall, Mount{2.0, 0.0, 0.0}), 0.0, 1e-12);
  EXPECT_NEAR(calib::PredictTheta(observation, wall, Mount{2.0, 0.0, 0.3}), -0.3, 1e-12);
}

TEST(WallLineCostTest, JacobiansMatchNumericDifferentiation) {
  WallLineMeasurement m = HandMeasurement();
  m.wall_normal_local = Eigen::Vector2d(0.6, 0.8);
  m.wall_centre_local_m = Eigen::Vector2d(3.0, 9.0);
  m.sign = -1.0;
  m.wall_normal_angle_rad = std::atan2(-0.8, -0.6);
  m.vehicle_yaw_rad = 0.3;
  m.velocity_local_mps = Eigen::Vector2d(0.8, -0.3);
  m.yaw_rate_rps = 0.05;
  std::unique_ptr<ceres::CostFunction> cost(WallLineCost::Create(m));
  ceres::NumericDiffOptions numeric_options;
  const std::vector<const ceres::Manifold*>* euclidean = nullptr;
  ceres::GradientChecker checker(cost.get(), euclidean, numeric_options);
  const double mount[3] = {2.57, 0.056, 0.0489};
  const double wall[2] = {0.013, -0.004};
  const double bias[2] = {0.011, -0.017};
  m.drift_time_s = 250.0;
  const double time_offset[2] = {0.07, -0.03};
  const double heading_offset[1] = {0.003};
  const double heading_drift[1] = {2e-6};
  const double* parameters[6] = {mount, wall, bias, time_offset, heading_offset, heading_drift};
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(parameters, 1e-7, &results)) << results.error_log;
}

TEST(WallLineCostTest, HandWrittenJacobiansMatchAutomaticDifferentiation) {
  // The adjustment's cost (analytic Jacobians) against the same residual differentiated by
  // ceres::Jet, at random points: both orientations of the wall, moving and turning, every
  // nuisance parameter non-zero. Agreement to 1e-9 relative to the row's largest entry (the
  // two differ only by rounding).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    WallLineMeasurement m;
    m.antenna_local_m = Eigen::Vector2d(20.0 * u(rng), 20.0 * u(rng));
    m.vehicle_yaw_rad = kPi * u(rng);
    m.velocity_local_mps = Eigen::Vector2d(u(rng), u(rng));
    m.yaw_rate_rps = 0.2 * u(rng);
    m.drift_time_s = 600.0 * u(rng);
    m.sign = trial % 2 == 0 ? 1.0 : -1.0;
    const double alpha = kPi * u(rng);
    m.wall_normal_local = Eigen::Vector2d(std::cos(alpha), std::sin(alpha));
    m.wall_centre_local_m = Eigen::Vector2d(30.0 * u(rng), 30.0 * u(rng));
    m.wall_normal_angle_rad = std::atan2(m.sign * m.wall_normal_local.y(),
                                         m.sign * m.wall_normal_local.x());
    m.rho_m = 5.0 + 3.0 * u(rng);
    m.theta_rad = u(rng);
    m.sqrt_information << 200.0 * (1.5 + u(rng)), 0.0, 50.0 * u(rng), 400.0 * (1.5 + u(rng));
    const double mount[3] = {2.5 + u(rng), 0.5 * u(rng), 0.1 * u(rng)};
    const double wall[2] = {0.05 * u(rng), 0.01 * u(rng)};
    const double bias[2] = {0.02 * u(rng), 0.02 * u(rng)};
    const double time_offset[2] = {0.1 * u(rng), 0.05 * u(rng)};
    const double heading_offset[1] = {0.005 * u(rng)};
    const double heading_drift[1] = {1e-5 * u(rng)};
    const double* parameters[6] = {mount, wall, bias, time_offset, heading_offset, heading_drift};
    const int sizes[6] = {3, 2, 2, 2, 1, 1};

    std::unique_ptr<ceres::CostFunction> analytic(WallLineCost::Create(m));
    std::unique_ptr<ceres::CostFunction> automatic(WallLineCost::CreateAutoDiff(m));
    double r_analytic[2], r_automatic[2];
    std::vector<std::vector<double>> j_analytic(6), j_automatic(6);
    double* jacobians_analytic[6];
    double* jacobians_automatic[6];
    for (int b = 0; b < 6; ++b) {
      j_analytic[b].assign(2 * sizes[b], 0.0);
      j_automatic[b].assign(2 * sizes[b], 0.0);
      jacobians_analytic[b] = j_analytic[b].data();
      jacobians_automatic[b] = j_automatic[b].data();
    }
    ASSERT_TRUE(analytic->Evaluate(parameters, r_analytic, jacobians_analytic));
    ASSERT_TRUE(automatic->Evaluate(parameters, r_automatic, jacobians_automatic));
    EXPECT_EQ(r_analytic[0], r_automatic[0]) << "trial " << trial;
    EXPECT_EQ(r_analytic[1], r_automatic[1]) << "trial " << trial;
    for (int row = 0; row < 2; ++row) {
      double scale = 0.0;
      for (int b = 0; b < 6; ++b) {
        for (int k = 0; k < sizes[b]; ++k) {
          scale = std::max(scale, std::abs(j_automatic[b][row * sizes[b] + k]));
        }
      }
      for (int b = 0; b < 6; ++b) {
        for (int k = 0; k < sizes[b]; ++k) {
          EXPECT_NEAR(j_analytic[b][row * sizes[b] + k], j_automatic[b][row * sizes[b] + k],
                      1e-9 * scale)
              << "trial " << trial << ", row " << row << ", block " << b << ", column " << k;
        }
      }
    }
    // A null block pointer leaves the others to be filled.
    double* some[6] = {nullptr, j_analytic[1].data(), nullptr, nullptr, nullptr, nullptr};
    EXPECT_TRUE(analytic->Evaluate(parameters, r_analytic, some));
  }
}

TEST(GaussianPriorCostTest, EvaluatesAndDifferentiates) {
  // r = value / σ: (0.01 / 0.005, −0.002 / 0.001) = (2, −2).
  std::unique_ptr<ceres::CostFunction> cost(
      GaussianPriorCost::Create(Eigen::Vector2d(0.005, 0.001)));
  const double value[2] = {0.01, -0.002};
  const double* parameters[1] = {value};
  double residual[2];
  ASSERT_TRUE(cost->Evaluate(parameters, residual, nullptr));
  EXPECT_NEAR(residual[0], 2.0, 1e-12);
  EXPECT_NEAR(residual[1], -2.0, 1e-12);
  ceres::NumericDiffOptions numeric_options;
  const std::vector<const ceres::Manifold*>* euclidean = nullptr;
  ceres::GradientChecker checker(cost.get(), euclidean, numeric_options);
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(parameters, 1e-7, &results)) << results.error_log;
}

TEST(ObservationCovarianceTest, CouplesHeadingNoiseThroughTheLeverArm) {
  // Wall y = 10 ahead of a vehicle facing east (ψ = 0): n = (0, 1). Mount (2.5, 0): the lever
  // R(0)(2.5, 0) = (2.5, 0), turned by 90°: (0, 2.5), ℓ = n·(0, 2.5) = 2.5 m (the lever is
  // parallel to the wall). σ_h = 0.01: heading block 1e-4 [6.25, 2.5; 2.5, 1].
  calib::WallGeometry wall;
  wall.normal_local = Eigen::Vector2d(0.0, 1.0);
  wall.offset_m = 10.0;
  calib::WallObservation observation;
  observation.sigma_rho_m = 0.002;
  observation.sigma_theta_rad = 0.003;
  observation.cov_rho_theta = 1e-6;
  observation.pose.segment = 4;
  solvers::SolverOptions options;
  options.gnss_white_sigma_m = 0.004;
  options.heading_sigma_rad = 0.01;
  const Eigen::Matrix2d covariance =
      ObservationCovariance(observation, wall, options, Mount{2.5, 0.0, 0.0}, 0.02);
  EXPECT_NEAR(covariance(0, 0), 4e-6 + 16e-6 + 6.25e-4, 1e-15);
  EXPECT_NEAR(covariance(0, 1), 1e-6 + 2.5e-4, 1e-15);
  EXPECT_NEAR(covariance(1, 0), 1e-6 + 2.5e-4, 1e-15);
  EXPECT_NEAR(covariance(1, 1), 9e-6 + 1e-4, 1e-15);
  // Without a segment, the bias σ (0.02 m) joins the white part of rho.
  observation.pose.segment = -1;
  EXPECT_NEAR(ObservationCovariance(observation, wall, options, Mount{2.5, 0.0, 0.0}, 0.02)(0, 0),
              4e-6 + 16e-6 + 6.25e-4 + 4e-4, 1e-15);
  // At a station the scan uses the dwell's mean heading: its error is the dwell's heading
  // offset parameter, not white noise of this scan, so no heading term.
  observation.pose.segment = 4;
  observation.pose.stationary = true;
  const Eigen::Matrix2d at_station =
      ObservationCovariance(observation, wall, options, Mount{2.5, 0.0, 0.0}, 0.02);
  EXPECT_NEAR(at_station(0, 0), 4e-6 + 16e-6, 1e-15);
  EXPECT_NEAR(at_station(0, 1), 1e-6, 1e-15);
  EXPECT_NEAR(at_station(1, 1), 9e-6, 1e-15);
}

TEST(GaussMarkovStepCostTest, EvaluatesAndDifferentiates) {
  std::unique_ptr<ceres::CostFunction> cost(GaussMarkovStepCost::Create(0.5, 0.02));
  const double previous[2] = {0.02, -0.01};
  const double next[2] = {0.03, 0.01};
  const double* parameters[2] = {previous, next};
  double residual[2];
  double d_previous[4], d_next[4];
  double* jacobians[2] = {d_previous, d_next};
  ASSERT_TRUE(cost->Evaluate(parameters, residual, jacobians));
  EXPECT_NEAR(residual[0], (0.03 - 0.01) / 0.02, 1e-12);
  EXPECT_NEAR(residual[1], (0.01 + 0.005) / 0.02, 1e-12);
  EXPECT_NEAR(d_previous[0], -0.5 / 0.02, 1e-9);
  EXPECT_NEAR(d_next[3], 1.0 / 0.02, 1e-9);
  EXPECT_NEAR(d_next[1], 0.0, 1e-12);
}

}  // namespace
}  // namespace wallcal::solvers
