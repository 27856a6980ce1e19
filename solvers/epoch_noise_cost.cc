// SPDX-License-Identifier: Apache-2.0
#include "solvers/epoch_noise_cost.h"

#include <utility>
#include <vector>

namespace wallcal::solvers {
namespace {

constexpr int kBias = 2;     // the wrapped cost's bias block
constexpr int kFixA = 6;     // the white errors of the fixes before and after
constexpr int kFixB = 7;

}  // namespace

EpochNoiseCost::EpochNoiseCost(std::unique_ptr<WallSliceCost> scan, double fix_fraction)
    : scan_(std::move(scan)), fix_fraction_(fix_fraction) {
  set_num_residuals(scan_->num_residuals());
  std::vector<int32_t>* sizes = mutable_parameter_block_sizes();
  *sizes = scan_->parameter_block_sizes();
  sizes->insert(sizes->end(), {2, 2});
}

bool EpochNoiseCost::Evaluate(double const* const* parameters, double* residuals,
                              double** jacobians) const {
  const double f = fix_fraction_;
  const double* w_a = parameters[kFixA];
  const double* w_b = parameters[kFixB];
  const double bias[2] = {parameters[kBias][0] + (1.0 - f) * w_a[0] + f * w_b[0],
                          parameters[kBias][1] + (1.0 - f) * w_a[1] + f * w_b[1]};
  const double* inner[6] = {parameters[0], parameters[1], bias,
                            parameters[3], parameters[4], parameters[5]};
  if (jacobians == nullptr) return scan_->Evaluate(inner, residuals, nullptr);

  const int rows = num_residuals();
  // The bias Jacobian is needed for the white errors' blocks as well.
  std::vector<double> bias_jacobian(static_cast<size_t>(rows) * 2);
  double* inner_jacobians[6] = {jacobians[0], jacobians[1], bias_jacobian.data(),
                                jacobians[3], jacobians[4], jacobians[5]};
  if (!scan_->Evaluate(inner, residuals, inner_jacobians)) return false;
  const auto scatter = [&bias_jacobian](double scale, double* to) {
    if (to == nullptr) return;
    for (size_t k = 0; k < bias_jacobian.size(); ++k) to[k] = scale * bias_jacobian[k];
  };
  scatter(1.0, jacobians[kBias]);
  scatter(1.0 - f, jacobians[kFixA]);
  scatter(f, jacobians[kFixB]);
  return true;
}

}  // namespace wallcal::solvers
