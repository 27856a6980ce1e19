// SPDX-License-Identifier: Apache-2.0
#include "bench/crb.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "bench/crb_interp.h"
#include "bench/crb_site.h"
#include "sim/simulator.h"

namespace wallcal::bench {
namespace {

Eigen::Matrix2d Rotation(double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

const Eigen::Matrix2d kQuarterTurn = Rotation(0.5 * 3.14159265358979323846);

// ---- Survey: the wall lines as a function of the survey noise -------------------------------
// The same set-up as sim::Simulate (control points C1, C2 2 m in front of the first surveyed
// wall at 5 % and 95 % of it; wall points every survey_spacing_m, two heights each) and the
// same estimation as calibrate (calib/survey_tie.cc: rigid two-point tie, total least squares
// per wall), so that the numerical Jacobian of the lines with respect to the noise is the
// linear propagation of the survey's errors.
struct SurveyModel {
  bool rover = false;  // survey_mode rover: the points in the GNSS frame, no control, no tie
  Eigen::Vector2d frame_origin_enu_m;
  double frame_rotation_rad = 0.0;
  std::vector<Eigen::Vector2d> control_enu_m;              // true positions
  std::vector<std::vector<Eigen::Vector2d>> wall_points_enu_m;  // per surveyed wall, true
  // Noise vector layout: [total station on control (2 each), RTK on control (2 each),
  // total station on every wall point (2 each)].
  int NoiseSize() const {
    int n = 4 * static_cast<int>(control_enu_m.size());
    for (const auto& w : wall_points_enu_m) n += 2 * static_cast<int>(w.size());
    return n;
  }
};

// A rover's wall points: one at the foot of the wall every survey_spacing_m, in the GNSS frame.
SurveyModel MakeRoverSurveyModel(const sim::SimulationConfig& config) {
  SurveyModel model;
  model.rover = true;
  model.frame_origin_enu_m.setZero();
  for (const auto& w : config.walls) {
    if (w.code.empty()) continue;
    const Eigen::Vector2d w0(w.x0_m, w.y0_m), w1(w.x1_m, w.y1_m);
    const double length_m = (w1 - w0).norm();
    const double spacing_m = w.survey_spacing_m > 0.0 ? w.survey_spacing_m : 1.0;
    const int steps = static_cast<int>(std::floor(length_m / spacing_m + 1e-9));
    std::vector<Eigen::Vector2d> points;
    for (int k = 0; k <= steps; ++k) points.push_back(w0 + (k * spacing_m / length_m) * (w1 - w0));
    model.wall_points_enu_m.push_back(points);
  }
  return model;
}

SurveyModel MakeSurveyModel(const sim::SimulationConfig& config) {
  if (config.survey_mode == sim::SurveyMode::kRover) return MakeRoverSurveyModel(config);
  SurveyModel model;
  model.frame_origin_enu_m = {config.survey_origin_x_m, config.survey_origin_y_m};
  model.frame_rotation_rad = config.survey_rotation_rad;
  const sim::SimWall* first = nullptr;
  for (const auto& w : config.walls) {
    if (w.code.empty()) continue;
    if (first == nullptr) first = &w;
    const Eigen::Vector2d w0(w.x0_m, w.y0_m), w1(w.x1_m, w.y1_m);
    const double length_m = (w1 - w0).norm();
    const double spacing_m = w.survey_spacing_m > 0.0 ? w.survey_spacing_m : 1.0;
    const int steps = static_cast<int>(std::floor(length_m / spacing_m + 1e-9));
    std::vector<Eigen::Vector2d> points;
    for (int k = 0; k <= steps; ++k) {
      const Eigen::Vector2d p = w0 + (k * spacing_m / length_m) * (w1 - w0);
      points.push_back(p);  // two heights: two independent measurements of the same x, y
      points.push_back(p);
    }
    model.wall_points_enu_m.push_back(points);
  }
  const Eigen::Vector2d a(first->x0_m, first->y0_m), b(first->x1_m, first->y1_m);
  const Eigen::Vector2d along = (b - a).normalized();
  Eigen::Vector2d out(-along.y(), along.x());
  if (-out.dot(a) < 0.0) out = -out;
  for (double f : {0.05, 0.95}) model.control_enu_m.push_back(a + f * (b - a) + 2.0 * out);
  return model;
}

// [α_0, d_0, α_1, d_1, ...]: wall w is {q : (cos α_w, sin α_w) · q = d_w} (local ENU), its
// normal oriented as calib::FitWalls orients it (direction first -> last point, turned +90°).
Eigen::VectorXd WallLines(const SurveyModel& model, const Eigen::VectorXd& noise) {
  const Eigen::Matrix2d to_station = Rotation(-model.frame_rotation_rad);
  auto station = [&](const Eigen::Vector2d& p_enu) {
    return Eigen::Vector2d(to_station * (p_enu - model.frame_origin_enu_m));
  };
  const int nc = static_cast<int>(model.control_enu_m.size());
  int at = 0;
  std::vector<Eigen::Vector2d> a(nc), b(nc);
  for (int i = 0; i < nc; ++i, at += 2) a[i] = station(model.control_enu_m[i]) + noise.segment<2>(at);
  for (int i = 0; i < nc; ++i, at += 2) b[i] = model.control_enu_m[i] + noise.segment<2>(at);
  Eigen::Vector2d a_mean = Eigen::Vector2d::Zero(), b_mean = Eigen::Vector2d::Zero();
  for (int i = 0; i < nc; ++i) {
    a_mean += a[i] / nc;
    b_mean += b[i] / nc;
  }
  double sum_dot = 0.0, sum_cross = 0.0;
  for (int i = 0; i < nc; ++i) {
    const Eigen::Vector2d u = a[i] - a_mean, v = b[i] - b_mean;
    sum_dot += u.dot(v);
    sum_cross += u.x() * v.y() - u.y() * v.x();
  }
  Eigen::Matrix2d R = Rotation(std::atan2(sum_cross, sum_dot));
  Eigen::Vector2d t = b_mean - R * a_mean;
  if (model.rover) {  // no tie: the points are in the GNSS frame
    R.setIdentity();
    t.setZero();
  }

  Eigen::VectorXd lines(2 * model.wall_points_enu_m.size());
  for (size_t w = 0; w < model.wall_points_enu_m.size(); ++w) {
    const auto& truth = model.wall_points_enu_m[w];
    std::vector<Eigen::Vector2d> p(truth.size());
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < truth.size(); ++i, at += 2) {
      p[i] = R * (station(truth[i]) + noise.segment<2>(at)) + t;
      centroid += p[i];
    }
    centroid /= static_cast<double>(p.size());
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const auto& q : p) scatter += (q - centroid) * (q - centroid).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(scatter);
    Eigen::Vector2d direction = eigen.eigenvectors().col(1);
    if (direction.dot(p.back() - p.front()) < 0.0) direction = -direction;
    const Eigen::Vector2d normal(-direction.y(), direction.x());
    lines[2 * w] = std::atan2(normal.y(), normal.x());
    lines[2 * w + 1] = normal.dot(centroid);
  }
  return lines;
}

// Covariance of WallLines from the noise σs, by central differences (the map is smooth and
// nearly linear at the centimetre scale).
Eigen::MatrixXd WallLineCovariance(const SurveyModel& model, const sim::SimulationConfig& config,
                                   Eigen::VectorXd* truth) {
  const int n = model.NoiseSize();
  const int nc = static_cast<int>(model.control_enu_m.size());
  Eigen::VectorXd sigma(n);
  sigma.setConstant(model.rover ? config.rover_sigma_m : config.total_station_sigma_m);
  sigma.segment(2 * nc, 2 * nc).setConstant(config.control_sigma_m);
  *truth = WallLines(model, Eigen::VectorXd::Zero(n));
  const int m = static_cast<int>(truth->size());
  Eigen::MatrixXd jacobian(m, n);
  constexpr double kStepM = 1e-5;
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd plus = Eigen::VectorXd::Zero(n), minus = Eigen::VectorXd::Zero(n);
    plus[j] = kStepM;
    minus[j] = -kStepM;
    Eigen::VectorXd diff = WallLines(model, plus) - WallLines(model, minus);
    for (int r = 0; r < m; r += 2) diff[r] = std::remainder(diff[r], 2.0 * 3.14159265358979323846);
    jacobian.col(j) = diff / (2.0 * kStepM);
  }
  return jacobian * sigma.array().square().matrix().asDiagonal() * jacobian.transpose();
}

