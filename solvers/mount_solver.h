#pragma once
// Estimating the scanner mount (vehicle_T_scanner = [x_m, y_m, yaw_rad]) from wall
// observations. Two methods on the same observations:
//  - SolveMountCeres: the joint least-squares adjustment (robust loss, nuisance parameters for
//    the wall lines and the correlated GNSS error per segment, covariance from Ceres);
//  - SolveMountBarawid: the closed form of seed 002 (Eq. 8-16), for comparison.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/observation.h"
#include "io/options.h"

namespace wallcal::solvers {

struct Mount {
  double x_m = 0.0;    // scanner origin in the vehicle frame, forward
  double y_m = 0.0;    // left
  double yaw_rad = 0.0;  // scanner x axis from vehicle x axis, ccw
};

struct MountEstimate {
  Mount mount;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // x, y, yaw (m, m, rad)
  bool usable = false;  // false: do not write offsets; `message` says why
  std::string message;
  std::string method;   // "ceres" or "barawid"
  int observations_used = 0;
  int observations_rejected = 0;  // down-weighted as outliers by the robust loss (> 3σ)
  double residual_rms_m = 0.0;    // RMS of the distance residuals of used observations
  std::vector<double> residual_rho_m;  // per observation (same order as the input), metres
  std::string solver_report;  // Ceres' brief report, or a line for barawid
};

MountEstimate SolveMountCeres(const std::vector<calib::WallObservation>& observations,
                              const std::vector<calib::WallGeometry>& walls,
                              const io::SolverOptions& options, const Mount& initial);

MountEstimate SolveMountBarawid(const std::vector<calib::WallObservation>& observations,
                                const std::vector<calib::WallGeometry>& walls,
                                const io::SolverOptions& options);

// The wall line `observation` should show for `mount`, from the nominal surveyed wall and the
// measured pose (no nuisance parameters): the scanner-frame line parameters that the
// observation's rho_m (m, > 0 when the scanner is in front of the wall) and theta_rad (rad, in
// (−π, π]) estimate. The wall normal is oriented so that the antenna is on its negative side.
// `wall` must be walls[observation.wall_index]. Used to gate the wall detector's second pass.
double PredictRho(const calib::WallObservation& observation, const calib::WallGeometry& wall,
                  const Mount& mount);
double PredictTheta(const calib::WallObservation& observation, const calib::WallGeometry& wall,
                    const Mount& mount);

}  // namespace wallcal::solvers
