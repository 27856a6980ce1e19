// SPDX-License-Identifier: Apache-2.0
#include "calib/site_geometry.h"

#include <cmath>

#include <Eigen/Geometry>

#include "calib/wall_geometry.h"
#include "common/angles.h"

namespace wallcal::calib {
namespace {

Eigen::Matrix3d RotZ(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).matrix(); }
Eigen::Matrix3d RotY(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).matrix(); }
Eigen::Matrix3d RotX(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).matrix(); }

}  // namespace

double SolverYaw(const WallObservation& observation) {
  const VehiclePose& pose = observation.pose;
  return pose.stationary && pose.segment >= 0 && pose.dwell_yaw_samples > 0 ? pose.dwell_yaw_rad
                                                                            : pose.yaw_rad;
}

Eigen::Matrix3d VehicleRotation(double yaw_rad, const Attitude& attitude) {
  return RotZ(yaw_rad) * RotY(-attitude.pitch_rad) * RotX(attitude.roll_rad);
}

Attitude AttitudeOnGround(const Eigen::Vector2d& grade, double yaw_rad) {
  // The vehicle's x axis in the plane with its plan direction at yaw; its z axis the plane's
  // upward normal; y = z × x. Then pitch and roll from R_v's last row (sin p, cos p sin r,
  // cos p cos r).
  const Eigen::Vector2d forward(std::cos(yaw_rad), std::sin(yaw_rad));
  const Eigen::Vector3d x = Eigen::Vector3d(forward.x(), forward.y(), grade.dot(forward)).normalized();
  const Eigen::Vector3d z = Eigen::Vector3d(-grade.x(), -grade.y(), 1.0).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Attitude attitude;
  attitude.pitch_rad = std::asin(std::max(-1.0, std::min(1.0, x.z())));
  attitude.roll_rad = std::atan2(y.z(), z.z());
  return attitude;
}

Eigen::Vector2d PredictLine3d(const VehiclePose& pose, double yaw_rad, const Attitude& attitude,
                              const Mount& mount, const ScannerPlacement& placement,
                              const WallGeometry& wall, double sign, const Heights& heights) {
  const Eigen::Matrix3d vehicle = VehicleRotation(yaw_rad, attitude);
  const Eigen::Matrix3d scanner =
      vehicle * RotZ(mount.yaw_rad) * RotY(-placement.pitch_rad) * RotX(placement.roll_rad);
  // The scanner's origin, its height taken from the wall's reference height.
  const Eigen::Vector3d lever = vehicle * Eigen::Vector3d(mount.x_m, mount.y_m, placement.z_m);
  const Eigen::Vector3d origin(pose.antenna_local_m.x() + lever.x(),
                               pose.antenna_local_m.y() + lever.y(),
                               heights.antenna_m - heights.wall_reference_m + lever.z());
  // The wall's plane {q : n_h · q_xy − offset = tan(lean) · q_z} (heights from its reference),
  // its top leaning towards +normal_local; oriented by `sign` towards the vehicle.
  const double t = std::tan(wall.lean_rad);
  const Eigen::Vector3d normal =
      sign * Eigen::Vector3d(wall.normal_local.x(), wall.normal_local.y(), -t);
  const double offset = sign * wall.offset_m;
  // The beam plane's points origin + scanner · (u, v, 0) on the wall: m · (u, v) = offset −
  // normal · origin, with m the first two elements of scannerᵀ · normal.
  const Eigen::Vector3d m = scanner.transpose() * normal;
  const double m_xy = std::hypot(m.x(), m.y());
  return Eigen::Vector2d((offset - normal.dot(origin)) / m_xy, std::atan2(m.y(), m.x()));
}

Eigen::Vector2d LevelCorrection(const WallObservation& observation, const WallGeometry& wall,
                                const Mount& mount, const Attitude& attitude,
                                const ScannerPlacement& placement, const Heights& heights) {
  const double yaw_rad = SolverYaw(observation);
  const OrientedWall oriented = OrientWall(wall, observation.pose.antenna_local_m);
  const Eigen::Vector2d line = PredictLine3d(observation.pose, yaw_rad, attitude, mount,
                                             placement, wall, oriented.sign, heights);
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  const Eigen::Vector2d scanner =
      observation.pose.antenna_local_m +
      Eigen::Vector2d(c * mount.x_m - s * mount.y_m, s * mount.x_m + c * mount.y_m);
  const double level_rho = oriented.offset_m - oriented.normal_local.dot(scanner);
  const double level_theta = oriented.normal_angle_rad - yaw_rad - mount.yaw_rad;
  return Eigen::Vector2d(line.x() - level_rho, WrapAngle(line.y() - level_theta));
}

}  // namespace wallcal::calib