// Everything per observation that C and J need.
struct Row {
  int scanner = 0;
  double t_s = 0.0;
  int wall = 0;  // surveyed wall index
  Eigen::Vector2d n = Eigen::Vector2d::Zero();  // oriented normal (scanner -> wall), ENU
  double sign = 1.0;                             // n = sign · (cos α_w, sin α_w)
  Eigen::Vector2d scanner_enu_m = Eigen::Vector2d::Zero();
  Eigen::Matrix2d fit_cov = Eigen::Matrix2d::Zero();
  // d(rho, theta) per unit of the scanner's range offset (m) and of its relative scale error.
  Eigen::Matrix2d unit_gain = Eigen::Matrix2d::Zero();
  // x, y, yaw, then the pose's time shifts: the position part (antenna velocity) and the
  // heading part (yaw rate, through the lever arm too) of d(rho, theta)/d(time). A scanner
  // clock offset moves both, a GNSS delay the first, a heading delay the second.
  Eigen::Matrix<double, 2, 3> J = Eigen::Matrix<double, 2, 3>::Zero();
  Eigen::Vector2d J_position_time = Eigen::Vector2d::Zero();
  Eigen::Vector2d J_heading_time = Eigen::Vector2d::Zero();
  double n_dot_v = 0.0;   // n · antenna velocity (m/s)
  double yaw_rate = 0.0;  // rad/s
  Eigen::Vector2d B = Eigen::Vector2d::Zero();       // d(rho, theta)/d heading error
  Eigen::Matrix2d W = Eigen::Matrix2d::Zero();       // d(rho, theta)/d(α_w, d_w)
  Interp gnss, heading;
  bool has_residual = false;
  Eigen::Vector2d residual = Eigen::Vector2d::Zero();
};

}  // namespace

