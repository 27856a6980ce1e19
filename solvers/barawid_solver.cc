// SPDX-License-Identifier: Apache-2.0
// Barawid 2007's closed form (Barawid et al. 2007, §III.2(2), Eq. 8-16), kept as published for
// comparison with the joint adjustment: the wall and the GNSS positions are taken as exact, every
// scan as an independent measurement, and no observation is down-weighted.

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "solvers/mount_solver.h"
#include "solvers/observability.h"

namespace wallcal::solvers {

MountEstimate SolveMountBarawid(const std::vector<calib::WallObservation>& observations,
                                const std::vector<calib::WallGeometry>& walls,
                                const solvers::SolverOptions& options, bool force) {
  MountEstimate estimate;
  estimate.method = Method::kBarawid;
  const ObservabilityReport observability = CheckObservability(observations, walls, options);
  if (!observability.ok) {
    if (!force || !observability.solvable) {
      estimate.failure = EstimateFailure::kNotDetermined;
      estimate.message = observability.message;
      return estimate;
    }
    // Forced: the closed form still needs a solvable normal system (checked below).
    estimate.forced = true;
    estimate.warnings.push_back(
        {SolverWarningKind::kForcedObservability, "FORCED: " + observability.message});
  }
  const int n = static_cast<int>(observations.size());

  // Yaw. Barawid 2007: φ = η − ν (Eq. 8) is the vehicle-to-wall angle, δ = κ − φ (Eq. 9) the
  // scanner yaw, κ the wall direction the scanner saw. In our frame (normals pointing from the
  // vehicle to the wall) that is yaw_i = atan2(n_i) − ψ_i − theta_i; the estimate is their
  // circular mean (the paper averages; the circular mean is the same away from ±π).
  std::vector<double> yaw_rad(n);
  double sum_sin = 0.0;
  double sum_cos = 0.0;
  // Position. Eq. 10: the antenna-to-wall distance D and the scanner-to-wall distance E differ
  // by the mount's component along the wall normal. With n_v = R(−ψ) n the normal in vehicle
  // coordinates, n_v·(x, y) = D − E, D = d − n·p, E = rho. (Barawid 2007 writes a cos φ + b sin φ =
  // E − D with its a lateral and b forward and its own signs; the content is the same.) Least
  // squares through the normal equations (Eq. 13-16).
  Eigen::Matrix2d normal_matrix = Eigen::Matrix2d::Zero();  // Aᵀ A
  Eigen::Vector2d normal_rhs = Eigen::Vector2d::Zero();     // Aᵀ b
  std::vector<Eigen::Vector2d> rows(n);
  std::vector<double> rhs_m(n);
  for (int i = 0; i < n; ++i) {
    const calib::WallObservation& observation = observations[i];
    const calib::OrientedWall wall =
        calib::OrientWall(walls[observation.wall_index], observation.pose.antenna_local_m);
    yaw_rad[i] =
        WrapAngle(wall.normal_angle_rad - observation.pose.yaw_rad - observation.theta_rad);
    sum_sin += std::sin(yaw_rad[i]);
    sum_cos += std::cos(yaw_rad[i]);

    rows[i] = calib::NormalInVehicle(wall, observation.pose.yaw_rad);
    const double antenna_to_wall_m =
        wall.offset_m - wall.normal_local.dot(observation.pose.antenna_local_m);  // D
    rhs_m[i] = antenna_to_wall_m - observation.rho_m;                             // D − E
    normal_matrix += rows[i] * rows[i].transpose();
    normal_rhs += rows[i] * rhs_m[i];
  }
  const double mean_yaw_rad = std::atan2(sum_sin, sum_cos);

  // The observability check already demands a spread of directions; this guards the
  // arithmetic (a 2x2 with a vanishing eigenvalue) in case the options allowed none.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(normal_matrix);
  if (!(eigen.eigenvalues().minCoeff() > 1e-9 * n)) {
    estimate.failure = EstimateFailure::kNotDetermined;
    estimate.message =
        "the wall normals seen from the vehicle all point one way: the offset along the wall is "
        "not determined";
    return estimate;
  }
  const Eigen::Matrix2d inverse = normal_matrix.inverse();
  const Eigen::Vector2d xy_m = inverse * normal_rhs;

  double sum_sq_m2 = 0.0;
  double sum_yaw_sq = 0.0;
  estimate.residual_rho_m.resize(n);
  for (int i = 0; i < n; ++i) {
    const double error_m = rhs_m[i] - rows[i].dot(xy_m);  // rho_pred − rho_observed
    estimate.residual_rho_m[i] = -error_m;                // observed − predicted
    sum_sq_m2 += error_m * error_m;
    const double dev = WrapAngle(yaw_rad[i] - mean_yaw_rad);
    sum_yaw_sq += dev * dev;
  }

  // The naive covariance of independent observations, as the method implies: σ² (AᵀA)⁻¹ with
  // σ² the residual variance, and the yaw's sample variance / N. Scans at one station share
  // their GNSS and wall errors, so this σ shrinks as 1/√N when it should not: it is reported
  // for comparison, not as the calibration's uncertainty.
  const double residual_variance_m2 = n > 2 ? sum_sq_m2 / (n - 2) : 0.0;
  const double yaw_variance = n > 1 ? sum_yaw_sq / (n - 1) : 0.0;
  estimate.covariance.setZero();
  estimate.covariance.topLeftCorner<2, 2>() = residual_variance_m2 * inverse;
  estimate.covariance(2, 2) = yaw_variance / n;

  estimate.mount.x_m = xy_m.x();
  estimate.mount.y_m = xy_m.y();
  estimate.mount.yaw_rad = mean_yaw_rad;
  estimate.observations_used = n;
  estimate.observations_rejected = 0;
  estimate.residual_rms_m = std::sqrt(sum_sq_m2 / n);
  char line[160];
  std::snprintf(line, sizeof line,
                "barawid closed form (Barawid 2007, Eq. 8-16): %d observations, rho residual RMS "
                "%.4f m, yaw scatter %.4f rad",
                n, estimate.residual_rms_m, std::sqrt(yaw_variance));
  estimate.solver_report = line;
  estimate.usable = true;
  return estimate;
}

}  // namespace wallcal::solvers
