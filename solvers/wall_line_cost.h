// SPDX-License-Identifier: Apache-2.0
#pragma once
// The cost of one wall observation (one scan's line fit on one surveyed wall) in the joint mount
// adjustment (built in solvers/mount_problem.cc, solved in solvers/ceres_solver.cc).
//
// Residual (2, dimensionless: whitened by the observation's total covariance):
//   e = W · [ rho_pred − rho_m ;  wrap(theta_pred − theta_rad) ]          ([m; rad] before W)
// with, in the local ground frame (metres, radians ccw from grid east):
//   n' = R(δα) n_w,   d' = n'·c_w + δd      wall w turned by δα about its centre c_w (a point on
//                                           the surveyed line) and shifted by δd along n'
//   n = σ n',  d = σ d'                     σ = ±1, fixed per observation so that the measured
//                                           antenna is on the negative side of the line
//   p' = p + v·dt                           the antenna at the scan's true time: the scan stamp
//                                           is dt early on the GNSS/heading clock (v, ω the
//                                           vehicle's velocity and yaw rate; ~0 at a station)
//   ψ' = ψ − h − r·τ + ω·(dt + δh)          the true vehicle yaw: ψ the yaw used (a dwell's mean
//                                           heading at a station, the interpolated heading
//                                           while moving), h the heading error common to the
//                                           segment (0 for moving scans), r the heading drift
//                                           rate, τ = t − t_ref the scan's (dwell's) time from
//                                           the session's reference time; δh the heading
//                                           stream's delay relative to the GNSS epochs (its
//                                           samples are stamped δh later than the positions)
//   s = p' − b + R(ψ')·(x, y)               scanner origin: the true antenna is the measured
//                                           one minus the segment's GNSS bias b
//   rho_pred   = d − n·s                    [m], > 0 when the scanner is in front of the wall
//   theta_pred = atan2(σ n_w) + δα − ψ' − yaw  [rad]  (atan2(n) = atan2(σ n_w) + δα exactly)
// W = L⁻¹ with L Lᵀ = Σ, the 2x2 covariance of [rho; theta] (m², m·rad, rad²): line fit +
// GNSS white noise + heading noise (ObservationCovariance in mount_problem.cc, where the choice
// is explained).
//
// Parameter blocks: mount [x_m, y_m, yaw_rad] (vehicle frame: x forward, y left, yaw ccw),
// wall [δd_m, δα_rad], GNSS bias [b_east_m, b_north_m] (measured = true + b), time offset
// [dt_s, δh_s] (true scan time = stamped time + dt; heading delay δh; held constant at 0 unless
// moving scans are used),
// heading offset [h_rad] of the segment (a constant zero block for moving scans), heading drift
// [r_rad_per_s] (one for the session; constant 0 when not modelled).
// The robust loss is chosen where the block is added (HuberLoss on these whitened units).

#include <ceres/autodiff_cost_function.h>
#include <ceres/jet.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <cmath>
#include <memory>
#include "common/angles.h"

namespace wallcal::solvers {

// Everything a WallLineCost holds fixed, precomputed once from the input.
struct WallLineMeasurement {
  Eigen::Vector2d antenna_local_m = Eigen::Vector2d::Zero();       // p, measured
  double vehicle_yaw_rad = 0.0;                                    // ψ
  Eigen::Vector2d velocity_local_mps = Eigen::Vector2d::Zero();    // v
  double yaw_rate_rps = 0.0;                                       // ω
  double drift_time_s = 0.0;                                       // τ = t − t_ref
  double sign = 1.0;                                               // σ = ±1
  Eigen::Vector2d wall_normal_local = Eigen::Vector2d::UnitX();    // n_w (unit, as surveyed)
  Eigen::Vector2d wall_centre_local_m = Eigen::Vector2d::Zero();   // c_w, on the surveyed line
  double wall_normal_angle_rad = 0.0;                              // atan2(σ n_w)
  double rho_m = 0.0;                                              // observed
  double theta_rad = 0.0;                                          // observed
  Eigen::Matrix2d sqrt_information = Eigen::Matrix2d::Identity();  // W = L⁻¹ (1/m, 1/rad)
  // The scans this observation stands for (a thinned or resampled re-solve's weight, > 0). W
  // carries √weight; the robust loss is applied to each scan it stands for (wall_slice_cost.h).
  double weight = 1.0;
};

class WallLineCost {
 public:
  // Refers to `measurement`, which must outlive the cost (Create makes an owning one).
  explicit WallLineCost(const WallLineMeasurement& measurement) : m_(&measurement) {}

  template <typename T>
  bool operator()(const T* const mount, const T* const wall_delta, const T* const bias,
                  const T* const time_offset, const T* const heading_offset,
                  const T* const heading_drift, T* residual) const {
    T error[2];
    Errors(mount, wall_delta, bias, time_offset, heading_offset, heading_drift, error);
    const Eigen::Matrix2d& w = m_->sqrt_information;
    residual[0] = w(0, 0) * error[0] + w(0, 1) * error[1];
    residual[1] = w(1, 0) * error[0] + w(1, 1) * error[1];
    return true;
  }