CrbResult ComputeCrb(const sim::SimulationConfig& config, const io::ScannerPreset& preset,
                     const std::vector<CrbObservation>& observations, unsigned sources,
                     const CrbDelays& delays, int max_observations) {
  return ComputeJointCrb({config}, preset, observations, sources, delays, max_observations);
}

CrbResult ComputeJointCrb(const std::vector<sim::SimulationConfig>& scanner_configs,
                          const io::ScannerPreset& preset,
                          const std::vector<CrbObservation>& observations, unsigned sources,
                          const CrbDelays& delays, int max_observations) {
  const sim::SimulationConfig& config = scanner_configs.front();  // the vehicle's noise
  const int scanners = static_cast<int>(scanner_configs.size());
  CrbResult result;
  result.observations_given = static_cast<int>(observations.size());
  if (observations.empty()) {
    result.message = "no observations";
    return result;
  }
  std::vector<CrbObservation> obs = observations;
  std::sort(obs.begin(), obs.end(), [](const CrbObservation& a, const CrbObservation& b) {
    return a.t_s < b.t_s || (a.t_s == b.t_s && (a.scanner < b.scanner ||
                                                 (a.scanner == b.scanner &&
                                                  a.surveyed_wall < b.surveyed_wall)));
  });
  if (max_observations > 0 && static_cast<int>(obs.size()) > max_observations) {
    // Evenly by scan: every wall line of a kept scan time is kept (a stride over the lines
    // would keep one wall's lines only when each scan sees two).
    std::vector<size_t> scan_start;  // first line of each distinct time
    for (size_t i = 0; i < obs.size(); ++i) {
      if (i == 0 || obs[i].t_s != obs[i - 1].t_s) scan_start.push_back(i);
    }
    const double lines_per_scan = static_cast<double>(obs.size()) / scan_start.size();
    const size_t keep_scans = std::max<size_t>(
        1, static_cast<size_t>(std::floor(max_observations / lines_per_scan)));
    std::vector<CrbObservation> kept;
    const double stride = static_cast<double>(scan_start.size()) / keep_scans;
    for (size_t k = 0; k < keep_scans && k < scan_start.size(); ++k) {
      const size_t s = scan_start[static_cast<size_t>(k * stride)];
      for (size_t i = s; i < obs.size() && obs[i].t_s == obs[s].t_s; ++i) kept.push_back(obs[i]);
    }
    obs = kept;
    result.subsampled = true;
  }

  std::vector<int> config_wall_of;  // surveyed index -> config.walls index
  for (size_t i = 0; i < config.walls.size(); ++i) {
    if (!config.walls[i].code.empty()) config_wall_of.push_back(static_cast<int>(i));
  }
  const SurveyModel survey = MakeSurveyModel(config);
  Eigen::VectorXd lines;
  const Eigen::MatrixXd wall_cov = WallLineCovariance(survey, config, &lines);

  // Range noise after calibrate's correction (corrected = k · raw + b): the simulator's ξ and
  // the quantisation (uniform over one resolution step), both scaled by k.
  const double k = preset.range_scale_k;
  const double range_var_m2 =
      k * k * (preset.range_sigma_m * preset.range_sigma_m +
               preset.range_resolution_m * preset.range_resolution_m / 12.0);
  constexpr double kMinRangeM = 0.5;  // calib::DetectorOptions::min_range_m default

  std::vector<double> times;
  for (const auto& o : obs) times.push_back(o.t_s);
  std::vector<double> before, after;
  constexpr double kDt = 0.01;
  for (double t : times) {
    before.push_back(t - kDt);
    after.push_back(t + kDt);
  }
  const auto poses = sim::TruePosesAt(config, times);
  const auto poses_before = sim::TruePosesAt(config, before);
  const auto poses_after = sim::TruePosesAt(config, after);
  std::vector<Row> rows;
  for (size_t i = 0; i < obs.size(); ++i) {
    if (obs[i].scanner < 0 || obs[i].scanner >= scanners) continue;
    const sim::SimulationConfig& own = scanner_configs[static_cast<size_t>(obs[i].scanner)];
    const Eigen::Vector2d lever(own.mount_x_m, own.mount_y_m);
    Row row;
    row.scanner = obs[i].scanner;
    row.t_s = obs[i].t_s;
    row.wall = obs[i].surveyed_wall;
    if (row.wall < 0 || row.wall >= static_cast<int>(config_wall_of.size())) continue;
    const double alpha = lines[2 * row.wall], offset = lines[2 * row.wall + 1];
    const Eigen::Vector2d n_wall(std::cos(alpha), std::sin(alpha));
    const double psi = poses[i].yaw_enu_rad;
    const Eigen::Matrix2d R = Rotation(psi);
    row.scanner_enu_m = poses[i].antenna_enu_m + R * lever;
    row.sign = offset - n_wall.dot(row.scanner_enu_m) >= 0.0 ? 1.0 : -1.0;
    row.n = row.sign * n_wall;
    const double theta = std::atan2(row.n.y(), row.n.x()) - psi - own.mount_yaw_rad;

    // Line fit information from the beams on this wall.
    const auto hits = sim::TrueBeamHits(own, preset, poses[i]);
    Eigen::Matrix2d info = Eigen::Matrix2d::Zero();
    Eigen::Vector2d offset_pull = Eigen::Vector2d::Zero();  // Σ w g cos: an offset's pull
    int beams = 0;
    const Eigen::Vector2d n_s(std::cos(theta), std::sin(theta));
    const Eigen::Vector2d along_s(-std::sin(theta), std::cos(theta));
    for (const auto& h : hits) {
      if (!h.returned || h.footprint_edge || h.wall_index != config_wall_of[row.wall] ||
          h.range_m < kMinRangeM) {
        continue;
      }
      const Eigen::Vector2d u(std::cos(h.bearing_rad), std::sin(h.bearing_rad));
      const double cos_inc = n_s.dot(u);
      const Eigen::Vector2d g(-1.0, along_s.dot(h.range_m * u));
      info += g * g.transpose() / (range_var_m2 * cos_inc * cos_inc);
      // A range offset δb moves the point δb·cos_inc off the line along its normal.
      offset_pull += g / (range_var_m2 * cos_inc);
      ++beams;
    }
    if (beams < 2) continue;
    row.fit_cov = info.inverse();
    const double rho_m = row.sign * (offset - n_wall.dot(row.scanner_enu_m));
    row.unit_gain.col(0) = -row.fit_cov * offset_pull;
    row.unit_gain.col(1) = Eigen::Vector2d(rho_m, 0.0);

    // Mount Jacobian: rho = d − n·(a + R m), theta = angle(n) − ψ − yaw.
    row.J.block<1, 2>(0, 0) = -row.n.transpose() * R;
    row.J(1, 2) = -1.0;
    // Heading error turns the lever arm and the scanner.
    row.B << -row.n.dot(kQuarterTurn * R * lever), -1.0;
    // The pose at t + δ: the antenna moves by v δ (d rho = −n·v δ), the yaw by ψ̇ δ (through
    // B). A scanner clock offset is both; a GNSS or heading delay one of them.
    const Eigen::Vector2d velocity =
        (poses_after[i].antenna_enu_m - poses_before[i].antenna_enu_m) / (2.0 * kDt);
    row.yaw_rate = (poses_after[i].yaw_enu_rad - poses_before[i].yaw_enu_rad) / (2.0 * kDt);
    row.n_dot_v = row.n.dot(velocity);
    row.J_position_time << -row.n_dot_v, 0.0;
    row.J_heading_time = row.B * row.yaw_rate;
    // Wall line: rho = sign·(d_w − n_w·s), theta = angle(sign·n_w) − φ.
    const Eigen::Vector2d n_wall_turned(-std::sin(alpha), std::cos(alpha));
    row.W << -row.sign * n_wall_turned.dot(row.scanner_enu_m), row.sign, 1.0, 0.0;
    row.gnss = Weights(row.t_s, config.gnss_rate_hz);
    row.heading = Weights(row.t_s, config.heading_rate_hz);
    row.has_residual = obs[i].has_residual;
    row.residual = obs[i].residual;
    rows.push_back(row);
  }
  const int n = static_cast<int>(rows.size());
  result.observations_used = n;
  if (n < 3) {
    result.message = "fewer than 3 observations with a wall line";
    return result;
  }

  const double var_b = std::pow(config.gnss_bias_sigma_m, 2);
  const double var_gw = std::pow(config.gnss_white_sigma_m, 2);
  const double var_hw = std::pow(config.heading_white_sigma_rad, 2);
  const double var_drift = std::pow(config.heading_drift_rad_per_s, 2);
  const double var_gj = std::pow(delays.gnss_jitter_sigma_s, 2);
  const double var_hj = std::pow(delays.heading_jitter_sigma_s, 2);
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (int a = 0; a < n; ++a) {
    const Row& ra = rows[a];
    for (int b = a; b < n; ++b) {
      const Row& rb = rows[b];
      Eigen::Matrix2d block = Eigen::Matrix2d::Zero();
      double g = 0.0;  // per-axis covariance of the two antenna errors
      if (sources & kGnssBias) {
        const double dt = std::abs(ra.t_s - rb.t_s);
        g += config.gnss_bias_tau_s > 0.0 ? var_b * std::exp(-dt / config.gnss_bias_tau_s)
                                          : (dt == 0.0 ? var_b : 0.0);
      }
      if (sources & kGnssWhite) g += var_gw * Overlap(ra.gnss, rb.gnss);
      block(0, 0) += g * ra.n.dot(rb.n);
      // Stamp jitter: fix j's position is off by −v ε_j (v taken at the scans' times).
      if (var_gj > 0.0) block(0, 0) += var_gj * Overlap(ra.gnss, rb.gnss) * ra.n_dot_v * rb.n_dot_v;
      double h = 0.0;  // covariance of the two heading errors
      if (sources & kHeadingWhite) h += var_hw * Overlap(ra.heading, rb.heading);
      if (var_hj > 0.0) h += var_hj * Overlap(ra.heading, rb.heading) * ra.yaw_rate * rb.yaw_rate;
      if (sources & kHeadingDrift) h += var_drift * ra.t_s * rb.t_s;
      block += h * ra.B * rb.B.transpose();
      if (sources & kSurvey) {
        block += ra.W * wall_cov.block<2, 2>(2 * ra.wall, 2 * rb.wall) * rb.W.transpose();
      }
      if (a == b && (sources & kLineFit)) block += ra.fit_cov;
      C.block<2, 2>(2 * a, 2 * b) = block;
      C.block<2, 2>(2 * b, 2 * a) = block.transpose();
    }
  }
  // Each unit's range model: one offset and one scale per scanner, shared by all its lines.
  Eigen::MatrixXd units_cov;
  if (sources & kUnitRange) {
    const Eigen::Vector2d variance(std::pow(preset.range_offset_sigma_m, 2),
                                   std::pow(preset.range_scale_sigma, 2));
    units_cov = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    for (int a = 0; a < n; ++a) {
      for (int b = 0; b < n; ++b) {
        if (rows[a].scanner != rows[b].scanner) continue;
        units_cov.block<2, 2>(2 * a, 2 * b) =
            rows[a].unit_gain * variance.asDiagonal() * rows[b].unit_gain.transpose();
      }
    }
  }
  if (sources & kSite) {
    std::vector<SiteRowInput> site_rows;
    for (const Row& r : rows) {
      site_rows.push_back({r.t_s, r.scanner, config_wall_of[r.wall], lines[2 * r.wall],
                           lines[2 * r.wall + 1], r.sign});
    }
    C += SiteLineCovariance(scanner_configs, site_rows);
  }
  // Unknowns: the mounts, then each delay with a prior (its information on the diagonal of
  // P): one scanner offset per scanner, the GNSS and heading delays shared.
  std::vector<double> prior_information;
  std::vector<int> delay_kind;     // 0 scanner offset, 1 GNSS delay, 2 heading delay
  std::vector<int> delay_scanner;  // the scanner of a scanner offset (-1: shared)
  const double prior_sigma[3] = {delays.scanner_offset_prior_sigma_s,
                                 delays.gnss_delay_prior_sigma_s,
                                 delays.heading_delay_prior_sigma_s};
  for (int kind = 0; kind < 3; ++kind) {
    if (!(prior_sigma[kind] > 0.0)) continue;
    for (int s = 0; s < (kind == 0 ? scanners : 1); ++s) {
      delay_kind.push_back(kind);
      delay_scanner.push_back(kind == 0 ? s : -1);
      prior_information.push_back(1.0 / (prior_sigma[kind] * prior_sigma[kind]));
    }
  }
  const int m = 3 * scanners;
  const int p = m + static_cast<int>(delay_kind.size());
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2 * n, p);
  for (int a = 0; a < n; ++a) {
    const Row& r = rows[a];
    J.block(2 * a, 3 * r.scanner, 2, 3) = r.J;
    for (size_t d = 0; d < delay_kind.size(); ++d) {
      if (delay_scanner[d] >= 0 && delay_scanner[d] != r.scanner) continue;
      J.block(2 * a, m + static_cast<int>(d), 2, 1) =
          delay_kind[d] == 0   ? Eigen::Vector2d(r.J_position_time + r.J_heading_time)
          : delay_kind[d] == 1 ? Eigen::Vector2d(-r.J_position_time)
                               : Eigen::Vector2d(-r.J_heading_time);
    }
  }
  // The units' terms as an estimator that ignores them meets them: the bound without them plus
  // the linear response S = F⁻¹ Jᵀ C⁻¹ A to each unit's offset and scale (A: the gains).
  // Not for an oracle's call (rows with residuals): it reads joint_crb only.
  const bool oracle_call =
      std::all_of(rows.begin(), rows.end(), [](const Row& r) { return r.has_residual; });
  if (units_cov.size() > 0 && !oracle_call) {
    const Eigen::LLT<Eigen::MatrixXd> llt0(C);
    if (llt0.info() == Eigen::Success) {
      Eigen::MatrixXd fisher0 = J.transpose() * llt0.solve(J);
      for (size_t d = 0; d < prior_information.size(); ++d) {
        fisher0(m + d, m + d) += prior_information[d];
      }
      const Eigen::FullPivLU<Eigen::MatrixXd> lu0(fisher0);
      if (lu0.isInvertible()) {
        const Eigen::MatrixXd bound0 = lu0.inverse();
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * scanners);
        for (int a = 0; a < n; ++a) A.block<2, 2>(2 * a, 2 * rows[a].scanner) = rows[a].unit_gain;
        const Eigen::MatrixXd S = bound0 * (J.transpose() * llt0.solve(A));
        Eigen::VectorXd variance(2 * scanners);
        for (int unit = 0; unit < scanners; ++unit) {
          variance[2 * unit] = std::pow(preset.range_offset_sigma_m, 2);
          variance[2 * unit + 1] = std::pow(preset.range_scale_sigma, 2);
        }
        result.joint_consider =
            (bound0 + S * variance.asDiagonal() * S.transpose()).topLeftCorner(m, m);
      }
    }
  }
  if (units_cov.size() > 0) C += units_cov;
  const Eigen::LLT<Eigen::MatrixXd> llt(C);
  if (llt.info() != Eigen::Success) {
    result.message = "the observation covariance is not positive definite";
    return result;
  }
  Eigen::MatrixXd fisher = J.transpose() * llt.solve(J);
  for (size_t d = 0; d < prior_information.size(); ++d) fisher(m + d, m + d) += prior_information[d];
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(fisher);
  if (!lu.isInvertible()) {
    result.message = "the Fisher information is singular (the mount is not observable)";
    return result;
  }
  const Eigen::MatrixXd bound = lu.inverse();
  result.crb = bound.topLeftCorner<3, 3>();
  result.joint_crb = bound.topLeftCorner(m, m);
  result.ok = true;
  // The timing calibrate reports, as combinations of the unknown delays (kind -> column).
  int column_of[3] = {-1, -1, -1};
  for (size_t d = 0; d < delay_kind.size(); ++d) column_of[delay_kind[d]] = m + static_cast<int>(d);
  if (scanners == 1 && column_of[0] >= 0 && column_of[2] >= 0) {
    const auto sigma_of = [&](double scanner, double gnss, double heading) {
      Eigen::VectorXd c = Eigen::VectorXd::Zero(p);
      c[column_of[0]] = scanner;
      if (column_of[1] >= 0) c[column_of[1]] = gnss;
      c[column_of[2]] = heading;
      return std::sqrt(std::max(0.0, c.dot(bound * c)));
    };
    result.has_delay_bound = true;
    result.delay_bound_dt_s = sigma_of(1.0, -1.0, 0.0);
    result.delay_bound_dh_s = sigma_of(0.0, 1.0, -1.0);
    result.delay_bound_sum_s = sigma_of(1.0, 0.0, -1.0);
  }
  if (std::all_of(rows.begin(), rows.end(), [](const Row& r) { return r.has_residual; })) {
    Eigen::VectorXd r(2 * n);
    for (int a = 0; a < n; ++a) r.segment<2>(2 * a) = rows[a].residual;
    // r ≈ J δm + ε, J = ∂(rho, theta)/∂m as above (the delays' priors are centred on the
    // truth, so they add nothing to the right-hand side).
    result.oracle_joint_error = (bound * (J.transpose() * llt.solve(r))).head(m);
    result.oracle_error = result.oracle_joint_error.head<3>();  // scanner 0
    result.has_oracle = true;
  }
  return result;
}

