// SPDX-License-Identifier: Apache-2.0
#pragma once
// A Gaussian prior on a 2-vector nuisance parameter block (solvers/mount_problem.cc), zero-mean
// unless a mean is given:
//   r_k = (value_k − mean_k) / sigma_k      (dimensionless), k = 0, 1
// Used for
//  - a wall's [δd_m, δα_rad] with sigma = [WallGeometry::sigma_offset_m, sigma_angle_rad]: the
//    surveyed line is known to that 1σ (survey points, tie to UTM);
//  - the first GNSS segment's bias [b_east_m, b_north_m] with sigma = [σ_b, σ_b] (m): the
//    correlated RTK error shared by all scans of one station or segment (the later segments
//    are tied to it by GaussMarkovStepCost below).
// sigma_k must be > 0; a coordinate known exactly is held constant by the caller instead.
// No robust loss: the prior is the model, not a measurement that can be an outlier.

#include <ceres/autodiff_cost_function.h>
#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace wallcal::solvers {

class GaussianPriorCost {
 public:
  // `mean`: where the prior is centred instead of 0 (the clock rounds' time block, whose
  // parameters are what the poses do not already carry: mount_problem.cc).
  explicit GaussianPriorCost(const Eigen::Vector2d& sigma,
                             const Eigen::Vector2d& mean = Eigen::Vector2d::Zero())
      : inverse_sigma_(sigma.cwiseInverse()), mean_(mean) {}

  template <typename T>
  bool operator()(const T* const value, T* residual) const {
    residual[0] = (value[0] - mean_.x()) * inverse_sigma_.x();
    residual[1] = (value[1] - mean_.y()) * inverse_sigma_.y();
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& sigma,
                                     const Eigen::Vector2d& mean = Eigen::Vector2d::Zero()) {
    return new ceres::AutoDiffCostFunction<GaussianPriorCost, 2, 2>(
        new GaussianPriorCost(sigma, mean));
  }

 private:
  Eigen::Vector2d inverse_sigma_;
  Eigen::Vector2d mean_;
};

// One step of a first-order Gauss–Markov process between two GNSS segment biases (2-vectors,
// metres), taken at times Δt apart with correlation ρ = exp(−Δt/τ) and marginal σ's σ0, σ1:
//   b1 = ρ (σ1/σ0) b0 + w,   w ~ N(0, σ1² (1 − ρ²) I)
//   r_k = (b1_k − a·b0_k) / σ_w      a = ρ σ1/σ0,  σ_w = σ1 √(1 − ρ²)   (dimensionless)
// With a zero-mean prior of σ0 on the first bias of a chain, the biases get exactly the joint
// distribution of the process sampled at those times. a >= 0 and σ_w > 0 (the caller keeps ρ
// below 1).
class GaussMarkovStepCost {
 public:
  GaussMarkovStepCost(double a, double sigma_w) : a_(a), inverse_sigma_(1.0 / sigma_w) {}

  template <typename T>
  bool operator()(const T* const previous, const T* const next, T* residual) const {
    residual[0] = (next[0] - a_ * previous[0]) * inverse_sigma_;
    residual[1] = (next[1] - a_ * previous[1]) * inverse_sigma_;
    return true;
  }

  static ceres::CostFunction* Create(double a, double sigma_w) {
    return new ceres::AutoDiffCostFunction<GaussMarkovStepCost, 2, 2, 2>(
        new GaussMarkovStepCost(a, sigma_w));
  }

 private:
  double a_;
  double inverse_sigma_;
};

// A zero-mean prior on a scalar: r = value / sigma. sigma > 0.
class ScalarPriorCost {
 public:
  explicit ScalarPriorCost(double sigma) : inverse_sigma_(1.0 / sigma) {}

  template <typename T>
  bool operator()(const T* const value, T* residual) const {
    residual[0] = value[0] * inverse_sigma_;
    return true;
  }

  static ceres::CostFunction* Create(double sigma) {
    return new ceres::AutoDiffCostFunction<ScalarPriorCost, 1, 1>(new ScalarPriorCost(sigma));
  }

 private:
  double inverse_sigma_;
};

// A zero-mean Gaussian prior on several coordinates spread over several parameter blocks,
// with a full covariance Σ (k × k): r = W x, W = L⁻¹ with L Lᵀ = Σ (dimensionless). Used for
// the walls' [δd_m, δα_rad] jointly: every wall of a session hangs on the same survey tie, so
// their errors are correlated (calib::WallGeometry, solvers/mount_problem.cc). `coordinates`
// names, for each of the k entries of x in order, (parameter block index, coordinate in it);
// `block_sizes` gives each block's size. Coordinates of a block not named are not in the prior
// (their Jacobian column is 0). Linear, so the Jacobian is W itself, scattered into the blocks.
class JointPriorCost : public ceres::CostFunction {
 public:
  JointPriorCost(const Eigen::MatrixXd& whitening, std::vector<std::pair<int, int>> coordinates,
                 const std::vector<int>& block_sizes)
      : whitening_(whitening), coordinates_(std::move(coordinates)) {
    set_num_residuals(static_cast<int>(whitening_.rows()));
    for (int size : block_sizes) mutable_parameter_block_sizes()->push_back(size);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int k = static_cast<int>(coordinates_.size());
    Eigen::VectorXd x(k);
    for (int j = 0; j < k; ++j) x[j] = parameters[coordinates_[j].first][coordinates_[j].second];
    Eigen::Map<Eigen::VectorXd>(residuals, k) = whitening_ * x;
    if (jacobians == nullptr) return true;
    const std::vector<int32_t>& sizes = parameter_block_sizes();
    for (size_t b = 0; b < sizes.size(); ++b) {
      if (jacobians[b] == nullptr) continue;
      // Row-major k × sizes[b].
      std::fill(jacobians[b], jacobians[b] + k * sizes[b], 0.0);
    }
    for (int j = 0; j < k; ++j) {
      const auto [block, coordinate] = coordinates_[j];
      if (jacobians[block] == nullptr) continue;
      for (int r = 0; r < k; ++r) {
        jacobians[block][r * sizes[block] + coordinate] = whitening_(r, j);
      }
    }
    return true;
  }

 private:
  Eigen::MatrixXd whitening_;
  std::vector<std::pair<int, int>> coordinates_;
};

}  // namespace wallcal::solvers
