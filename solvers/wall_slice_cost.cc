// SPDX-License-Identifier: Apache-2.0
#include "solvers/wall_slice_cost.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace wallcal::solvers {
namespace {

// The wall-angle column (δα) among the 11: after the mount's three and the wall offset.
constexpr int kWallAngleColumn = 4;

// Whether two standing scans have the same model rows but for the wall-angle lever: the same
// heading, drift time, wall and side, and no motion (wall_slice_cost.h, the compressed form).
bool SameRows(const WallLineMeasurement& a, const WallLineMeasurement& b) {
  return a.vehicle_yaw_rad == b.vehicle_yaw_rad && a.drift_time_s == b.drift_time_s &&
         a.sign == b.sign && a.wall_normal_local == b.wall_normal_local &&
         a.wall_centre_local_m == b.wall_centre_local_m &&
         a.wall_normal_angle_rad == b.wall_normal_angle_rad;
}

bool Standing(const WallLineMeasurement& m) {
  return m.yaw_rate_rps == 0.0 && m.velocity_local_mps.x() == 0.0 &&
         m.velocity_local_mps.y() == 0.0;
}

// An upper-triangular R (4 x 4, row-major) with RᵀR = MᵀM for the rows of M given one at a time
// (Givens rotations): the QR factorisation of M without storing it.
class RowsToTriangle {
 public:
  void Add(double v0, double v1, double v2, double v3) {
    double v[4] = {v0, v1, v2, v3};
    for (int j = 0; j < 4; ++j) {
      if (v[j] == 0.0) continue;
      double* row = r_ + 4 * j;
      const double h = std::sqrt(row[j] * row[j] + v[j] * v[j]);
      const double c = row[j] / h, s = v[j] / h;
      row[j] = h;
      for (int k = j + 1; k < 4; ++k) {
        const double a = row[k];
        row[k] = c * a + s * v[k];
        v[k] = c * v[k] - s * a;
      }
    }
  }
  double operator()(int i, int j) const { return r_[4 * i + j]; }

 private:
  double r_[16] = {};
};

}  // namespace

WallSliceCost::WallSliceCost(const std::vector<WallLineMeasurement>& measurements,
                             std::vector<int> indices, double huber_scale)
    : measurements_(measurements), indices_(std::move(indices)), huber_scale_(huber_scale) {
  const WallLineMeasurement& first = measurements_[indices_.front()];
  compressed_ = indices_.size() >= 2 && Standing(first);
  for (size_t i = 1; i < indices_.size() && compressed_; ++i) {
    const WallLineMeasurement& m = measurements_[indices_[i]];
    compressed_ = Standing(m) && SameRows(first, m);
  }
  set_num_residuals(compressed_ ? kCompressedResiduals : 2 * static_cast<int>(indices_.size()) + 1);
  mutable_parameter_block_sizes()->assign(kWallLineBlockSizes,
                                          kWallLineBlockSizes + kWallLineBlocks);
}

bool WallSliceCost::Evaluate(double const* const* parameters, double* residuals,
                             double** jacobians) const {
  if (compressed_) return EvaluateCompressed(parameters, residuals, jacobians);
  const double k = huber_scale_;
  const size_t n = indices_.size();
  double* scan_jacobians[kWallLineBlocks];
  double beyond = 0.0;  // Σ (ρ − ρ′ s) over the scans in the loss's linear region
  for (size_t i = 0; i < n; ++i) {
    double* e = residuals + 2 * i;
    if (jacobians != nullptr) {
      for (int b = 0; b < kWallLineBlocks; ++b) {
        scan_jacobians[b] =
            jacobians[b] == nullptr ? nullptr : jacobians[b] + 2 * i * kWallLineBlockSizes[b];
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
    for (int b = 0; b < kWallLineBlocks; ++b) {
      double* j = scan_jacobians[b];
      if (j == nullptr) continue;
      for (int col = 0; col < 2 * kWallLineBlockSizes[b]; ++col) j[col] *= a;
    }
  }
  // The last residual tops the sum of squares up to Σρ; it does not move with the parameters.
  residuals[2 * n] = std::sqrt(std::max(0.0, beyond));
  if (jacobians != nullptr) {
    for (int b = 0; b < kWallLineBlocks; ++b) {
      if (jacobians[b] == nullptr) continue;
      std::fill_n(jacobians[b] + 2 * n * kWallLineBlockSizes[b], kWallLineBlockSizes[b], 0.0);
    }
  }
  return true;
}

bool WallSliceCost::EvaluateCompressed(double const* const* parameters, double* residuals,
                                       double** jacobians) const {
  const double k = huber_scale_;
  // Scan i's unwhitened rows are [P + (δ_i − δ_0) u; T] with P, T the first scan's rows and u
  // the wall-angle column's unit row: in the basis B = [P; T; u] its whitened, loss-corrected
  // rows are C_i = √ρ′ W_i [[1, 0, δ_i − δ_0], [0, 1, 0]], its residual √ρ′ e_i.
  double first_rows[2 * kWallLineColumns];
  double rows[2 * kWallLineColumns];
  double beyond = 0.0;
  RowsToTriangle triangle;  // of [C | r] over every scan's two rows
  for (size_t i = 0; i < indices_.size(); ++i) {
    const WallLineMeasurement& m = measurements_[indices_[i]];
    double e[2];
    EvaluateWallLine(m, parameters, e, nullptr, i == 0 ? first_rows : rows);
    const double lever = i == 0 ? 0.0
                                : rows[kWallAngleColumn] - first_rows[kWallAngleColumn];
    double a = 1.0;  // √ρ′
    const double s = (e[0] * e[0] + e[1] * e[1]) / m.weight;
    if (k > 0.0 && s > k * k) {
      const double root_s = std::sqrt(s);
      const double rho1 = k / root_s;
      beyond += m.weight * ((2.0 * k * root_s - k * k) - rho1 * s);
      a = std::sqrt(rho1);
    }
    const Eigen::Matrix2d& w = m.sqrt_information;
    for (int row = 0; row < 2; ++row) {
      triangle.Add(a * w(row, 0), a * w(row, 1), a * w(row, 0) * lever, a * e[row]);
    }
  }
  // [C | r] = Q R: the block's Jacobian C B and residual r give the rows R_C B and residuals
  // Qᵀr (three), with the same JᵀJ, gradient and model; r's part outside C's columns, |R₃₃|, and
  // the loss's top-up share the fourth residual, which does not move with the parameters.
  for (int a = 0; a < 3; ++a) residuals[a] = triangle(a, 3);
  residuals[3] = std::sqrt(triangle(3, 3) * triangle(3, 3) + std::max(0.0, beyond));
  if (jacobians == nullptr) return true;
  int first = 0;
  for (int b = 0; b < kWallLineBlocks; ++b) {
    const int size = kWallLineBlockSizes[b];
    double* j = jacobians[b];
    if (j != nullptr) {
      for (int a = 0; a < 3; ++a) {
        for (int c = 0; c < size; ++c) {
          const int column = first + c;
          j[a * size + c] = triangle(a, 0) * first_rows[column] +
                            triangle(a, 1) * first_rows[kWallLineColumns + column] +
                            (column == kWallAngleColumn ? triangle(a, 2) : 0.0);
        }
      }
      std::fill_n(j + 3 * size, size, 0.0);
    }
    first += size;
  }
  return true;
}

}  // namespace wallcal::solvers
