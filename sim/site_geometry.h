// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulated site in three dimensions: the yard's ground plane, the vehicle standing on it
// (its roll and pitch from the ground under its heading, the antenna's height), the scanner's
// pose from its mount, and the surfaces a beam meets: walls standing on the ground up to their
// height, upright or leaning, round obstacles, and the ground itself.
//
// Frames and units: local ENU (x true east, y true north, z up; origin the site origin at
// site_height_m), metres, radians.
// - Ground: the plane z = slope · (rise_dir_enu · (x, y)) through the site origin.
// - Vehicle frame: x forward, y left, z up, origin at the GNSS antenna; enu_R_vehicle =
//   Rz(yaw)·Ry(−pitch)·Rx(roll) (yaw ccw from east, pitch positive nose up, roll positive right
//   side down). Standing on the ground, its z axis is the ground's normal and its antenna is
//   antenna_height_m from the ground along it.
// - Scanner frame: origin antenna + enu_R_vehicle·(mount_x, mount_y, mount_z), axes
//   enu_R_vehicle·Rz(mount_yaw)·Ry(−scanner_pitch)·Rx(scanner_roll); each beam is the ray from
//   its origin in its x–y plane at the beam's bearing (ccw from its x axis).
// A configuration with no key of the 3-D site (SimulationConfig::IsThreeDSite) is the 2-D
// model: no ground, walls without foot or top, the antenna and the scanner at the site origin's
// height, every beam horizontal. The code below then does the 2-D model's arithmetic operation
// for operation (its files bit for bit): the tilts are applied only when one is not zero.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "sim/simulation_config.h"

namespace wallcal::sim {

// The vehicle's roll and pitch (rad), as in the frame comment above.
struct VehicleAttitude {
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
};

// The yard of a configuration and where the vehicle stands on it.
struct Site {
  bool has_ground = false;  // false: the 2-D model (no ground, no wall foot or top)
  double slope = 0.0;       // rise per metre of horizontal distance along rise_dir_enu (>= 0)
  Eigen::Vector2d rise_dir_enu = Eigen::Vector2d::UnitY();  // unit, horizontal
  double antenna_height_m = 0.0;  // antenna above the ground along its normal; 0 in 2-D

  // The ground's height (m, ENU up) under a horizontal position.
  double GroundUpM(const Eigen::Vector2d& p_enu_m) const {
    return slope * rise_dir_enu.dot(p_enu_m);
  }
  // The ground's upward unit normal.
  Eigen::Vector3d GroundNormalEnu() const;
  // The attitude of a vehicle standing on the ground heading yaw_enu_rad (ccw from east):
  // pitch = atan(slope along the heading), roll = atan(slope towards its left · cos pitch), so
  // that both its x and its y axis lie in the ground (exact for a plane). Heading uphill: nose
  // up; the ground rising to its left: right side down (roll > 0).
  VehicleAttitude AttitudeAt(double yaw_enu_rad) const;
  // The antenna's height (m, ENU up) when its horizontal position is antenna_enu_m: the ground
  // there plus antenna_height_m·sqrt(1 + slope²) (antenna_height_m along the normal); 0 in 2-D.
  double AntennaUpM(const Eigen::Vector2d& antenna_enu_m) const;
};

// The site of `config`: its grade and antenna height when IsThreeDSite(), the 2-D model
// otherwise.
Site SiteOf(const SimulationConfig& config);

// Rz(yaw)·Ry(−pitch)·Rx(roll): the frame comment's rotation of a vehicle (or scanner) frame.
Eigen::Matrix3d EnuRotation(double yaw_rad, double pitch_rad, double roll_rad);

// The scanner's mount on the vehicle (SimulationConfig mount_*, scanner_pitch/roll).
struct ScannerMount {
  Eigen::Vector3d lever_m = Eigen::Vector3d::Zero();  // vehicle frame
  double yaw_rad = 0.0;
  double pitch_rad = 0.0;
  double roll_rad = 0.0;
};
ScannerMount MountOf(const SimulationConfig& config);

// The scanner's pose in ENU. Its rotation is kept as Rz(yaw_enu_rad) · tilt, the vehicle's
// yaw plus the mount yaw first: with no tilt (tilted false, tilt the identity) a beam's
// direction is the 2-D model's, bit for bit.
struct SimScannerPose {
  Eigen::Vector3d origin_enu_m = Eigen::Vector3d::Zero();
  double yaw_enu_rad = 0.0;  // vehicle yaw + mount yaw
  bool tilted = false;       // the vehicle or the scanner rolled or pitched
  Eigen::Matrix3d tilt = Eigen::Matrix3d::Identity();
  // enu_R_scanner (the frame comment's scanner axes).
  Eigen::Matrix3d EnuRScanner() const;
  // The unit ENU direction of the beam at bearing_rad (ccw from the scanner's x axis).
  Eigen::Vector3d BeamEnu(double bearing_rad) const;
};

// The scanner's pose with the antenna at (antenna_enu_m, antenna_up_m), the vehicle at
// yaw_enu_rad with `attitude`.
SimScannerPose ScannerPoseOf(const ScannerMount& mount, const Eigen::Vector2d& antenna_enu_m,
                             double antenna_up_m, double yaw_enu_rad,
                             const VehicleAttitude& attitude);

// A point of a wall's face h_m above its foot, at the horizontal place p_enu_m of its base line
// (ENU, m): moved h·tan(lean) towards the wall's left, at the ground's height there plus h.
Eigen::Vector3d WallFacePoint(const Site& site, const SimWall& wall,
                              const Eigen::Vector2d& p_enu_m, double h_m);

namespace detail {

enum class Surface { kWall, kObstacle, kGround };

struct Hit {
  double range_m;
  double cos_incidence;  // |cos| of the angle between the beam and the surface normal
  int wall_index;        // into config.walls; -1 for an obstacle or the ground
  Surface surface;
};

// The surfaces of a configuration's site and the ray cast against them.
class Scene {
 public:
  explicit Scene(const SimulationConfig& config);

  // Nearest surface along the ray origin + t·dir, t > 0 (dir a unit vector, ENU).
  std::optional<Hit> Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const;

 private:
  struct Wall {
    Eigen::Vector2d p0, e;  // foot line start and direction p1 − p0 (horizontal)
    double length_m;
    double up0_m, up1_m;    // the ground under its ends
    double height_m;
    bool leans;
    Eigen::Vector3d normal;  // leaning walls: unit normal of the face's plane
    double offset;           // leaning walls: normal · (p0, up0_m)
  };
  Site site_;
  std::vector<Wall> walls_;
  std::vector<std::pair<Eigen::Vector2d, double>> circles_;
};

}  // namespace detail
}  // namespace wallcal::sim
