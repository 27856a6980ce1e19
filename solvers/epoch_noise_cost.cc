// SPDX-License-Identifier: Apache-2.0
#include "solvers/epoch_noise_cost.h"

#include <utility>
#include <vector>

namespace wallcal::solvers {
namespace {

constexpr int kBias = 2;      // the wrapped cost's bias block
constexpr int kHeading = 4;   // and its heading-offset block
constexpr int kFixA = 6;      // the white errors of the fixes before and after
constexpr int kFixB = 7;
constexpr int kSampleA = 8;   // and of the heading samples before and after
constexpr int kSampleB = 9;

}  // namespace

EpochNoiseCost::EpochNoiseCost(std::unique_ptr<WallSliceCost> scan, double fix_fraction,
                               double heading_fraction)
    : scan_(std::move(scan)), fix_fraction_(fix_fraction), heading_fraction_(heading_fraction) {
  set_num_residuals(scan_->num_residuals());
  std::vector<int32_t>* sizes = mutable_parameter_block_sizes();
  *sizes = scan_->parameter_block_sizes();
  sizes->insert(sizes->end(), {2, 2, 1, 1});
}

bool EpochNoiseCost::Evaluate(double const* const* parameters, double* residuals,
                              double** jacobians) const {
  const double f = fix_fraction_, g = heading_fraction_;
  const double* w_a = parameters[kFixA];
  const double* w_b = parameters[kFixB];
  const double bias[2] = {parameters[kBias][0] + (1.0 - f) * w_a[0] + f * w_b[0],
                          parameters[kBias][1] + (1.0 - f) * w_a[1] + f * w_b[1]};
  const double heading[1] = {parameters[kHeading][0] + (1.0 - g) * parameters[kSampleA][0] +
                             g * parameters[kSampleB][0]};
  const double* inner[6] = {parameters[0], parameters[1], bias,
                            parameters[3], heading,       parameters[5]};
  if (jacobians == nullptr) return scan_->Evaluate(inner, residuals, nullptr);

  const int rows = num_residuals();
  // The bias and heading Jacobians are needed for the white errors' blocks as well.
  std::vector<double> bias_jacobian(static_cast<size_t>(rows) * 2);
  std::vector<double> heading_jacobian(static_cast<size_t>(rows));
  double* inner_jacobians[6] = {jacobians[0], jacobians[1], bias_jacobian.data(),
                                jacobians[3], heading_jacobian.data(), jacobians[5]};
  if (!scan_->Evaluate(inner, residuals, inner_jacobians)) return false;
  const auto scatter = [](const std::vector<double>& from, double scale, double* to) {
    if (to == nullptr) return;
    for (size_t k = 0; k < from.size(); ++k) to[k] = scale * from[k];
  };
  scatter(bias_jacobian, 1.0, jacobians[kBias]);
  scatter(heading_jacobian, 1.0, jacobians[kHeading]);
  scatter(bias_jacobian, 1.0 - f, jacobians[kFixA]);
  scatter(bias_jacobian, f, jacobians[kFixB]);
  scatter(heading_jacobian, 1.0 - g, jacobians[kSampleA]);
  scatter(heading_jacobian, g, jacobians[kSampleB]);
  return true;
}

}  // namespace wallcal::solvers
