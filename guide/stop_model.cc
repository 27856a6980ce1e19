// SPDX-License-Identifier: Apache-2.0
#include "guide/stop_model.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "common/angles.h"

namespace wallcal::guide {
namespace {

Eigen::Vector2d WallCentre(const calib::WallGeometry& wall) {
  // As solvers/mount_problem.cc: the middle of the surveyed extent, projected onto the line.
  const Eigen::Vector2d middle = 0.5 * (wall.end_a_local + wall.end_b_local);
  return middle - (wall.normal_local.dot(middle) - wall.offset_m) * wall.normal_local;
}

Eigen::Matrix2d Rotation(double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

}  // namespace

bool ModelLineFit(const StopModel& model, const calib::WallGeometry& wall,
                  const Eigen::Vector2d& scanner_local_m, double scanner_yaw_rad,
                  LineFitModel* fit) {
  const io::ScannerPreset& preset = model.preset;
  const Eigen::Vector2d along = Eigen::Vector2d(-wall.normal_local.y(), wall.normal_local.x());
  const double s_a = along.dot(wall.end_a_local), s_b = along.dot(wall.end_b_local);
  const double s_lo = std::min(s_a, s_b), s_hi = std::max(s_a, s_b);
  const double side =
      (wall.offset_m - wall.normal_local.dot(scanner_local_m)) >= 0.0 ? 1.0 : -1.0;
  const Eigen::Vector2d normal = side * wall.normal_local;  // towards the wall
  const double rho = side * (wall.offset_m - wall.normal_local.dot(scanner_local_m));
  if (!(rho > 0.0)) return false;
  const double normal_angle = std::atan2(normal.y(), normal.x());
  const double sigma_range = std::max(preset.range_sigma_m, 1e-4);
  Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
  int beams = 0;
  double range_min = 1e300, range_max = 0.0;
  for (int i = 0; i < preset.num_beams; ++i) {
    const double bearing_local =
        scanner_yaw_rad + preset.start_angle_rad + i * preset.angular_step_rad;
    const double incidence = WrapAngle(bearing_local - normal_angle);
    if (std::abs(incidence) >= std::min(preset.max_incidence_rad, 0.5 * kPi - 1e-3)) continue;
    const double range = rho / std::cos(incidence);
    if (range <= preset.min_range_m || range >= preset.max_range_m) continue;
    const Eigen::Vector2d hit =
        scanner_local_m + range * Eigen::Vector2d(std::cos(bearing_local), std::sin(bearing_local));
    const double s = along.dot(hit);
    if (s < s_lo || s > s_hi) continue;
    // The point's error along the normal: the range error seen at this incidence.
    const double sigma_normal = sigma_range * std::cos(incidence);
    const double w = 1.0 / (sigma_normal * sigma_normal);
    const double place = range * std::sin(incidence);  // along the line from the foot point
    information(0, 0) += w;
    information(0, 1) -= w * place;
    information(1, 1) += w * place * place;
    ++beams;
    range_min = std::min(range_min, range);
    range_max = std::max(range_max, range);
  }
  if (beams < 5) return false;
  information(1, 0) = information(0, 1);
  const Eigen::Matrix2d covariance = information.inverse();
  fit->beams = beams;
  fit->sigma_rho_m = std::sqrt(covariance(0, 0));
  fit->sigma_theta_rad = std::sqrt(covariance(1, 1));
  fit->cov_rho_theta = covariance(0, 1);
  fit->range_min_m = range_min;
  fit->range_max_m = range_max;
  return std::isfinite(fit->sigma_rho_m) && std::isfinite(fit->sigma_theta_rad);
}

bool StopPose(const StopModel& model, const StopSpec& stop, SitePose* pose) {
  if (stop.wall_index < 0 || stop.wall_index >= static_cast<int>(model.walls.size())) return false;
  const calib::WallGeometry& wall = model.walls[stop.wall_index];
  const double side = stop.wall_index < static_cast<int>(model.side.size())
                          ? model.side[stop.wall_index]
                          : 1.0;
  const Eigen::Vector2d normal = side * wall.normal_local;  // towards the wall
  const double normal_angle = std::atan2(normal.y(), normal.x());
  pose->yaw_rad = WrapAngle(normal_angle - stop.vehicle_to_wall_rad);  // ψ
  const Eigen::Vector2d lever(model.mount.x_m, model.mount.y_m);
  // The scanner abreast of the wall's centre: the antenna where that puts it.
  const Eigen::Vector2d lever_local = Rotation(pose->yaw_rad) * lever;
  const Eigen::Vector2d along(-wall.normal_local.y(), wall.normal_local.x());
  pose->antenna_local_m =
      WallCentre(wall) - normal * stop.distance_m - along * along.dot(lever_local);
  return true;
}

bool AppendStopObservations(const StopModel& model, const StopSpec& stop, double start_s,
                            int station_id, std::vector<calib::WallObservation>* observations,
                            std::vector<double>* weights) {
  SitePose placed;
  if (!StopPose(model, stop, &placed)) return false;
  const calib::WallGeometry& wall = model.walls[stop.wall_index];
  const double side = stop.wall_index < static_cast<int>(model.side.size())
                          ? model.side[stop.wall_index]
                          : 1.0;
  const Eigen::Vector2d normal = side * wall.normal_local;  // towards the wall
  const double normal_angle = std::atan2(normal.y(), normal.x());
  const double yaw_rad = placed.yaw_rad;
  const Eigen::Vector2d lever(model.mount.x_m, model.mount.y_m);
  const Eigen::Vector2d centre = WallCentre(wall);
  const Eigen::Vector2d antenna = placed.antenna_local_m;

  const double mid_s = start_s + 0.5 * stop.dwell_s;
  const double drift_yaw = model.heading_drift_rad_per_s * (mid_s - model.heading_reference_s);
  const double true_yaw = yaw_rad - drift_yaw;  // ψ' = ψ − r·τ (no heading offset, no bias)
  const Eigen::Vector2d scanner = antenna + Rotation(true_yaw) * lever;
  const double scanner_yaw = true_yaw + model.mount.yaw_rad;

  LineFitModel fit;
  if (!ModelLineFit(model, wall, scanner, scanner_yaw, &fit)) return false;

  // The wall as the solution has it: turned by δα about its centre, shifted by δd.
  double delta_d = 0.0, delta_alpha = 0.0;
  if (stop.wall_index < static_cast<int>(model.wall_deltas.size())) {
    delta_d = model.wall_deltas[stop.wall_index][0];
    delta_alpha = model.wall_deltas[stop.wall_index][1];
  }
  const Eigen::Vector2d turned = Rotation(delta_alpha) * wall.normal_local;
  const double offset = turned.dot(centre) + delta_d;
  const double rho = side * (offset - turned.dot(scanner));
  const double theta = WrapAngle(normal_angle + delta_alpha - true_yaw - model.mount.yaw_rad);
  if (!(rho > 0.0)) return false;

  const double rate = model.scan_rate_hz > 0.0 ? model.scan_rate_hz : model.preset.rate_hz;
  const double t0 = start_s + model.dwell_guard_s, t1 = start_s + stop.dwell_s - model.dwell_guard_s;
  if (!(t1 > t0) || !(rate > 0.0) || !(model.slice_s > 0.0)) return false;
  const int heading_samples =
      std::max(1, static_cast<int>(std::lround(model.heading_rate_hz * stop.dwell_s)));
  const size_t before = observations->size();
  const long first_slice = static_cast<long>(std::floor((t0 - model.slice_start_s) / model.slice_s));
  const long last_slice = static_cast<long>(std::floor((t1 - model.slice_start_s) / model.slice_s));
  for (long k = first_slice; k <= last_slice; ++k) {
    const double a = std::max(t0, model.slice_start_s + k * model.slice_s);
    const double b = std::min(t1, model.slice_start_s + (k + 1) * model.slice_s);
    const double scans = (b - a) * rate;
    if (scans < 0.5) continue;
    calib::WallObservation o;
    o.scan_index = -1;
    o.wall_index = stop.wall_index;
    o.rho_m = rho;
    o.theta_rad = theta;
    o.sigma_rho_m = fit.sigma_rho_m * model.fit_scale;
    o.sigma_theta_rad = fit.sigma_theta_rad * model.fit_scale;
    o.cov_rho_theta = fit.cov_rho_theta * model.fit_scale * model.fit_scale;
    o.num_inliers = fit.beams;
    o.range_min_m = fit.range_min_m;
    o.range_max_m = fit.range_max_m;
    o.pose.stamp_s = 0.5 * (a + b);
    o.pose.antenna_local_m = antenna;
    o.pose.yaw_rad = yaw_rad;
    o.pose.gnss_sigma_m = model.gnss_sigma_m;
    o.pose.stationary = true;
    o.pose.segment = station_id;
    o.pose.gnss_segment = static_cast<int>(k);
    o.pose.gnss_period_s = model.gnss_period_s;
    o.pose.dwell_yaw_rad = yaw_rad;
    o.pose.dwell_yaw_samples = heading_samples;
    o.pose.dwell_mid_s = mid_s;
    observations->push_back(o);
    weights->push_back(scans);
  }
  return observations->size() > before;
}

bool AppendWaitAndStop(const StopModel& model, const StopSpec* previous, const StopSpec& stop,
                       double wait_start_s, int* next_station_id,
                       std::vector<calib::WallObservation>* observations,
                       std::vector<double>* weights) {
  std::vector<calib::WallObservation> added;
  std::vector<double> added_weights;
  if (!AppendStopObservations(model, stop, wait_start_s + stop.wait_s, *next_station_id + 1,
                              &added, &added_weights)) {
    return false;
  }
  if (previous != nullptr && stop.wait_s > kDriveS + 2.0 * model.dwell_guard_s) {
    StopSpec standing = *previous;
    standing.dwell_s = stop.wait_s - kDriveS;
    AppendStopObservations(model, standing, wait_start_s, *next_station_id, observations, weights);
  }
  observations->insert(observations->end(), added.begin(), added.end());
  weights->insert(weights->end(), added_weights.begin(), added_weights.end());
  *next_station_id += 2;
  return true;
}

}  // namespace wallcal::guide
