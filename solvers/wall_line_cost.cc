// SPDX-License-Identifier: Apache-2.0
#include "solvers/wall_line_cost.h"

#include <algorithm>
#include <cmath>

namespace wallcal::solvers {

bool WallLineCostFunction::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  EvaluateWallLine(*m_, parameters, residuals, jacobians);
  return true;
}

void EvaluateWallLine(const WallLineMeasurement& m, double const* const* parameters,
                      double* residuals, double** jacobians, double* raw_rows) {
  const double* mount = parameters[0];
  const double* wall_delta = parameters[1];
  const double* bias = parameters[2];
  const double* time_offset = parameters[3];
  const double* heading_offset = parameters[4];
  const double* heading_drift = parameters[5];

  // The same expressions, in the same order, as WallLineCost::Errors (the residuals agree to
  // the last bit).
  const double delta_d_m = wall_delta[0];
  const double delta_alpha_rad = wall_delta[1];
  const double ca = std::cos(delta_alpha_rad);
  const double sa = std::sin(delta_alpha_rad);
  const double nx = m.sign * (ca * m.wall_normal_local.x() - sa * m.wall_normal_local.y());
  const double ny = m.sign * (sa * m.wall_normal_local.x() + ca * m.wall_normal_local.y());
  const double d_m =
      nx * m.wall_centre_local_m.x() + ny * m.wall_centre_local_m.y() + m.sign * delta_d_m;
  const double dt_s = time_offset[0];
  const double heading_delay_s = time_offset[1];
  const double psi = m.vehicle_yaw_rad - heading_offset[0] - heading_drift[0] * m.drift_time_s +
                     m.yaw_rate_rps * (dt_s + heading_delay_s);
  const double cpsi = std::cos(psi);
  const double spsi = std::sin(psi);
  const double sx = m.antenna_local_m.x() + m.velocity_local_mps.x() * dt_s - bias[0] +
                    cpsi * mount[0] - spsi * mount[1];
  const double sy = m.antenna_local_m.y() + m.velocity_local_mps.y() * dt_s - bias[1] +
                    spsi * mount[0] + cpsi * mount[1];
  double error[2];
  error[0] = d_m - (nx * sx + ny * sy) - m.rho_m;
  error[1] = WrapAngle(m.wall_normal_angle_rad + delta_alpha_rad - psi - mount[2] - m.theta_rad);
  const Eigen::Matrix2d& w = m.sqrt_information;
  residuals[0] = w(0, 0) * error[0] + w(0, 1) * error[1];
  residuals[1] = w(1, 0) * error[0] + w(1, 1) * error[1];
  if (jacobians == nullptr && raw_rows == nullptr) return;

  // Unwhitened rows over the blocks' columns in order: rho[k] = ∂e_rho/∂p_k,
  // theta[k] = ∂e_theta/∂p_k; then J = W [rho; theta].
  const double tau = m.drift_time_s;
  const double omega = m.yaw_rate_rps;
  // ∂s/∂ψ' = ∂R(ψ')/∂ψ' (x, y) = (−sinψ' x − cosψ' y, cosψ' x − sinψ' y).
  const double g = -(nx * (-spsi * mount[0] - cpsi * mount[1]) +
                     ny * (cpsi * mount[0] - spsi * mount[1]));
  const double cx = m.wall_centre_local_m.x(), cy = m.wall_centre_local_m.y();
  const double normal_speed = nx * m.velocity_local_mps.x() + ny * m.velocity_local_mps.y();
  const double rho[kWallLineColumns] = {
      -(nx * cpsi + ny * spsi), nx * spsi - ny * cpsi, 0.0,  // mount
      m.sign, -ny * (cx - sx) + nx * (cy - sy),                // wall
      nx, ny,                                                  // bias
      -normal_speed + g * omega, g * omega,                    // time offset, heading delay
      -g,                                                      // heading offset
      -g * tau};                                               // heading drift
  const double theta[kWallLineColumns] = {0.0, 0.0, -1.0, 0.0, 1.0, 0.0,
                                          0.0, -omega, -omega, 1.0, tau};
  if (raw_rows != nullptr) {
    std::copy(rho, rho + kWallLineColumns, raw_rows);
    std::copy(theta, theta + kWallLineColumns, raw_rows + kWallLineColumns);
  }
  if (jacobians == nullptr) return;
  int first = 0;
  for (int b = 0; b < kWallLineBlocks; ++b) {
    const int size = kWallLineBlockSizes[b];
    double* j = jacobians[b];
    if (j != nullptr) {
      for (int k = 0; k < size; ++k) {
        j[k] = w(0, 0) * rho[first + k] + w(0, 1) * theta[first + k];
        j[size + k] = w(1, 0) * rho[first + k] + w(1, 1) * theta[first + k];
      }
    }
    first += size;
  }
}

}  // namespace wallcal::solvers
