// SPDX-License-Identifier: Apache-2.0
#include "sim/synthetic_observations.h"

#include <cmath>
#include <string>

namespace wallcal::sim {
namespace {

calib::WallGeometry MakeWall(const std::string& id, const Eigen::Vector2d& a,
                             const Eigen::Vector2d& b, const SimSettings& s) {
  calib::WallGeometry wall;
  wall.id = id;
  const Eigen::Vector2d along = (b - a).normalized();
  wall.normal_local = Eigen::Vector2d(-along.y(), along.x());
  wall.offset_m = wall.normal_local.dot(a);
  wall.end_a_local = a;
  wall.end_b_local = b;
  wall.sigma_offset_m = s.wall_sigma_offset_m;
  wall.sigma_angle_rad = s.wall_sigma_angle_rad;
  wall.num_points = 20;
  return wall;
}

Eigen::Vector2d Rotate(double angle_rad, const Eigen::Vector2d& v) {
  const double c = std::cos(angle_rad);
  const double s = std::sin(angle_rad);
  return Eigen::Vector2d(c * v.x() - s * v.y(), s * v.x() + c * v.y());
}

}  // namespace

// Stations along the first wall (y = 10, x from −10 to 10), antenna 7.5-8.5 m from it, headings
// spread evenly over base ± half spread. The second wall runs north along x = 12.
SimData SimulateObservations(const SimSettings& s, std::mt19937& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  auto draw = [&](double sigma) { return s.noise ? sigma * unit(rng) : 0.0; };
  SimData data;
  data.walls.push_back(MakeWall("north", {-10.0, 10.0}, {10.0, 10.0}, s));
  data.walls.push_back(MakeWall("east", {12.0, -5.0}, {12.0, 15.0}, s));

  // The true walls: the surveyed ones moved by their (unknown) survey error.
  struct Line {
    Eigen::Vector2d n;
    double d;
  };
  std::vector<Line> true_walls;
  for (const auto& wall : data.walls) {
    const Eigen::Vector2d middle = 0.5 * (wall.end_a_local + wall.end_b_local);
    const Eigen::Vector2d centre =
        middle - (wall.normal_local.dot(middle) - wall.offset_m) * wall.normal_local;
    const Eigen::Vector2d n = Rotate(draw(wall.sigma_angle_rad), wall.normal_local);
    true_walls.push_back({n, n.dot(centre) + draw(wall.sigma_offset_m)});
  }

  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  int scan = 0;
  Eigen::Vector2d bias = Eigen::Vector2d::Zero();
  for (int k = 0; k < s.stations; ++k) {
    const double t = s.stations > 1 ? static_cast<double>(k) / (s.stations - 1) : 0.5;
    const double heading_true_rad = s.base_heading_rad + s.heading_half_spread_rad * (2 * t - 1);
    // Positions in a different order than headings, so the two are not tied.
    const double u =
        s.stations > 1 ? static_cast<double>((k * 7) % s.stations) / (s.stations - 1) : 0.5;
    const Eigen::Vector2d antenna_true(-4.0 + 8.0 * u, 1.5 + 0.5 * (k % 3));
    const Eigen::Vector2d fresh(draw(s.gnss_bias_sigma_m), draw(s.gnss_bias_sigma_m));
    if (k == 0 || !(s.bias_tau_s > 0.0)) {
      bias = fresh;
    } else {
      const double rho = std::exp(-s.station_spacing_s / s.bias_tau_s);
      bias = rho * bias + std::sqrt(1.0 - rho * rho) * fresh;
    }
    const double direction = s.alternate_direction && k % 2 == 1 ? -1.0 : 1.0;
    const double speed_mps = direction * s.speed_mps;
    const double yaw_rate_rps = direction * s.yaw_rate_rps;
    double dwell_yaw_rad = 0.0;
    if (s.dwell_heading_samples > 0) {
      double sum_rad = 0.0;
      for (int i = 0; i < s.dwell_heading_samples; ++i) sum_rad += draw(s.heading_sigma_rad);
      dwell_yaw_rad = heading_true_rad + sum_rad / s.dwell_heading_samples;
    }
    for (int j = 0; j < s.scans_per_station; ++j, ++scan) {
      // Recorded pose at the stamp t; the scan was taken at t + time_offset_s, when the vehicle
      // had moved on by v·dt and turned by ω·dt.
      const double dt_into_run_s = j * s.scan_period_s;
      const double recorded_heading_rad = heading_true_rad + yaw_rate_rps * dt_into_run_s;
      const Eigen::Vector2d recorded_antenna =
          antenna_true + speed_mps * dt_into_run_s *
                             Eigen::Vector2d(std::cos(heading_true_rad), std::sin(heading_true_rad));
      const double scan_heading_rad = recorded_heading_rad + yaw_rate_rps * s.time_offset_s;
      const Eigen::Vector2d scan_antenna =
          recorded_antenna + speed_mps * s.time_offset_s *
                                 Eigen::Vector2d(std::cos(heading_true_rad),
                                                 std::sin(heading_true_rad));
      const Eigen::Vector2d antenna_measured =
          recorded_antenna + bias +
          Eigen::Vector2d(draw(s.gnss_white_sigma_m), draw(s.gnss_white_sigma_m));
      const double heading_measured_rad = recorded_heading_rad + draw(s.heading_sigma_rad);
      const Eigen::Vector2d scanner_true =
          scan_antenna + Rotate(scan_heading_rad, {s.truth.x_m, s.truth.y_m});
      for (int w = 0; w < 2; ++w) {
        if ((w == 0 && !s.first_wall) || (w == 1 && !s.second_wall)) continue;
        // Orientation as the solver decides it: from the surveyed wall and the measured antenna.
        const double sign =
            data.walls[w].offset_m - data.walls[w].normal_local.dot(antenna_measured) < 0 ? -1.0
                                                                                          : 1.0;
        const Eigen::Vector2d n = sign * true_walls[w].n;
        const double d = sign * true_walls[w].d;
        calib::WallObservation o;
        o.scan_index = scan;
        o.wall_index = w;
        o.rho_m = d - n.dot(scanner_true) + draw(s.fit_sigma_rho_m);
        o.theta_rad = WrapAngle(std::atan2(n.y(), n.x()) - scan_heading_rad - s.truth.yaw_rad +
                                draw(s.fit_sigma_theta_rad));
        const bool outlier = uniform(rng) < s.outlier_fraction;
        if (outlier) o.rho_m += 0.5;
        o.sigma_rho_m = s.fit_sigma_rho_m;
        o.sigma_theta_rad = s.fit_sigma_theta_rad;
        o.num_inliers = 100;
        o.pose.stamp_s = 1000.0 + k * s.station_spacing_s + j * s.scan_period_s;
        if (s.dwell_heading_samples > 0) {
          o.pose.dwell_yaw_rad = dwell_yaw_rad;
          o.pose.dwell_yaw_samples = s.dwell_heading_samples;
          o.pose.dwell_mid_s =
              1000.0 + k * s.station_spacing_s + 0.5 * (s.scans_per_station - 1) * s.scan_period_s;
        }
        o.pose.antenna_local_m = antenna_measured;
        o.pose.yaw_rad = heading_measured_rad;
        o.pose.stationary = speed_mps == 0.0 && yaw_rate_rps == 0.0;
        o.pose.velocity_local_mps =
            speed_mps * Eigen::Vector2d(std::cos(heading_true_rad), std::sin(heading_true_rad));
        o.pose.yaw_rate_rps = yaw_rate_rps;
        o.pose.segment = k;
        data.observations.push_back(o);
        data.is_outlier.push_back(outlier);
      }
    }
  }
  return data;
}


}  // namespace wallcal::sim