  // The errors before whitening: error[0] = rho_pred − rho_m (m), error[1] = wrap(theta_pred −
  // theta_rad) (rad, in (−π, π]).
  template <typename T>
  void Errors(const T* const mount, const T* const wall_delta, const T* const bias,
              const T* const time_offset, const T* const heading_offset,
              const T* const heading_drift, T* error) const {
    using std::cos;
    using std::sin;
    const T& delta_d_m = wall_delta[0];
    const T& delta_alpha_rad = wall_delta[1];
    // Moved wall line, oriented towards the vehicle.
    const T ca = cos(delta_alpha_rad);
    const T sa = sin(delta_alpha_rad);
    const T nx = m_->sign * (ca * m_->wall_normal_local.x() - sa * m_->wall_normal_local.y());
    const T ny = m_->sign * (sa * m_->wall_normal_local.x() + ca * m_->wall_normal_local.y());
    const T d_m =
        nx * m_->wall_centre_local_m.x() + ny * m_->wall_centre_local_m.y() + m_->sign * delta_d_m;
    // Scanner origin in the local frame.
    const T& dt_s = time_offset[0];
    const T& heading_delay_s = time_offset[1];
    const T psi = m_->vehicle_yaw_rad - heading_offset[0] - heading_drift[0] * m_->drift_time_s +
                  m_->yaw_rate_rps * (dt_s + heading_delay_s);
    const T cpsi = cos(psi);
    const T spsi = sin(psi);
    const T sx = m_->antenna_local_m.x() + m_->velocity_local_mps.x() * dt_s - bias[0] +
                 cpsi * mount[0] - spsi * mount[1];
    const T sy = m_->antenna_local_m.y() + m_->velocity_local_mps.y() * dt_s - bias[1] +
                 spsi * mount[0] + cpsi * mount[1];
    error[0] = d_m - (nx * sx + ny * sy) - m_->rho_m;
    T theta_error_rad =
        m_->wall_normal_angle_rad + delta_alpha_rad - psi - mount[2] - m_->theta_rad;
    // Wrapped into (−π, π]; the wrap's ceil has a zero derivative, so the Jacobian is unaffected.
    error[1] = WrapAngle(theta_error_rad);
  }

  const WallLineMeasurement& measurement() const { return *m_; }

  // One observation's cost as the adjustment evaluates it: residual from Errors above,
  // Jacobians written out by hand (WallLineCostFunction below; the tests check them against
  // automatic and numeric differentiation). The adjustment itself puts the observations of a
  // GNSS-error slice in one block (wall_slice_cost.h), each evaluated by EvaluateWallLine.
  static ceres::CostFunction* Create(const WallLineMeasurement& measurement);
  // The same cost differentiated automatically (ceres::Jet), for the tests.
  static ceres::CostFunction* CreateAutoDiff(const WallLineMeasurement& measurement) {
    auto* cost = new WallLineCost(measurement);
    cost->owned_ = std::make_unique<const WallLineMeasurement>(measurement);
    cost->m_ = cost->owned_.get();
    return new ceres::AutoDiffCostFunction<WallLineCost, 2, 3, 2, 2, 2, 1, 1>(cost);
  }

 private:
  const WallLineMeasurement* m_;
  std::unique_ptr<const WallLineMeasurement> owned_;  // set by CreateAutoDiff
};

// WallLineCost with analytic Jacobians: about a fifth of the work of the 11-wide dual numbers,
// on the adjustment's hottest path (every observation, every iteration). With ψ' the true yaw,
// s the scanner origin and n the moved wall normal (wall_line_cost.h, top):
//   ∂e_rho/∂(x, y)  = −nᵀ R(ψ')                ∂e_rho/∂yaw = 0
//   ∂e_rho/∂δd      = σ                         ∂e_rho/∂δα  = n⊥·(c_w − s), n⊥ = (−n_y, n_x)
//   ∂e_rho/∂b       = n                         g = ∂e_rho/∂ψ' = −n·(∂R(ψ')/∂ψ' (x, y))
//   ∂e_rho/∂dt      = −n·v + g ω                ∂e_rho/∂δh  = g ω
//   ∂e_rho/∂h       = −g                        ∂e_rho/∂r   = −g τ
//   ∂e_theta/∂(yaw, δα, dt, δh, h, r) = (−1, 1, −ω, −ω, 1, τ), 0 for the rest.
// Residual and Jacobian rows are then whitened by W.
class WallLineCostFunction : public ceres::SizedCostFunction<2, 3, 2, 2, 2, 1, 1> {
 public:
  explicit WallLineCostFunction(const WallLineMeasurement& measurement) : m_(&measurement) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  friend class WallLineCost;
  const WallLineMeasurement* m_;
  std::unique_ptr<const WallLineMeasurement> owned_;  // set by WallLineCost::Create
};

// The parameter blocks' sizes (mount, wall, bias, time offset, heading offset, drift) and
// their columns in all.
inline constexpr int kWallLineBlocks = 6;
inline constexpr int kWallLineBlockSizes[kWallLineBlocks] = {3, 2, 2, 2, 1, 1};
inline constexpr int kWallLineColumns = 11;

// The residual (2) and, when `jacobians` is not null, the Jacobians (row-major 2 x block size,
// for each of the six blocks whose pointer is not null) of one observation: what
// WallLineCostFunction::Evaluate returns, for costs that hold several observations. When
// `raw_rows` is not null it gets the unwhitened rows ∂(e_rho, e_theta)/∂p, row-major
// 2 x kWallLineColumns (the blocks' columns in order): J = W · raw.
void EvaluateWallLine(const WallLineMeasurement& measurement, double const* const* parameters,
                      double* residuals, double** jacobians, double* raw_rows = nullptr);

inline ceres::CostFunction* WallLineCost::Create(const WallLineMeasurement& measurement) {
  auto* cost = new WallLineCostFunction(measurement);
  cost->owned_ = std::make_unique<const WallLineMeasurement>(measurement);
  cost->m_ = cost->owned_.get();
  return cost;
}

}  // namespace wallcal::solvers
