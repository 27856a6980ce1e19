// SPDX-License-Identifier: Apache-2.0
// A scan with its unit's range model as a parameter (solvers/unit_range_cost.h): its residual is
// the wrapped scan's with the model's effect (rho by drho_db·δb + rho·δk, theta by
// dtheta_db·δb) taken off the measured line, and the Jacobian of [δb, δk] is that by the chain
// rule, under the robust loss too.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "common/angles.h"
#include "solvers/unit_range_cost.h"
#include "solvers/wall_line_cost.h"
#include "solvers/wall_slice_cost.h"

namespace wallcal::solvers {
namespace {

// One standing scan 5.3 m from a wall along the local x axis, seen from its negative side.
WallLineMeasurement OneScan(double sign) {
  WallLineMeasurement m;
  m.antenna_local_m = Eigen::Vector2d(1.0, 2.0);
  m.vehicle_yaw_rad = 0.5 * kPi + 0.1;
  m.wall_normal_local = Eigen::Vector2d(0.0, 1.0);
  m.wall_centre_local_m = Eigen::Vector2d(0.0, 10.0);
  m.sign = sign;
  m.wall_normal_angle_rad = sign > 0.0 ? 0.5 * kPi : -0.5 * kPi;
  m.sqrt_information << 300.0, 0.0, 20.0, 400.0;
  m.rho_m = 5.3;
  m.theta_rad = -0.15;
  return m;
}

constexpr double kDrhoDb = 0.93, kDthetaDb = -0.004, kHuber = 1.5;

// Evaluates the wrapped cost at [δb, δk] = unit with every other block at fixed values.
struct Fixture {
  std::vector<WallLineMeasurement> scans;
  std::array<double, 3> mount{2.5, 0.06, 0.05};
  std::array<double, 2> wall{0.01, -0.002};
  std::array<double, 2> bias{0.004, -0.007};
  std::array<double, 2> time{0.0, 0.0};
  std::array<double, 1> heading{0.001};
  std::array<double, 1> drift{0.0};
  explicit Fixture(double sign) : scans{OneScan(sign)} {}
  std::vector<const double*> Blocks(const double* unit) const {
    return {mount.data(), wall.data(), bias.data(), time.data(), heading.data(), drift.data(), unit};
  }
};

TEST(UnitRangeCostTest, IsTheScanWithItsLineMovedByTheUnitsModel) {
  for (double sign : {1.0, -1.0}) {
    Fixture f(sign);
    const double unit[2] = {0.012, 4e-4};
    UnitRangeCost cost(std::make_unique<WallSliceCost>(f.scans, std::vector<int>{0}, kHuber),
                       f.scans[0].sign, kDrhoDb, kDthetaDb, f.scans[0].rho_m);
    ASSERT_EQ(cost.parameter_block_sizes().size(), 7u);
    std::vector<double> residuals(cost.num_residuals());
    ASSERT_TRUE(cost.Evaluate(f.Blocks(unit).data(), residuals.data(), nullptr));

    // The same scan with the model's effect taken off its measured line.
    std::vector<WallLineMeasurement> moved = f.scans;
    moved[0].rho_m -= kDrhoDb * unit[0] + f.scans[0].rho_m * unit[1];
    moved[0].theta_rad -= kDthetaDb * unit[0];
    WallSliceCost plain(moved, {0}, kHuber);
    std::vector<double> expected(plain.num_residuals());
    ASSERT_TRUE(plain.Evaluate(f.Blocks(unit).data(), expected.data(), nullptr));
    for (size_t r = 0; r < expected.size(); ++r) {
      EXPECT_NEAR(residuals[r], expected[r], 1e-9 * (1.0 + std::abs(expected[r]))) << sign << r;
    }
  }
}

// The unit's Jacobian over [δb, δk] at `unit`, with residuals, from a cost of huber scale `k`.
struct Evaluated {
  std::vector<double> residuals, jacobian;
};
Evaluated EvaluateAt(const Fixture& f, const double* unit, double huber, bool mount_too) {
  UnitRangeCost cost(std::make_unique<WallSliceCost>(f.scans, std::vector<int>{0}, huber),
                     f.scans[0].sign, kDrhoDb, kDthetaDb, f.scans[0].rho_m);
  const int rows = cost.num_residuals();
  Evaluated out{std::vector<double>(rows), std::vector<double>(rows * 2)};
  std::vector<double> jac_mount(rows * 3);
  std::vector<double*> jacobians(7, nullptr);
  if (mount_too) jacobians[0] = jac_mount.data();
  jacobians[6] = out.jacobian.data();
  EXPECT_TRUE(cost.Evaluate(f.Blocks(unit).data(), out.residuals.data(), jacobians.data()));
  return out;
}

TEST(UnitRangeCostTest, UnitJacobianIsTheMovedLinesByTheChainRule) {
  for (double sign : {1.0, -1.0}) {
    const Fixture f(sign);
    const double unit[2] = {0.002, 3e-4};
    // Without the loss, against central differences.
    const Evaluated plain = EvaluateAt(f, unit, 0.0, true);
    EXPECT_EQ(plain.jacobian, EvaluateAt(f, unit, 0.0, false).jacobian);  // asked alone: same
    const double steps[2] = {1e-7, 1e-9};
    for (int c = 0; c < 2; ++c) {
      double up[2] = {unit[0], unit[1]}, down[2] = {unit[0], unit[1]};
      up[c] += steps[c];
      down[c] -= steps[c];
      const Evaluated a = EvaluateAt(f, up, 0.0, false), b = EvaluateAt(f, down, 0.0, false);
      for (int r = 0; r < 2; ++r) {
        const double numeric = (a.residuals[r] - b.residuals[r]) / (2.0 * steps[c]);
        EXPECT_NEAR(plain.jacobian[2 * r + c], numeric, 1e-5 * (1.0 + std::abs(numeric)))
            << sign << " row " << r << " col " << c;
      }
      EXPECT_EQ(plain.jacobian[4 + c], 0.0);  // the loss's top-up row
    }
    // 40 mm of offset is tens of σ, past the loss's corner: the rows are the plain ones scaled
    // by √ρ′, as WallSliceCost scales its own (the residuals' ratio).
    const double far[2] = {0.04, 3e-4};
    const Evaluated robust = EvaluateAt(f, far, kHuber, true);
    const Evaluated unrobust = EvaluateAt(f, far, 0.0, true);
    const double scale = robust.residuals[0] / unrobust.residuals[0];
    ASSERT_LT(scale, 0.9);
    for (int k = 0; k < 4; ++k) {
      EXPECT_NEAR(robust.jacobian[k], scale * unrobust.jacobian[k],
                  1e-9 * (1.0 + std::abs(unrobust.jacobian[k])))
          << sign << " " << k;
    }
  }
}

}  // namespace
}  // namespace wallcal::solvers
