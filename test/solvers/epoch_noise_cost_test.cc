// SPDX-License-Identifier: Apache-2.0
// The scan whose pose carries its fixes' and heading samples' white noise as parameters
// (solvers/epoch_noise_cost.h): its residual is the wrapped scan's at the bias and heading
// offset plus the white errors weighted as the interpolation weighted their samples (four per
// stream: a cubic's), and its Jacobians are the scan's (automatic differentiation) by the
// chain rule.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "common/angles.h"
#include "solvers/epoch_noise_cost.h"
#include "solvers/wall_line_cost.h"
#include "solvers/wall_slice_cost.h"

namespace wallcal::solvers {
namespace {

// One moving scan 8 m in front of a wall along the local x axis.
std::vector<WallLineMeasurement> OneScan() {
  WallLineMeasurement m;
  m.antenna_local_m = Eigen::Vector2d(1.0, 2.0);
  m.vehicle_yaw_rad = 0.5 * kPi + 0.1;
  m.velocity_local_mps = Eigen::Vector2d(0.2, 0.5);
  m.yaw_rate_rps = 0.05;
  m.drift_time_s = 30.0;
  m.wall_normal_local = Eigen::Vector2d(0.0, 1.0);
  m.wall_centre_local_m = Eigen::Vector2d(0.0, 10.0);
  m.wall_normal_angle_rad = 0.5 * kPi;
  m.sqrt_information << 300.0, 0.0, 20.0, 400.0;
  m.rho_m = 5.3;
  m.theta_rad = -0.15;
  return {m};
}

struct Values {
  std::array<double, 3> mount{2.5, 0.06, 0.05};
  std::array<double, 2> wall{0.01, -0.002};
  std::array<double, 2> bias{0.004, -0.007};
  std::array<double, 2> time{0.02, -0.01};
  std::array<double, 1> heading{0.001};
  std::array<double, 1> drift{2e-4};
  std::array<std::array<double, 2>, 4> fixes{{{0.001, -0.002}, {0.003, 0.002}, {-0.001, 0.004},
                                               {0.002, 0.001}}};
  std::array<std::array<double, 1>, 4> samples{{{0.0003}, {0.0008}, {-0.0004}, {-0.0002}}};
  std::vector<const double*> All() const {
    std::vector<const double*> all = {mount.data(), wall.data(),    bias.data(),
                                      time.data(),  heading.data(), drift.data()};
    for (const auto& f : fixes) all.push_back(f.data());
    for (const auto& h : samples) all.push_back(h.data());
    return all;
  }
};

// Hermite weights at a quarter of the way (fixes) and a linear interpolation at 0.6 (samples).
constexpr std::array<double, 4> kFixWeights = {-0.0703125, 0.8671875, 0.2265625, -0.0234375};
constexpr std::array<double, 4> kSampleWeights = {0.0, 0.4, 0.6, 0.0};

TEST(EpochNoiseCostTest, IsTheScanAtTheBiasAndHeadingPlusTheInterpolatedWhiteErrors) {
  const std::vector<WallLineMeasurement> scans = OneScan();
  const Values v;
  EpochNoiseCost cost(std::make_unique<WallSliceCost>(scans, std::vector<int>{0}, 0.0),
                      kFixWeights, kSampleWeights);
  ASSERT_EQ(cost.parameter_block_sizes().size(), 14u);
  std::vector<double> residuals(cost.num_residuals());
  ASSERT_TRUE(cost.Evaluate(v.All().data(), residuals.data(), nullptr));

  // By hand: b + Σ u_j w_j = (0.004 − 0.0000703125 + 0.0026015625 − 0.0002265625 − 0.000046875,
  // −0.007 + 0.000140625 + 0.001734375 + 0.00090625 − 0.0000234375); h + Σ v_j η_j =
  // 0.001 + 0.00032 − 0.00024.
  const double bias[2] = {0.0062578125, -0.0042421875};
  const double heading[1] = {0.00108};
  const double* at[6] = {v.mount.data(), v.wall.data(), bias,
                         v.time.data(),  heading,       v.drift.data()};
  WallSliceCost plain(scans, {0}, 0.0);
  std::vector<double> expected(plain.num_residuals());
  ASSERT_TRUE(plain.Evaluate(at, expected.data(), nullptr));
  ASSERT_EQ(residuals.size(), expected.size());
  for (size_t k = 0; k < expected.size(); ++k) {
    EXPECT_NEAR(residuals[k], expected[k], 1e-9 * (1.0 + std::abs(expected[k]))) << k;
  }
  // The white errors move the residual: the same bias without them gives another one.
  const double* without[6] = {v.mount.data(), v.wall.data(),    v.bias.data(),
                              v.time.data(),  v.heading.data(), v.drift.data()};
  std::vector<double> other(plain.num_residuals());
  ASSERT_TRUE(plain.Evaluate(without, other.data(), nullptr));
  EXPECT_GT(std::abs(other[0] - expected[0]), 0.1);
}

TEST(EpochNoiseCostTest, JacobiansAreTheScansByTheChainRule) {
  const std::vector<WallLineMeasurement> scans = OneScan();
  const Values v;
  EpochNoiseCost cost(std::make_unique<WallSliceCost>(scans, std::vector<int>{0}, 0.0),
                      kFixWeights, kSampleWeights);
  const int rows = cost.num_residuals();
  const std::vector<int> sizes = {3, 2, 2, 2, 1, 1, 2, 2, 2, 2, 1, 1, 1, 1};
  std::vector<std::vector<double>> j(14);
  std::vector<double*> jp(14);
  for (int b = 0; b < 14; ++b) {
    j[b].assign(static_cast<size_t>(rows * sizes[b]), 0.0);
    jp[b] = j[b].data();
  }
  std::vector<double> residuals(rows);
  ASSERT_TRUE(cost.Evaluate(v.All().data(), residuals.data(), jp.data()));
  // The wrapped scan at the effective bias and heading (as in the test above), by automatic
  // differentiation.
  const double bias[2] = {0.0062578125, -0.0042421875};
  const double heading[1] = {0.00108};
  const double* at[6] = {v.mount.data(), v.wall.data(), bias,
                         v.time.data(),  heading,       v.drift.data()};
  std::unique_ptr<ceres::CostFunction> scan(WallLineCost::CreateAutoDiff(scans[0]));
  double expected[6][6];
  double* ep[6] = {expected[0], expected[1], expected[2], expected[3], expected[4], expected[5]};
  double r[2];
  ASSERT_TRUE(scan->Evaluate(at, r, ep));
  const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-9 * (1.0 + std::abs(b)); };
  for (int b = 0; b < 6; ++b) {
    for (int k = 0; k < 2 * sizes[b]; ++k) EXPECT_TRUE(near(j[b][k], expected[b][k])) << b << " " << k;
  }
  // The white errors' columns: the bias's and heading's, times the interpolation weights.
  for (int f = 0; f < 4; ++f) {
    for (int k = 0; k < 4; ++k) {
      EXPECT_TRUE(near(j[6 + f][k], kFixWeights[f] * expected[2][k])) << f << " " << k;
    }
    for (int k = 0; k < 2; ++k) {
      EXPECT_TRUE(near(j[10 + f][k], kSampleWeights[f] * expected[4][k])) << f << " " << k;
    }
  }
}

}  // namespace
}  // namespace wallcal::solvers
