// SPDX-License-Identifier: Apache-2.0
#include "sim/site_geometry.h"

#include <Eigen/Geometry>
#include <cmath>

namespace wallcal::sim {
namespace {

Eigen::Matrix3d Rz(double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// Ry(−pitch)·Rx(roll): the tilt part of EnuRotation.
Eigen::Matrix3d Tilt(double pitch_rad, double roll_rad) {
  return (Eigen::AngleAxisd(-pitch_rad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace

Eigen::Vector3d Site::GroundNormalEnu() const {
  return Eigen::Vector3d(-slope * rise_dir_enu.x(), -slope * rise_dir_enu.y(), 1.0).normalized();
}

VehicleAttitude Site::AttitudeAt(double yaw_enu_rad) const {
  if (slope == 0.0) return {};
  const Eigen::Vector2d forward(std::cos(yaw_enu_rad), std::sin(yaw_enu_rad));
  const Eigen::Vector2d left(-forward.y(), forward.x());
  VehicleAttitude attitude;
  attitude.pitch_rad = std::atan(slope * rise_dir_enu.dot(forward));
  // The y axis, (−sin r·sin p, cos r, sin r·cos p) in (forward, left, up), lies in the ground
  // when tan r = slope_left · cos p.
  attitude.roll_rad = std::atan(slope * rise_dir_enu.dot(left) * std::cos(attitude.pitch_rad));
  return attitude;
}

double Site::AntennaUpM(const Eigen::Vector2d& antenna_enu_m) const {
  if (!has_ground) return 0.0;
  // The foot of the normal through the antenna lies antenna_height_m·slope/sqrt(1 + slope²)
  // uphill of it (the normal leans downhill) and antenna_height_m/sqrt(1 + slope²) below it:
  // h·sqrt(1 + slope²) above the ground at the antenna's own horizontal place.
  return GroundUpM(antenna_enu_m) + antenna_height_m * std::sqrt(1.0 + slope * slope);
}

Site SiteOf(const SimulationConfig& config) {
  Site site;
  if (!config.IsThreeDSite()) return site;
  site.has_ground = true;
  site.slope = config.yard_grade_pct / 100.0;
  // A heading (cw from true north) as an ENU direction.
  site.rise_dir_enu = {std::sin(config.yard_grade_dir_rad), std::cos(config.yard_grade_dir_rad)};
  site.antenna_height_m = config.AntennaHeightM();
  return site;
}

Eigen::Matrix3d EnuRotation(double yaw_rad, double pitch_rad, double roll_rad) {
  return Rz(yaw_rad) * Tilt(pitch_rad, roll_rad);
}

ScannerMount MountOf(const SimulationConfig& config) {
  ScannerMount mount;
  mount.lever_m = {config.mount_x_m, config.mount_y_m, config.MountZM()};
  mount.yaw_rad = config.mount_yaw_rad;
  mount.pitch_rad = config.scanner_pitch_rad;
  mount.roll_rad = config.scanner_roll_rad;
  return mount;
}

Eigen::Matrix3d SimScannerPose::EnuRScanner() const { return Rz(yaw_enu_rad) * tilt; }

Eigen::Vector3d SimScannerPose::BeamEnu(double bearing_rad) const {
  if (!tilted) {
    const double enu_rad = yaw_enu_rad + bearing_rad;
    return {std::cos(enu_rad), std::sin(enu_rad), 0.0};
  }
  return EnuRScanner() * Eigen::Vector3d(std::cos(bearing_rad), std::sin(bearing_rad), 0.0);
}

SimScannerPose ScannerPoseOf(const ScannerMount& mount, const Eigen::Vector2d& antenna_enu_m,
                             double antenna_up_m, double yaw_enu_rad,
                             const VehicleAttitude& attitude) {
  const bool vehicle_tilted = attitude.roll_rad != 0.0 || attitude.pitch_rad != 0.0;
  const Eigen::Matrix3d vehicle_tilt =
      vehicle_tilted ? Tilt(attitude.pitch_rad, attitude.roll_rad) : Eigen::Matrix3d::Identity();
  const Eigen::Vector3d lever = vehicle_tilted ? Eigen::Vector3d(vehicle_tilt * mount.lever_m)
                                               : mount.lever_m;
  // Rotated by the yaw as the 2-D model did, operation for operation.
  const double c = std::cos(yaw_enu_rad), s = std::sin(yaw_enu_rad);
  SimScannerPose pose;
  pose.origin_enu_m = {antenna_enu_m.x() + (c * lever.x() - s * lever.y()),
                       antenna_enu_m.y() + (s * lever.x() + c * lever.y()),
                       antenna_up_m + lever.z()};
  pose.yaw_enu_rad = yaw_enu_rad + mount.yaw_rad;
  pose.tilted = vehicle_tilted || mount.pitch_rad != 0.0 || mount.roll_rad != 0.0;
  if (pose.tilted) {
    // Rz(yaw)·T_v·Rz(mount_yaw)·T_s = Rz(yaw + mount_yaw)·[Rz(−mount_yaw)·T_v·Rz(mount_yaw)·T_s].
    pose.tilt = Rz(-mount.yaw_rad) * vehicle_tilt * Rz(mount.yaw_rad) *
                Tilt(mount.pitch_rad, mount.roll_rad);
  }
  return pose;
}

Eigen::Vector3d WallFacePoint(const Site& site, const SimWall& wall,
                              const Eigen::Vector2d& p_enu_m, double h_m) {
  Eigen::Vector2d p = p_enu_m;
  if (wall.LeanRad() != 0.0) {
    const Eigen::Vector2d along =
        Eigen::Vector2d(wall.x1_m - wall.x0_m, wall.y1_m - wall.y0_m).normalized();
    p += h_m * std::tan(wall.LeanRad()) * Eigen::Vector2d(-along.y(), along.x());
  }
  return {p.x(), p.y(), site.GroundUpM(p_enu_m) + h_m};
}

namespace detail {

Scene::Scene(const SimulationConfig& config) : site_(SiteOf(config)) {
  for (const SimWall& w : config.walls) {
    Wall wall;
    wall.p0 = {w.x0_m, w.y0_m};
    wall.e = Eigen::Vector2d(w.x1_m, w.y1_m) - wall.p0;
    wall.length_m = wall.e.norm();
    wall.up0_m = site_.GroundUpM(wall.p0);
    wall.up1_m = site_.GroundUpM({w.x1_m, w.y1_m});
    wall.height_m = w.height_m;
    wall.leans = w.LeanRad() != 0.0 && wall.length_m > 0.0;
    wall.normal.setZero();
    wall.offset = 0.0;
    if (wall.leans) {
      // The face {q : (q − p0)·left = tan(lean)·(height of q above the foot line)}, the foot
      // line rising rise_per_m along the wall: a plane through the foot line.
      const Eigen::Vector2d along = wall.e / wall.length_m;
      const Eigen::Vector2d left(-along.y(), along.x());
      const double tan_lean = std::tan(w.LeanRad());
      const double rise_per_m = (wall.up1_m - wall.up0_m) / wall.length_m;
      const Eigen::Vector2d horizontal = left + tan_lean * rise_per_m * along;
      wall.normal = Eigen::Vector3d(horizontal.x(), horizontal.y(), -tan_lean).normalized();
      wall.offset = wall.normal.dot(Eigen::Vector3d(wall.p0.x(), wall.p0.y(), wall.up0_m));
    }
    walls_.push_back(wall);
  }
  for (const auto& o : config.obstacles) circles_.push_back({{o.x_m, o.y_m}, o.radius_m});
}

std::optional<Hit> Scene::Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const {
  constexpr double kMinT = 1e-9;
  constexpr double kEdgeM = 1e-9;  // a beam grazing a wall's foot or top still meets it
  std::optional<Hit> best;
  auto offer = [&best](double t, double cos_inc, int wall_index, Surface surface) {
    if (!best || t < best->range_m) best = Hit{t, cos_inc, wall_index, surface};
  };
  const Eigen::Vector2d o(origin.x(), origin.y());
  const Eigen::Vector2d d(dir.x(), dir.y());  // not unit when the beam is tilted
  const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  int wall_index = -1;
  for (const Wall& wall : walls_) {
    ++wall_index;
    if (wall.length_m <= 0.0) continue;
    double t = 0.0, s = 0.0, cos_inc = 0.0;
    if (!wall.leans) {
      // In the horizontal plane: origin + t·d = p0 + s·e  =>  t = (w×e)/(d×e),
      // s = (w×d)/(d×e), w = p0 − origin; t is the range along the unit 3-D direction.
      const double denom = cross(d, wall.e);
      if (std::abs(denom) < 1e-12 * wall.length_m) continue;  // parallel
      const Eigen::Vector2d w = wall.p0 - o;
      t = cross(w, wall.e) / denom;
      s = cross(w, d) / denom;
      cos_inc = std::abs(denom) / wall.length_m;
    } else {
      const double nd = wall.normal.dot(dir);
      if (std::abs(nd) < 1e-12) continue;
      t = (wall.offset - wall.normal.dot(origin)) / nd;
      const Eigen::Vector2d q = o + t * d;
      s = (q - wall.p0).dot(wall.e) / (wall.length_m * wall.length_m);
      cos_inc = std::abs(nd);
    }
    if (!(t > kMinT && s >= 0.0 && s <= 1.0)) continue;
    if (site_.has_ground) {
      const double above_foot_m = origin.z() + t * dir.z() - (wall.up0_m + s * (wall.up1_m - wall.up0_m));
      if (above_foot_m < -kEdgeM || above_foot_m > wall.height_m + kEdgeM) continue;
    }
    offer(t, cos_inc, wall_index, Surface::kWall);
  }
  // Round obstacles: upright cylinders without a top. For a horizontal beam |d| = 1 (as the 2-D
  // model took it); otherwise the quadratic's leading coefficient is |d|².
  const double a = dir.z() == 0.0 ? 1.0 : d.squaredNorm();
  for (const auto& [centre, radius] : circles_) {
    if (a <= 0.0) break;  // a vertical beam meets no upright surface
    const Eigen::Vector2d f = o - centre;
    const double half_b = f.dot(d);
    const double disc = half_b * half_b - a * (f.squaredNorm() - radius * radius);
    if (disc < 0.0) continue;
    const double root = std::sqrt(disc);
    double t = (-half_b - root) / a;
    if (t <= kMinT) t = (-half_b + root) / a;  // the scanner inside the obstacle: its far side
    if (t <= kMinT) continue;
    const Eigen::Vector2d normal = (o + t * d - centre) / radius;
    offer(t, std::abs(normal.dot(d)), -1, Surface::kObstacle);
  }
  if (site_.has_ground) {
    // g·q = 0 with g = (−slope·rise_dir, 1): the ground through the site origin.
    const Eigen::Vector3d g(-site_.slope * site_.rise_dir_enu.x(),
                            -site_.slope * site_.rise_dir_enu.y(), 1.0);
    const double gd = g.dot(dir);
    if (gd < 0.0) {
      const double t = -g.dot(origin) / gd;
      if (t > kMinT) offer(t, std::abs(gd) / g.norm(), -1, Surface::kGround);
    }
  }
  return best;
}

}  // namespace detail
}  // namespace wallcal::sim
