// SPDX-License-Identifier: Apache-2.0
// One residual block per GNSS-error slice (solvers/wall_slice_cost.h) against one block per
// scan with ceres::HuberLoss, the form it replaced: the same cost, the same gradient and the
// same Gauss–Newton matrix (Ceres's loss-corrected JᵀJ), with scans in both regions of the
// loss; and without a loss, plain least squares.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "common/angles.h"
#include "solvers/wall_line_cost.h"
#include "solvers/wall_slice_cost.h"

namespace wallcal::solvers {
namespace {

struct Blocks {
  std::array<double, 3> mount{2.5, 0.06, 0.05};
  std::array<double, 2> wall{0.01, -0.002};
  std::array<double, 2> bias{0.004, -0.007};
  std::array<double, 2> time{0.02, -0.01};
  std::array<double, 1> heading{0.001};
  std::array<double, 1> drift{1e-6};
};

// Scans of one wall from one slice, with measured rho off the prediction by a few σ for some
// (the loss's linear region) and by less than its scale for the others.
// With `standing`, the scans of one station's dwell: one heading and drift time, no motion; the
// antenna positions differ by the GNSS noise (so the wall-angle lever differs from scan to scan).
std::vector<WallLineMeasurement> Scans(int count, const Blocks& at, std::mt19937* rng,
                                       bool standing = false) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<WallLineMeasurement> scans;
  for (int i = 0; i < count; ++i) {
    WallLineMeasurement m;
    m.antenna_local_m = Eigen::Vector2d(1.0 + 0.01 * u(*rng), 2.0 + 0.01 * u(*rng));
    m.vehicle_yaw_rad = 0.5 * kPi + 0.2 * u(*rng);
    m.velocity_local_mps = Eigen::Vector2d(0.3 * u(*rng), 0.3 * u(*rng));
    m.yaw_rate_rps = 0.1 * u(*rng);
    m.drift_time_s = 100.0 + i;
    if (standing) {
      m.vehicle_yaw_rad = 0.5 * kPi + 0.1;
      m.velocity_local_mps.setZero();
      m.yaw_rate_rps = 0.0;
      m.drift_time_s = 100.0;
    }
    m.wall_normal_local = Eigen::Vector2d(0.0, 1.0);
    m.wall_centre_local_m = Eigen::Vector2d(0.0, 10.0);
    m.wall_normal_angle_rad = 0.5 * kPi;
    m.sqrt_information << 300.0, 0.0, 20.0, 400.0;
    // Measured = predicted at `at` + an error: 3 to 10 σ in rho for every third scan, within
    // half a σ otherwise.
    double predicted[2];
    WallLineCost(m).Errors(at.mount.data(), at.wall.data(), at.bias.data(), at.time.data(),
                           at.heading.data(), at.drift.data(), predicted);
    const double sigma_rho_m = 1.0 / 300.0;
    const double off = i % 3 == 0 ? (3.0 + 7.0 * std::abs(u(*rng))) * (u(*rng) < 0 ? -1 : 1)
                                  : 0.5 * u(*rng);
    m.rho_m = predicted[0] + off * sigma_rho_m;
    m.theta_rad = predicted[1] + 0.001 * u(*rng);
    scans.push_back(m);
  }
  return scans;
}

struct Evaluated {
  double cost = 0.0;
  std::vector<double> gradient;
  Eigen::MatrixXd normal;
};

Evaluated Evaluate(ceres::Problem& problem, Blocks& b) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = {b.mount.data(), b.wall.data(), b.bias.data(),
                              b.time.data(),  b.heading.data(), b.drift.data()};
  Evaluated out;
  ceres::CRSMatrix crs;
  EXPECT_TRUE(problem.Evaluate(options, &out.cost, nullptr, &out.gradient, &crs));
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r) {
    for (int k = crs.rows[r]; k < crs.rows[r + 1]; ++k) j(r, crs.cols[k]) = crs.values[k];
  }
  out.normal = j.transpose() * j;
  return out;
}

// The slice form's cost, gradient and Gauss–Newton matrix (b) against the reference (a).
void ExpectAgree(const Evaluated& a, const Evaluated& b, double tolerance) {
  EXPECT_NEAR(b.cost, a.cost, tolerance * a.cost);
  ASSERT_EQ(a.gradient.size(), b.gradient.size());
  double scale = 0.0;
  for (double g : a.gradient) scale = std::max(scale, std::abs(g));
  for (size_t k = 0; k < a.gradient.size(); ++k) {
    EXPECT_NEAR(b.gradient[k], a.gradient[k], tolerance * scale) << "coordinate " << k;
  }
  EXPECT_LE((b.normal - a.normal).cwiseAbs().maxCoeff(),
            tolerance * a.normal.cwiseAbs().maxCoeff());
}