std::vector<CrbObservation> AllSessionObservations(const sim::SimulationConfig& config,
                                                   const io::ScannerPreset& preset,
                                                   int min_wall_beams) {
  std::vector<CrbObservation> out;
  const double duration_s = sim::RunDurationS(config);
  const int64_t log_every = std::max<int64_t>(1, std::llround(config.log_every_n));
  // As sim::Simulate: scan k at true time k / rate, every log_every-th logged.
  const int64_t scan_count = static_cast<int64_t>(std::floor(duration_s * preset.rate_hz + 1e-9)) + 1;
  std::vector<double> times;
  for (int64_t k = 0; k < scan_count; k += log_every) times.push_back(k / preset.rate_hz);
  const std::vector<sim::SimTruthPose> poses = sim::TruePosesAt(config, times);
  std::vector<int> surveyed_of(config.walls.size(), -1);  // config.walls index -> surveyed
  int surveyed = 0;
  for (size_t i = 0; i < config.walls.size(); ++i) {
    if (!config.walls[i].code.empty()) surveyed_of[i] = surveyed++;
  }
  constexpr double kMinRangeM = 0.5;  // as ComputeCrb
  for (size_t i = 0; i < times.size(); ++i) {
    std::vector<int> beams(static_cast<size_t>(surveyed), 0);
    for (const sim::SimBeamHit& h : sim::TrueBeamHits(config, preset, poses[i])) {
      if (!h.returned || h.footprint_edge || h.wall_index < 0 || h.range_m < kMinRangeM) continue;
      const int w = surveyed_of[static_cast<size_t>(h.wall_index)];
      if (w >= 0) ++beams[static_cast<size_t>(w)];
    }
    for (int w = 0; w < surveyed; ++w) {
      if (beams[static_cast<size_t>(w)] < min_wall_beams) continue;
      CrbObservation o;
      o.t_s = times[i];
      o.surveyed_wall = w;
      out.push_back(o);
    }
  }
  return out;
}

}  // namespace wallcal::bench
