// SPDX-License-Identifier: Apache-2.0
#include "calib/wall_geometry.h"

#include <cmath>

#include "common/angles.h"

namespace wallcal::calib {

OrientedWall OrientWall(const WallGeometry& wall, const Eigen::Vector2d& antenna_local_m) {
  OrientedWall oriented;
  // An antenna exactly on the line (never in practice: the vehicle cannot stand in the wall)
  // keeps the surveyed orientation.
  oriented.sign = (wall.offset_m - wall.normal_local.dot(antenna_local_m) < 0.0) ? -1.0 : 1.0;
  oriented.normal_local = oriented.sign * wall.normal_local;
  oriented.offset_m = oriented.sign * wall.offset_m;
  oriented.normal_angle_rad = std::atan2(oriented.normal_local.y(), oriented.normal_local.x());
  return oriented;
}

Eigen::Vector2d ScannerPositionLocal(const VehiclePose& pose, const Mount& mount) {
  const double c = std::cos(pose.yaw_rad);
  const double s = std::sin(pose.yaw_rad);
  return pose.antenna_local_m +
         Eigen::Vector2d(c * mount.x_m - s * mount.y_m, s * mount.x_m + c * mount.y_m);
}

Eigen::Vector2d NormalInVehicle(const OrientedWall& wall, double vehicle_yaw_rad) {
  const double c = std::cos(vehicle_yaw_rad);
  const double s = std::sin(vehicle_yaw_rad);
  const Eigen::Vector2d& n = wall.normal_local;
  return Eigen::Vector2d(c * n.x() + s * n.y(), -s * n.x() + c * n.y());
}

double VehicleToWallAngle(const OrientedWall& wall, double vehicle_yaw_rad) {
  return WrapAngle(wall.normal_angle_rad - vehicle_yaw_rad);
}

double PredictRho(const WallObservation& observation, const WallGeometry& wall,
                  const Mount& mount) {
  const OrientedWall oriented = OrientWall(wall, observation.pose.antenna_local_m);
  return oriented.offset_m -
         oriented.normal_local.dot(ScannerPositionLocal(observation.pose, mount));
}

double PredictTheta(const WallObservation& observation, const WallGeometry& wall,
                    const Mount& mount) {
  const OrientedWall oriented = OrientWall(wall, observation.pose.antenna_local_m);
  return WrapAngle(oriented.normal_angle_rad - observation.pose.yaw_rad - mount.yaw_rad);
}

}  // namespace wallcal::calib
