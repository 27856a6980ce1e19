#pragma once
// A zero-mean Gaussian prior on a 2-vector nuisance parameter block (solvers/ceres_solver.cc):
//   r_k = value_k / sigma_k      (dimensionless), k = 0, 1
// Used for
//  - a wall's [δd_m, δα_rad] with sigma = [WallGeometry::sigma_offset_m, sigma_angle_rad]: the
//    surveyed line is known to that 1σ (survey points, tie to UTM);
//  - a GNSS segment's bias [b_east_m, b_north_m] with sigma = [σ_b, σ_b] (m): the correlated
//    RTK error shared by all scans of one station or segment.
// sigma_k must be > 0; a coordinate known exactly is held constant by the caller instead.
// No robust loss: the prior is the model, not a measurement that can be an outlier.

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>

namespace wallcal::solvers {

class ZeroMeanPriorCost {
 public:
  explicit ZeroMeanPriorCost(const Eigen::Vector2d& sigma) : inverse_sigma_(sigma.cwiseInverse()) {}

  template <typename T>
  bool operator()(const T* const value, T* residual) const {
    residual[0] = value[0] * inverse_sigma_.x();
    residual[1] = value[1] * inverse_sigma_.y();
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& sigma) {
    return new ceres::AutoDiffCostFunction<ZeroMeanPriorCost, 2, 2>(new ZeroMeanPriorCost(sigma));
  }

 private:
  Eigen::Vector2d inverse_sigma_;
};

}  // namespace wallcal::solvers
