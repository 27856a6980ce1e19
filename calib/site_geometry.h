// SPDX-License-Identifier: Apache-2.0
#pragma once
// The site in 3-D: a vehicle standing tilted on a graded yard, a scanner below (or above) the
// GNSS antenna and tilted on the vehicle, walls that lean. The adjustment works in the level
// model of calib/wall_geometry.h (a horizontal scan plane through the antenna, vertical walls);
// each observation is moved into that model by its level correction: what the 3-D geometry
// puts into the scanner's line beyond what the level model predicts (docs/method.md, "The
// geometry in 3-D").
//
// Frames (metres, radians): the local frame x grid east, y grid north, z up (heights relative
// to any fixed datum; differences only). Vehicle frame x forward, y left, z up, origin at the
// GNSS antenna; its attitude R_v = Rz(ψ) · Ry(−pitch) · Rx(roll): pitch positive nose up, roll
// positive right side down. Scanner: origin at antenna + R_v · (x, y, z) (z: its height relative
// to the antenna, negative below it), axes R_v · Rz(yaw) · Ry(−pitch_s) · Rx(roll_s); its beams
// lie in its own x–y plane.

#include <Eigen/Core>

#include "calib/observation.h"

namespace wallcal::calib {

// The vehicle's roll and pitch (rad), in the conventions above.
struct Attitude {
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
};

// What the 3-D model knows of the scanner beyond the estimated (x, y, yaw) mount: its height
// relative to the antenna (m) and its own tilt on the vehicle (rad).
struct ScannerPlacement {
  double z_m = 0.0;
  double pitch_rad = 0.0;
  double roll_rad = 0.0;
};

// The yaw the solver uses for an observation: its dwell's mean heading at a station (one
// heading per station), else its own.
double SolverYaw(const WallObservation& observation);

// R_v = Rz(yaw) · Ry(−pitch) · Rx(roll).
Eigen::Matrix3d VehicleRotation(double yaw_rad, const Attitude& attitude);

// The attitude of a vehicle standing on a plane that rises by `grade` (m of height per m along
// the local x and y) with its x axis at `yaw_rad` (ccw from grid east) in plan.
Attitude AttitudeOnGround(const Eigen::Vector2d& grade, double yaw_rad);

// The heights a level correction needs (m, on one datum): the antenna's, and the height at
// which the wall's surveyed line (WallGeometry normal_local, offset_m) lies; only their
// difference matters, and only for a leaning wall.
struct Heights {
  double antenna_m = 0.0;
  double wall_reference_m = 0.0;
};

// The line (rho, theta) a scanner at the pose, attitude and placement sees on `wall` (tilted by
// WallGeometry::lean_rad about its surveyed line): the plane of its beams cuts the wall's plane
// in a line; rho its distance from the scanner origin in the beam plane, theta the direction
// of its normal from the scanner's x axis. `sign` orients the wall towards the vehicle as
// calib::OrientWall does. With a level vehicle, no tilt and an upright wall it is
// PredictRho / PredictTheta of calib/wall_geometry.h.
Eigen::Vector2d PredictLine3d(const VehiclePose& pose, double yaw_rad, const Attitude& attitude,
                              const Mount& mount, const ScannerPlacement& placement,
                              const WallGeometry& wall, double sign, const Heights& heights);

// The level correction of one observation: PredictLine3d − the level model's (rho, theta)
// (theta's difference wrapped into (−π, π]) at `mount`, with the pose's yaw (the dwell's mean
// yaw at a station) and the wall oriented by the measured antenna.
Eigen::Vector2d LevelCorrection(const WallObservation& observation, const WallGeometry& wall,
                                const Mount& mount, const Attitude& attitude,
                                const ScannerPlacement& placement, const Heights& heights);

}  // namespace wallcal::calib
