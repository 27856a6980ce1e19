// SPDX-License-Identifier: Apache-2.0
#include "guide/stop_poses.h"

#include <cmath>

#include "common/angles.h"

namespace wallcal::guide {

VehicleMove MoveBetween(const SitePose& from, const SitePose& to) {
  const Eigen::Vector2d d = to.antenna_local_m - from.antenna_local_m;
  const double c = std::cos(from.yaw_rad), s = std::sin(from.yaw_rad);
  VehicleMove move;
  move.forward_m = c * d.x() + s * d.y();
  move.left_m = -s * d.x() + c * d.y();
  move.turn_rad = WrapAngle(to.yaw_rad - from.yaw_rad);
  return move;
}

std::vector<StopTarget> TargetsFor(const StopModel& model, const std::vector<StopSpec>& stops,
                                   const std::optional<SitePose>& from) {
  std::vector<StopTarget> targets;
  std::optional<SitePose> previous = from;
  for (const StopSpec& stop : stops) {
    StopTarget target;
    if (!StopPose(model, stop, &target.pose)) {
      targets.push_back(target);
      previous.reset();
      continue;
    }
    if (previous) {
      target.has_move = true;
      target.move = MoveBetween(*previous, target.pose);
    }
    previous = target.pose;
    targets.push_back(target);
  }
  return targets;
}

std::optional<SitePose> MeanPose(const std::vector<const calib::WallObservation*>& observations) {
  if (observations.empty()) return std::nullopt;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double sin_sum = 0.0, cos_sum = 0.0;
  for (const calib::WallObservation* o : observations) {
    sum += o->pose.antenna_local_m;
    sin_sum += std::sin(o->pose.yaw_rad);
    cos_sum += std::cos(o->pose.yaw_rad);
  }
  SitePose pose;
  pose.antenna_local_m = sum / static_cast<double>(observations.size());
  pose.yaw_rad = std::atan2(sin_sum, cos_sum);
  return pose;
}

std::optional<SitePose> LatestPose(const std::vector<calib::WallObservation>& observations,
                                   double* stamp_s) {
  const calib::WallObservation* latest = nullptr;
  for (const calib::WallObservation& o : observations) {
    if (latest == nullptr || o.pose.stamp_s > latest->pose.stamp_s) latest = &o;
  }
  if (latest == nullptr) return std::nullopt;
  if (stamp_s != nullptr) *stamp_s = latest->pose.stamp_s;
  return SitePose{latest->pose.antenna_local_m, latest->pose.yaw_rad};
}

ScannerPlace ScannerAt(const SitePose& vehicle, const calib::Mount& mount) {
  const double c = std::cos(vehicle.yaw_rad), s = std::sin(vehicle.yaw_rad);
  ScannerPlace scanner;
  scanner.p_local_m = vehicle.antenna_local_m +
                      Eigen::Vector2d(c * mount.x_m - s * mount.y_m, s * mount.x_m + c * mount.y_m);
  scanner.yaw_rad = WrapAngle(vehicle.yaw_rad + mount.yaw_rad);
  return scanner;
}

}  // namespace wallcal::guide
