// SPDX-License-Identifier: Apache-2.0
#pragma once
// The guide's report as a map of the site: where the vehicle stood at each station and stands
// now, each advised stop as the pose the stop model places it at (stop_model.h), and how to get
// there from the vehicle's pose, as a driver would do it. All in the session's local frame
// (calib/observation.h: x grid east, y grid north, ground metres).

#include <optional>
#include <vector>

#include "calib/observation.h"
#include "guide/stop_model.h"

namespace wallcal::guide {

// From one pose to another, in the vehicle frame of the first (x forward, y left).
struct VehicleMove {
  double forward_m = 0.0;  // negative: back
  double left_m = 0.0;     // negative: to the right
  double turn_rad = 0.0;   // the change of yaw, ccw (left) positive, in (−π, π]
};
VehicleMove MoveBetween(const SitePose& from, const SitePose& to);

// An advised stop on the map.
struct StopTarget {
  SitePose pose;          // where the model places it (StopPose)
  bool has_move = false;  // false: no pose to move from (no scan with a pose yet, a plan's first)
  VehicleMove move;       // from the vehicle's pose (the first stop) or from the stop before
};

// The targets of `stops`, in order: the first moved to from `from` (none: has_move false), each
// next from the one before. A stop whose wall index is not a wall is left at the origin with no
// move (the model never advises one).
std::vector<StopTarget> TargetsFor(const StopModel& model, const std::vector<StopSpec>& stops,
                                   const std::optional<SitePose>& from);

// The mean pose of `observations`: their antenna positions' mean and their yaws' circular mean.
// None when empty.
std::optional<SitePose> MeanPose(const std::vector<const calib::WallObservation*>& observations);

// The vehicle's pose at the latest stamp among `observations` (none when empty): where it stood
// when it last saw a wall.
std::optional<SitePose> LatestPose(const std::vector<calib::WallObservation>& observations,
                                   double* stamp_s);

// The scanner on the site: its origin in the local frame (m) and its x axis' yaw (rad, ccw from
// grid east).
struct ScannerPlace {
  Eigen::Vector2d p_local_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
};
// Where the scanner at `mount` is when the vehicle is at `vehicle`.
ScannerPlace ScannerAt(const SitePose& vehicle, const calib::Mount& mount);

}  // namespace wallcal::guide
