// SPDX-License-Identifier: Apache-2.0
#pragma once
// A surveyed wall line seen from one vehicle pose and a scanner mount: what the wall detector's
// gates predict and what both mount solvers compare observations with. All in the session's
// local ground frame (metres, radians ccw from grid east); see calib/observation.h.

#include <Eigen/Core>

#include "calib/observation.h"

namespace wallcal::calib {

// A wall line {q : normal_local · q = offset_m} with its normal turned so that the vehicle's
// antenna lies on the negative side (offset_m − normal_local · antenna > 0): the normal then
// points from the vehicle towards the wall, as the scanner's theta does.
struct OrientedWall {
  double sign = 1.0;  // +1 or −1: normal_local = sign · wall.normal_local
  Eigen::Vector2d normal_local = Eigen::Vector2d::UnitX();  // unit
  double offset_m = 0.0;
  double normal_angle_rad = 0.0;  // atan2 of normal_local, (−π, π]
};

// Orients `wall` for an antenna at `antenna_local_m` (the measured one: the sign is decided once
// from the input and then kept, so that it cannot flip while a solver moves the estimate).
OrientedWall OrientWall(const WallGeometry& wall, const Eigen::Vector2d& antenna_local_m);

// Scanner origin in the local frame: s = p_antenna + R(ψ) · (x_m, y_m).
Eigen::Vector2d ScannerPositionLocal(const VehiclePose& pose, const Mount& mount);

// The wall normal in vehicle coordinates, n_v = R(−ψ) n (Barawid 2007's cos φ, sin φ; Eq. 8, 10).
Eigen::Vector2d NormalInVehicle(const OrientedWall& wall, double vehicle_yaw_rad);

// The vehicle-to-wall angle φ = atan2(n) − ψ (Barawid 2007, Eq. 8), wrapped into (−π, π].
double VehicleToWallAngle(const OrientedWall& wall, double vehicle_yaw_rad);

// The wall line `observation` should show for `mount`, from the nominal surveyed wall and the
// measured pose (no nuisance parameters): the scanner-frame line parameters that the
// observation's rho_m (m, > 0 when the scanner is in front of the wall) and theta_rad (rad, in
// (−π, π]) estimate. The wall normal is oriented so that the antenna is on its negative side.
// `wall` must be walls[observation.wall_index]. Used to gate the wall detector's second pass.
double PredictRho(const WallObservation& observation, const WallGeometry& wall,
                  const Mount& mount);
double PredictTheta(const WallObservation& observation, const WallGeometry& wall,
                    const Mount& mount);

}  // namespace wallcal::calib
