// SPDX-License-Identifier: Apache-2.0
#include "solvers/epoch_noise_cost.h"

#include <utility>
#include <vector>

namespace wallcal::solvers {
namespace {

constexpr int kBias = 2;      // the wrapped cost's bias block
constexpr int kHeading = 4;   // and its heading-offset block
constexpr int kFixes = 6;     // the white errors of the fixes k − 1 .. k + 2
constexpr int kSamples = 10;  // and of the heading samples k − 1 .. k + 2

}  // namespace

EpochNoiseCost::EpochNoiseCost(std::unique_ptr<WallSliceCost> scan,
                               const std::array<double, 4>& fix_weights,
                               const std::array<double, 4>& sample_weights)
    : scan_(std::move(scan)), fix_weights_(fix_weights), sample_weights_(sample_weights) {
  set_num_residuals(scan_->num_residuals());
  std::vector<int32_t>* sizes = mutable_parameter_block_sizes();
  *sizes = scan_->parameter_block_sizes();
  sizes->insert(sizes->end(), {2, 2, 2, 2, 1, 1, 1, 1});
}

bool EpochNoiseCost::Evaluate(double const* const* parameters, double* residuals,
                              double** jacobians) const {
  double bias[2] = {parameters[kBias][0], parameters[kBias][1]};
  double heading[1] = {parameters[kHeading][0]};
  for (int j = 0; j < 4; ++j) {
    bias[0] += fix_weights_[j] * parameters[kFixes + j][0];
    bias[1] += fix_weights_[j] * parameters[kFixes + j][1];
    heading[0] += sample_weights_[j] * parameters[kSamples + j][0];
  }
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
  for (int j = 0; j < 4; ++j) {
    scatter(bias_jacobian, fix_weights_[j], jacobians[kFixes + j]);
    scatter(heading_jacobian, sample_weights_[j], jacobians[kSamples + j]);
  }
  return true;
}

}  // namespace wallcal::solvers
