#include "solvers/wall_slice_cost.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace wallcal::solvers {
namespace {

constexpr int kBlocks = 6;
constexpr int kBlockSizes[kBlocks] = {3, 2, 2, 2, 1, 1};

}  // namespace

WallSliceCost::WallSliceCost(const std::vector<WallLineMeasurement>& measurements,
                             std::vector<int> indices, double huber_scale)
    : measurements_(measurements), indices_(std::move(indices)), huber_scale_(huber_scale) {
  set_num_residuals(2 * static_cast<int>(indices_.size()) + 1);
  mutable_parameter_block_sizes()->assign(kBlockSizes, kBlockSizes + kBlocks);
}

bool WallSliceCost::Evaluate(double const* const* parameters, double* residuals,
                             double** jacobians) const {
  const double k = huber_scale_;
  const size_t n = indices_.size();
  double* scan_jacobians[kBlocks];
  double beyond = 0.0;  // Σ (ρ − ρ′ s) over the scans in the loss's linear region
  for (size_t i = 0; i < n; ++i) {
    double* e = residuals + 2 * i;
    if (jacobians != nullptr) {
      for (int b = 0; b < kBlocks; ++b) {
        scan_jacobians[b] =
            jacobians[b] == nullptr ? nullptr : jacobians[b] + 2 * i * kBlockSizes[b];
      }
    }
    const WallLineMeasurement& m = measurements_[indices_[i]];
    EvaluateWallLine(m, parameters, e, jacobians == nullptr ? nullptr : scan_jacobians);
    const double s = (e[0] * e[0] + e[1] * e[1]) / m.weight;  // one scan's
    if (!(k > 0.0) || s <= k * k) continue;  // the loss's quadratic region: ρ(s) = s
    const double root_s = std::sqrt(s);
    const double rho = 2.0 * k * root_s - k * k;
    const double rho1 = k / root_s;
    beyond += m.weight * (rho - rho1 * s);
    const double a = std::sqrt(rho1);
    e[0] *= a;
    e[1] *= a;
    if (jacobians == nullptr) continue;
    for (int b = 0; b < kBlocks; ++b) {
      double* j = scan_jacobians[b];
      if (j == nullptr) continue;
      for (int col = 0; col < 2 * kBlockSizes[b]; ++col) j[col] *= a;
    }
  }
  // The last residual tops the sum of squares up to Σρ; it does not move with the parameters.
  residuals[2 * n] = std::sqrt(std::max(0.0, beyond));
  if (jacobians != nullptr) {
    for (int b = 0; b < kBlocks; ++b) {
      if (jacobians[b] == nullptr) continue;
      std::fill_n(jacobians[b] + 2 * n * kBlockSizes[b], kBlockSizes[b], 0.0);
    }
  }
  return true;
}

}  // namespace wallcal::solvers
