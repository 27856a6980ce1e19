// SPDX-License-Identifier: Apache-2.0
#include "bench/crb_site.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "bench/crb_interp.h"
#include "calib/site_geometry.h"
#include "common/angles.h"
#include "sim/simulator.h"
#include "sim/site_geometry.h"

namespace wallcal::bench {
namespace {

// The variance (rad²) of a wall's fitted lean: the slope of its points' offsets along the
// normal (total station σ each) against their heights.
double LeanVariance(const sim::SimulationConfig& config, const sim::SimWall& wall) {
  const std::vector<double> heights = sim::SurveyHeightsM(wall, config.survey_mode);
  const double stations = static_cast<double>(sim::SurveyStationsAlong(wall).size());
  double mean_m = 0.0;
  for (double h : heights) mean_m += h / static_cast<double>(heights.size());
  double spread_m2 = 0.0;
  for (double h : heights) spread_m2 += stations * (h - mean_m) * (h - mean_m);
  if (!(spread_m2 > 0.0)) return 0.0;
  const double sigma_m = config.survey_mode == sim::SurveyMode::kRover ? config.rover_sigma_m
                                                                       : config.total_station_sigma_m;
  return sigma_m * sigma_m / spread_m2;
}

// The mean of a wall's survey heights above the ground under its centre (m, ENU up): the
// height its surveyed line stands for.
double WallReferenceUpM(const sim::SimulationConfig& config, const sim::Site& site,
                        const sim::SimWall& wall) {
  const std::vector<double> heights = sim::SurveyHeightsM(wall, config.survey_mode);
  double mean_m = 0.0;
  for (double h : heights) mean_m += h / static_cast<double>(heights.size());
  const Eigen::Vector2d centre(0.5 * (wall.x0_m + wall.x1_m), 0.5 * (wall.y0_m + wall.y1_m));
  return (site.has_ground ? site.GroundUpM(centre) : 0.0) + mean_m;
}

// d(rho, theta)/d(one nuisance) by central differences of `line(±step)`.
template <typename Line>
Eigen::Vector2d Derivative(const Line& line, double step) {
  const Eigen::Vector2d plus = line(step), minus = line(-step);
  return Eigen::Vector2d((plus.x() - minus.x()) / (2.0 * step),
                         WrapAngle(plus.y() - minus.y()) / (2.0 * step));
}

// What the covariance needs of one row.
struct SiteRow {
  Eigen::Matrix2d d_grade = Eigen::Matrix2d::Zero();     // columns: grade along ENU x, y
  Eigen::Matrix2d d_attitude = Eigen::Matrix2d::Zero();  // columns: roll, pitch
  Eigen::Vector2d d_lean = Eigen::Vector2d::Zero();
  Interp attitude;
  int config_wall = 0;
};

}  // namespace

Eigen::Matrix2d YardGradeCovariance(const sim::SimulationConfig& config) {
  if (!config.IsThreeDSite() || !(config.gnss_rate_hz > 0.0)) return Eigen::Matrix2d::Zero();
  const double duration_s = sim::RunDurationS(config);
  const int64_t epochs = static_cast<int64_t>(std::floor(duration_s * config.gnss_rate_hz + 1e-9)) + 1;
  const int64_t stride = std::max<int64_t>(1, (epochs + kMaxYardEpochs - 1) / kMaxYardEpochs);
  std::vector<double> times;
  for (int64_t j = 0; j < epochs; j += stride) times.push_back(j / config.gnss_rate_hz);
  const std::vector<sim::SimTruthPose> poses = sim::TruePosesAt(config, times);
  const int m = static_cast<int>(poses.size());
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const sim::SimTruthPose& p : poses) centre += p.antenna_enu_m / m;
  const double factor = config.GnssVerticalFactor();
  const double var_bias_m2 = std::pow(factor * config.gnss_bias_sigma_m, 2);
  // Each kept epoch stands for `stride` epochs of white noise: its mean's variance.
  const double var_white_m2 = std::pow(factor * config.gnss_white_sigma_m, 2) / stride;
  Eigen::MatrixXd design(m, 3);
  Eigen::MatrixXd covariance(m, m);
  for (int a = 0; a < m; ++a) {
    design.row(a) << 1.0, poses[a].antenna_enu_m.x() - centre.x(),
        poses[a].antenna_enu_m.y() - centre.y();
    for (int b = a; b < m; ++b) {
      const double dt_s = std::abs(times[a] - times[b]);
      double c = config.gnss_bias_tau_s > 0.0 ? var_bias_m2 * std::exp(-dt_s / config.gnss_bias_tau_s)
                                              : (a == b ? var_bias_m2 : 0.0);
      if (a == b) c += var_white_m2;
      covariance(a, b) = covariance(b, a) = c;
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(covariance);
  const Eigen::Matrix3d information = design.transpose() * ldlt.solve(design);
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(information);
  if (!lu.isInvertible()) return Eigen::Matrix2d::Zero();
  return lu.inverse().bottomRightCorner<2, 2>();
}

Eigen::MatrixXd SiteLineCovariance(const std::vector<sim::SimulationConfig>& scanner_configs,
                                   const std::vector<SiteRowInput>& rows) {
  const int n = static_cast<int>(rows.size());
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  const sim::SimulationConfig& config = scanner_configs.front();
  if (!config.IsThreeDSite() || n == 0) return covariance;
  const sim::Site site = sim::SiteOf(config);
  const bool stream = config.attitude_rate_hz > 0.0;
  const Eigen::Matrix2d grade_covariance = stream ? Eigen::Matrix2d::Zero()
                                                  : YardGradeCovariance(config);
  const Eigen::Vector2d grade = site.slope * site.rise_dir_enu;
  std::vector<double> lean_variance(config.walls.size(), 0.0);
  for (size_t w = 0; w < config.walls.size(); ++w) {
    if (config.walls[w].LeanRad() != 0.0) lean_variance[w] = LeanVariance(config, config.walls[w]);
  }

  std::vector<double> times;
  for (const SiteRowInput& r : rows) times.push_back(r.t_s);
  const std::vector<sim::SimTruthPose> poses = sim::TruePosesAt(config, times);
  constexpr double kAngleStep = 1e-6;  // rad (and grade, m/m)
  std::vector<SiteRow> site_rows(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const SiteRowInput& in = rows[i];
    const sim::SimulationConfig& own = scanner_configs[static_cast<size_t>(in.scanner)];
    const sim::SimWall& sim_wall = config.walls[static_cast<size_t>(in.config_wall)];
    calib::VehiclePose pose;
    pose.antenna_local_m = poses[i].antenna_enu_m;
    pose.yaw_rad = poses[i].yaw_enu_rad;
    const calib::Mount mount{own.mount_x_m, own.mount_y_m, own.mount_yaw_rad};
    const calib::ScannerPlacement placement{own.MountZM(), own.scanner_pitch_rad,
                                            own.scanner_roll_rad};
    calib::WallGeometry wall;
    wall.normal_local = Eigen::Vector2d(std::cos(in.wall_angle_rad), std::sin(in.wall_angle_rad));
    wall.offset_m = in.wall_offset_m;
    wall.lean_rad = sim_wall.LeanRad();
    calib::Heights heights;
    heights.antenna_m = poses[i].antenna_up_m;
    heights.wall_reference_m = WallReferenceUpM(config, site, sim_wall);
    const calib::Attitude truth{poses[i].roll_rad, poses[i].pitch_rad};
    auto line = [&](const calib::Attitude& attitude, const calib::WallGeometry& w) {
      return calib::PredictLine3d(pose, pose.yaw_rad, attitude, mount, placement, w, in.sign,
                                  heights);
    };
    SiteRow& row = site_rows[static_cast<size_t>(i)];
    row.config_wall = in.config_wall;
    row.d_attitude.col(0) = Derivative(
        [&](double e) { return line({truth.roll_rad + e, truth.pitch_rad}, wall); }, kAngleStep);
    row.d_attitude.col(1) = Derivative(
        [&](double e) { return line({truth.roll_rad, truth.pitch_rad + e}, wall); }, kAngleStep);
    for (int k = 0; k < 2; ++k) {
      row.d_grade.col(k) = Derivative(
          [&](double e) {
            return line(calib::AttitudeOnGround(grade + e * Eigen::Vector2d::Unit(k), pose.yaw_rad),
                        wall);
          },
          kAngleStep);
    }
    row.d_lean = Derivative(
        [&](double e) {
          calib::WallGeometry leaned = wall;
          leaned.lean_rad += e;
          return line(truth, leaned);
        },
        kAngleStep);
    if (stream) row.attitude = Weights(in.t_s, config.attitude_rate_hz);
  }

  const double var_attitude = std::pow(config.attitude_white_sigma_rad, 2);
  for (int a = 0; a < n; ++a) {
    const SiteRow& ra = site_rows[static_cast<size_t>(a)];
    for (int b = a; b < n; ++b) {
      const SiteRow& rb = site_rows[static_cast<size_t>(b)];
      Eigen::Matrix2d block = ra.d_grade * grade_covariance * rb.d_grade.transpose();
      if (stream) {
        const double shared = var_attitude * Overlap(ra.attitude, rb.attitude);
        if (shared != 0.0) block += shared * ra.d_attitude * rb.d_attitude.transpose();
      }
      if (ra.config_wall == rb.config_wall) {
        block += lean_variance[static_cast<size_t>(ra.config_wall)] * ra.d_lean *
                 rb.d_lean.transpose();
      }
      covariance.block<2, 2>(2 * a, 2 * b) = block;
      covariance.block<2, 2>(2 * b, 2 * a) = block.transpose();
    }
  }
  return covariance;
}

}  // namespace wallcal::bench