// All of `scans` as one WallSliceCost block of `problem`, on `blocks`.
WallSliceCost* AddSlice(const std::vector<WallLineMeasurement>& scans, double huber_scale,
                        Blocks& blocks, ceres::Problem* problem) {
  std::vector<int> all(scans.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  auto* cost = new WallSliceCost(scans, all, huber_scale);
  problem->AddResidualBlock(cost, nullptr, blocks.mount.data(), blocks.wall.data(),
                            blocks.bias.data(), blocks.time.data(), blocks.heading.data(),
                            blocks.drift.data());
  return cost;
}

// The slice (the form under test) against the reference: each scan of Scans(19) its own
// WallLineCost block, `weight` times over, with a Huber loss of `huber_scale` (0: none). The
// slice takes each scan once as an observation standing for `weight` scans (W carries
// √weight): the loss applies per scan, not to the weighted residual. Same cost, gradient and
// normal matrix within `tolerance`. both_regions: at least 4 scans on each side of the loss's
// corner.
void ExpectSliceIsPerScanBlocks(double huber_scale, int weight, bool both_regions, bool standing,
                                double tolerance, unsigned seed) {
  std::mt19937 rng(seed);
  Blocks per_scan_blocks, slice_blocks;
  const std::vector<WallLineMeasurement> scans = Scans(19, per_scan_blocks, &rng, standing);
  ceres::Problem per_scan;
  ceres::LossFunction* loss = huber_scale > 0.0 ? new ceres::HuberLoss(huber_scale) : nullptr;
  int beyond = 0;
  std::vector<WallLineMeasurement> weighted = scans;
  for (size_t i = 0; i < scans.size(); ++i) {
    double r[2];
    const double* p[6] = {per_scan_blocks.mount.data(), per_scan_blocks.wall.data(),
                          per_scan_blocks.bias.data(),  per_scan_blocks.time.data(),
                          per_scan_blocks.heading.data(), per_scan_blocks.drift.data()};
    EvaluateWallLine(scans[i], p, r, nullptr);
    // Beyond the corner per scan, though a weighted residual of scans within it may not be.
    if (std::hypot(r[0], r[1]) > huber_scale) ++beyond;
    for (int c = 0; c < weight; ++c) {
      per_scan.AddResidualBlock(WallLineCost::Create(scans[i]), loss,
                                per_scan_blocks.mount.data(), per_scan_blocks.wall.data(),
                                per_scan_blocks.bias.data(), per_scan_blocks.time.data(),
                                per_scan_blocks.heading.data(), per_scan_blocks.drift.data());
    }
    weighted[i].sqrt_information *= std::sqrt(static_cast<double>(weight));
    weighted[i].weight = weight;
  }
  if (both_regions) {  // both regions of the loss are exercised
    ASSERT_GE(beyond, 4);
    ASSERT_LE(beyond, static_cast<int>(scans.size()) - 4);
  }
  ceres::Problem slice;
  ASSERT_EQ(AddSlice(weighted, huber_scale, slice_blocks, &slice)->compressed(), standing);
  ExpectAgree(Evaluate(per_scan, per_scan_blocks), Evaluate(slice, slice_blocks), tolerance);
}

// One block per scan against the slice, observations of weight 1 (seed 11).
void ExpectSame(double huber_scale, bool both_regions, bool standing = false,
                double tolerance = 1e-12) {
  ExpectSliceIsPerScanBlocks(huber_scale, 1, both_regions, standing, tolerance, 11);
}

TEST(WallSliceCostTest, SameCostGradientAndNormalMatrixAsOneHuberBlockPerScan) {
  ExpectSame(2.0, true);
}

TEST(WallSliceCostTest, WithoutALossIsPlainLeastSquares) {
  // huber_scale 0: no loss in either form.
  ExpectSame(0.0, false);
}

// A dwell's scans come back as four residuals (QR of their rows): the same cost, gradient and
// Gauss–Newton matrix up to rounding (1e-10 of the largest entry: Givens rotations over 38 rows
// of entries up to 1e5 against sums of their squares).
TEST(WallSliceCostTest, StandingScansCompressedToFourResidualsKeepCostGradientAndNormalMatrix) {
  ExpectSame(2.0, true, /*standing=*/true, 1e-10);
  ExpectSame(0.0, false, /*standing=*/true, 1e-10);
}

TEST(WallSliceCostTest, CompressedOnlyWhenEveryScanSharesTheRows) {
  std::mt19937 rng(3);
  Blocks blocks;
  const std::vector<WallLineMeasurement> scans = Scans(5, blocks, &rng, /*standing=*/true);
  const std::vector<int> all = {0, 1, 2, 3, 4};
  EXPECT_TRUE(WallSliceCost(scans, all, 2.0).compressed());
  EXPECT_EQ(WallSliceCost(scans, all, 2.0).num_residuals(), WallSliceCost::kCompressedResiduals);
  EXPECT_FALSE(WallSliceCost(scans, {2}, 2.0).compressed());  // one scan: its own two rows
  std::vector<WallLineMeasurement> turning = scans;
  turning[3].yaw_rate_rps = 0.01;
  EXPECT_FALSE(WallSliceCost(turning, all, 2.0).compressed());
  std::vector<WallLineMeasurement> other_side = scans;
  other_side[1].sign = -other_side[1].sign;
  EXPECT_FALSE(WallSliceCost(other_side, all, 2.0).compressed());
  std::vector<WallLineMeasurement> other_heading = scans;
  other_heading[4].vehicle_yaw_rad += 1e-9;
  EXPECT_FALSE(WallSliceCost(other_heading, all, 2.0).compressed());
}

// A re-solve's observation standing for 3 scans (W carries √3) against 3 copies of it, one
// Huber block each: the loss applies per scan, not to the weighted residual. In both forms.
TEST(WallSliceCostTest, AnObservationOfWeightWIsWScansEachWithItsOwnLoss) {
  ExpectSliceIsPerScanBlocks(2.0, 3, true, /*standing=*/false, 1e-12, 5);
  ExpectSliceIsPerScanBlocks(2.0, 3, true, /*standing=*/true, 1e-10, 5);
}

}  // namespace
}  // namespace wallcal::solvers
