// SPDX-License-Identifier: Apache-2.0
#include "solvers/unit_range_cost.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <utility>
#include <vector>

namespace wallcal::solvers {
namespace {

constexpr int kMount = 0;  // the wrapped cost's mount block [x, y, yaw]
constexpr int kWall = 1;   // and its wall block [δd, δα]
// The wrapped cost's blocks at most (an EpochNoiseCost has 14).
constexpr size_t kMaxBlocks = 16;

}  // namespace

UnitRangeCost::UnitRangeCost(std::unique_ptr<ceres::CostFunction> scan, double sign,
                             double drho_db, double dtheta_db, double rho_m)
    : scan_(std::move(scan)), sign_(sign), drho_db_(drho_db), dtheta_db_(dtheta_db), rho_m_(rho_m) {
  set_num_residuals(scan_->num_residuals());
  std::vector<int32_t>* sizes = mutable_parameter_block_sizes();
  *sizes = scan_->parameter_block_sizes();
  sizes->push_back(2);
  if (scan_->parameter_block_sizes().size() > kMaxBlocks) {
    throw std::logic_error("UnitRangeCost: the wrapped cost has more blocks than it holds");
  }
}

bool UnitRangeCost::Evaluate(double const* const* parameters, double* residuals,
                             double** jacobians) const {
  const int blocks = static_cast<int>(scan_->parameter_block_sizes().size());
  const double* unit = parameters[blocks];
  const double g_rho_m = drho_db_ * unit[0] + rho_m_ * unit[1];
  const double g_theta_rad = dtheta_db_ * unit[0];
  const double mount[3] = {parameters[kMount][0], parameters[kMount][1],
                           parameters[kMount][2] - g_theta_rad};
  const double wall[2] = {parameters[kWall][0] + sign_ * g_rho_m, parameters[kWall][1]};
  // Evaluated for every scan at every iteration: no allocation but the rare scratch below.
  std::array<const double*, kMaxBlocks> inner{};
  std::copy(parameters, parameters + blocks, inner.begin());
  inner[kMount] = mount;
  inner[kWall] = wall;
  if (jacobians == nullptr) return scan_->Evaluate(inner.data(), residuals, nullptr);

  const int rows = num_residuals();
  double* unit_jacobian = jacobians[blocks];
  // The mount's and wall's Jacobians are needed for u's as well: the caller's when it asks
  // for them (the solver does whenever both are free), else scratch.
  std::vector<double> mount_scratch, wall_scratch;
  std::array<double*, kMaxBlocks> inner_jacobians{};
  std::copy(jacobians, jacobians + blocks, inner_jacobians.begin());
  if (unit_jacobian != nullptr && inner_jacobians[kMount] == nullptr) {
    mount_scratch.resize(static_cast<size_t>(rows) * 3);
    inner_jacobians[kMount] = mount_scratch.data();
  }
  if (unit_jacobian != nullptr && inner_jacobians[kWall] == nullptr) {
    wall_scratch.resize(static_cast<size_t>(rows) * 2);
    inner_jacobians[kWall] = wall_scratch.data();
  }
  if (!scan_->Evaluate(inner.data(), residuals, inner_jacobians.data())) return false;
  if (unit_jacobian == nullptr) return true;
  const double* d_mount = inner_jacobians[kMount];  // rows × 3, row-major
  const double* d_wall = inner_jacobians[kWall];    // rows × 2
  for (int r = 0; r < rows; ++r) {
    const double d_yaw = d_mount[3 * r + 2];
    const double d_shift = d_wall[2 * r + 0];
    unit_jacobian[2 * r + 0] = d_shift * sign_ * drho_db_ - d_yaw * dtheta_db_;
    unit_jacobian[2 * r + 1] = d_shift * sign_ * rho_m_;
  }
  return true;
}

}  // namespace wallcal::solvers
