// SPDX-License-Identifier: Apache-2.0
// The range model's fit (characterise/range_fit.h).

#include "characterise/range_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/statistics.h"

namespace wallcal::characterise {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kHour_s = 3600.0;
constexpr double kMaxFootprintDepth_m = 0.1;

// Knot times (s) of the piecewise-linear drift: 0, then the fixed times inside the session,
// then its end. Fewer than two knots: no drift modelled.
std::vector<double> DriftKnots(double span_s) {
  std::vector<double> knots;
  if (span_s < 600.0) return knots;
  knots.push_back(0.0);
  for (double t : {450.0, 900.0, 1800.0, 3600.0, 7200.0, 14400.0}) {
    if (t < span_s - 120.0) knots.push_back(t);
  }
  knots.push_back(span_s);
  return knots;
}

// Hat-function weights of the drift at time t: drift(t) = Σ_k h_k(t)·D_k over knots 1..K
// (D_0 = 0); flat beyond the ends.
void DriftWeights(const std::vector<double>& knots, double t, std::vector<double>* h) {
  const size_t k_count = knots.empty() ? 0 : knots.size() - 1;
  h->assign(k_count, 0.0);
  if (k_count == 0) return;
  if (t >= knots.back()) {
    (*h)[k_count - 1] = 1.0;
    return;
  }
  if (t <= 0.0) return;
  size_t j = 1;
  while (j < knots.size() && knots[j] < t) ++j;  // knots[j-1] < t <= knots[j]
  const double u = (t - knots[j - 1]) / (knots[j] - knots[j - 1]);
  (*h)[j - 1] += u;  // weight of knot j (index j − 1)
  if (j >= 2) (*h)[j - 2] += 1.0 - u;
}

Value ValueOf(double value, const Eigen::VectorXd& gradient, const Eigen::MatrixXd& cov) {
  const double var = gradient.dot(cov * gradient);
  return {value, std::sqrt(std::max(0.0, var))};
}

}  // namespace

FitOutput FitRangeModel(const FitSetup& setup) {
  const BeamSet& set = *setup.beams;
  const std::vector<calib::WallGeometry>& walls = *setup.walls;
  const int num_stations = static_cast<int>(set.stations.size());
  const int num_walls = static_cast<int>(walls.size());
  const std::vector<double> knots = DriftKnots(set.span_s);
  const int num_knots = knots.empty() ? 0 : static_cast<int>(knots.size()) - 1;
  // Parameter layout.
  const int iN = 0, iC = 1, iD = 2, iM = iD + num_knots, iS = iM + 3,
            iW = iS + 3 * num_stations, P = iW + num_walls;

  Eigen::VectorXd x = Eigen::VectorXd::Zero(P);
  x[iN] = setup.start_n;
  x[iC] = setup.start_c_m;
  x[iM] = setup.mount_prior.x_m;
  x[iM + 1] = setup.mount_prior.y_m;
  x[iM + 2] = setup.mount_prior.yaw_rad;

  // Prior information.
  Eigen::MatrixXd prior = Eigen::MatrixXd::Zero(P, P);
  Eigen::VectorXd prior_mean = Eigen::VectorXd::Zero(P);
  prior.block<3, 3>(iM, iM) = setup.mount_prior_covariance.inverse();
  prior_mean.segment<3>(iM) = x.segment<3>(iM);
  {
    // GNSS error per station, per axis: Gauss–Markov covariance σ_i σ_j exp(−|Δt|/τ).
    Eigen::MatrixXd gm(num_stations, num_stations);
    for (int i = 0; i < num_stations; ++i) {
      for (int j = 0; j < num_stations; ++j) {
        const double dt = std::abs(set.stations[i].time_s - set.stations[j].time_s);
        const double rho = i == j ? 1.0 : setup.gnss_tau_s > 0.0 ? std::exp(-dt / setup.gnss_tau_s)
                                                                 : 0.0;
        gm(i, j) = set.stations[i].gnss_sigma_m * set.stations[j].gnss_sigma_m * rho;
      }
    }
    gm.diagonal().array() += 1e-10;  // stations at the same instant stay invertible
    const Eigen::MatrixXd info = gm.inverse();
    for (int i = 0; i < num_stations; ++i) {
      for (int j = 0; j < num_stations; ++j) {
        prior(iS + 3 * i, iS + 3 * j) = info(i, j);
        prior(iS + 3 * i + 1, iS + 3 * j + 1) = info(i, j);
      }
      prior(iS + 3 * i + 2, iS + 3 * i + 2) = 1.0 / (setup.heading_sigma_rad * setup.heading_sigma_rad);
    }
    for (int w = 0; w < num_walls; ++w) {
      const double s = std::max(1e-4, walls[w].sigma_offset_m);
      prior(iW + w, iW + w) = 1.0 / (s * s);
    }
  }

  FitOutput out;
  const size_t num_beams = set.beams.size();
  out.true_range_m.assign(num_beams, static_cast<float>(kNaN));
  out.incidence_rad.assign(num_beams, static_cast<float>(kNaN));
  out.residual_m.assign(num_beams, static_cast<float>(kNaN));
  out.drift_m.assign(num_beams, 0.0f);
  out.noise_residual_m.assign(num_beams, static_cast<float>(kNaN));

  double sigma_w = std::max(1e-4, setup.start_sigma_m);  // weights
  // Per beam: how the range moves with the scanner's distance to the wall and its angle, for the
  // within-scan noise estimate.
  std::vector<double> shape_offset(num_beams, 0.0), shape_angle(num_beams, 0.0);
  double gate_m = std::numeric_limits<double>::infinity();  // first pass: the collection gate
  Eigen::MatrixXd H(P, P);
  Eigen::VectorXd g(P);
  std::vector<double> h;
  std::vector<double> mean_h(num_knots, 0.0);
  double sum_r2 = 0.0, sum_r4 = 0.0;
  int used = 0, rejected = 0;
  constexpr int kIterations = 7;
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    H.setZero();
    g.setZero();
    sum_r2 = sum_r4 = 0.0;
    used = rejected = 0;
    std::fill(mean_h.begin(), mean_h.end(), 0.0);
    std::vector<double> abs_residuals;
    const double n = x[iN];
    const calib::Mount mount{x[iM], x[iM + 1], x[iM + 2]};
    // Each scan's own pose error (2-D position, yaw: the GNSS error wandering within the dwell,
    // white GNSS and heading noise) as three parameters eliminated scan by scan (Schur
    // complement), with priors: σ² = white² + σ_bias²·min(1, 2·dwell/(3τ)) per axis (the
    // Gauss–Markov error's spread about its dwell mean) and the heading σ.
    Eigen::MatrixXd Hgs = Eigen::MatrixXd::Zero(P, 3);
    Eigen::Matrix3d Hss = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gs = Eigen::Vector3d::Zero();
    int current_scan = -1, current_station = 0;
    double explained = 0.0;  // Σ g_sᵀ H_ss⁻¹ g_s: what the scans' own errors take out
    auto flush = [&]() {
      if (current_scan < 0) return;
      const StationPose& st = set.stations[current_station];
      const double wander = setup.gnss_tau_s > 0.0
                                ? std::min(1.0, 2.0 * st.dwell_s / (3.0 * setup.gnss_tau_s))
                                : 1.0;
      const double var_p = setup.gnss_white_sigma_m * setup.gnss_white_sigma_m +
                           setup.gnss_bias_sigma_m * setup.gnss_bias_sigma_m * wander;
      Hss += Eigen::Vector3d(1.0 / var_p, 1.0 / var_p,
                             1.0 / (setup.heading_sigma_rad * setup.heading_sigma_rad))
                 .asDiagonal();
      const Eigen::Matrix3d inv = Hss.inverse();
      H.noalias() -= Hgs * inv * Hgs.transpose();
      g.noalias() -= Hgs * (inv * gs);
      explained += gs.dot(inv * gs);
      Hgs.setZero();
      Hss.setZero();
      gs.setZero();
      current_scan = -1;
    };
    for (size_t b = 0; b < num_beams; ++b) {
      const BeamReturn& beam = set.beams[b];
      StationPose station = set.stations[beam.station];
      station.antenna_local_m += Eigen::Vector2d(x[iS + 3 * beam.station], x[iS + 3 * beam.station + 1]);
      station.yaw_rad += x[iS + 3 * beam.station + 2];
      calib::WallGeometry wall = walls[beam.wall];
      wall.offset_m += x[iW + beam.wall];
      const Ray ray = BeamRay(station, mount, beam.bearing_rad);
      const WallHit hit = HitWall(ray, wall);
      out.true_range_m[b] = static_cast<float>(hit.range_m);
      out.incidence_rad[b] = static_cast<float>(hit.incidence_rad);
      out.residual_m[b] = static_cast<float>(kNaN);
      if (beam.kind != BeamKind::kOnWall || !beam.near_wall || !std::isfinite(hit.range_m)) continue;
      DriftWeights(knots, beam.time_s, &h);
      double drift = 0.0;
      for (int k = 0; k < num_knots; ++k) drift += h[k] * x[iD + k];
      out.drift_m[b] = static_cast<float>(drift);
      const double t = hit.range_m;
      const double r = beam.z_m - (n * t + x[iC] + drift);
      out.residual_m[b] = static_cast<float>(r);
      // Only beams whose footprint spans little depth (t·tan(incidence)·step < kMaxFootprintDepth_m)
      // enter the fit: a footprint across a deep slice of an oblique wall returns a range from
      // anywhere in it (a mixed pixel without an edge), which is not the range noise.
      const double depth_m = t * std::tan(hit.incidence_rad) * setup.angular_step_rad;
      if (!(depth_m < kMaxFootprintDepth_m)) continue;
      abs_residuals.push_back(std::abs(r));
      if (std::abs(r) > gate_m) {
        ++rejected;
        continue;
      }
      ++used;
      sum_r2 += r * r;
      sum_r4 += r * r * r * r;
      for (int k = 0; k < num_knots; ++k) mean_h[k] += h[k];
      // ∂t: t = (offset − n_w·o) / (n_w·d); o = p + R(ψ)·m_xy; d = dir(ψ + m_yaw + β).
      const Eigen::Vector2d& nw = wall.normal_local;
      const double cos_in = nw.dot(ray.direction);
      const Eigen::Vector2d perp_d(-ray.direction.y(), ray.direction.x());
      const double dt_dphi = -t * nw.dot(perp_d) / cos_in;
      const double cy = std::cos(station.yaw_rad), sy = std::sin(station.yaw_rad);
      const Eigen::Vector2d rx(cy, sy), ry(-sy, cy);  // R(ψ)·e_x, R(ψ)·e_y
      const Eigen::Vector2d rm = mount.x_m * rx + mount.y_m * ry;
      const Eigen::Vector2d perp_rm(-rm.y(), rm.x());
      int idx[12];
      double val[12];
      int m = 0;
      auto put = [&](int i, double v) { idx[m] = i; val[m] = v; ++m; };
      put(iN, t);
      put(iC, 1.0);
      for (int k = 0; k < num_knots; ++k) {
        if (h[k] != 0.0) put(iD + k, h[k]);
      }
      put(iM, -n * nw.dot(rx) / cos_in);
      put(iM + 1, -n * nw.dot(ry) / cos_in);
      put(iM + 2, n * dt_dphi);
      const int is = iS + 3 * beam.station;
      put(is, -n * nw.x() / cos_in);
      put(is + 1, -n * nw.y() / cos_in);
      put(is + 2, n * (dt_dphi - nw.dot(perp_rm) / cos_in));
      put(iW + beam.wall, n / cos_in);
      shape_offset[b] = 1.0 / cos_in;
      shape_angle[b] = dt_dphi;
      const double w = 1.0 / (sigma_w * sigma_w);
      for (int a = 0; a < m; ++a) {
        g[idx[a]] += w * val[a] * r;
        for (int c = 0; c < m; ++c) H(idx[a], idx[c]) += w * val[a] * val[c];
      }
      if (beam.scan != current_scan) {
        flush();
        current_scan = beam.scan;
        current_station = beam.station;
      }
      // The scan's pose error moves the range as the station's does (same partials).
      const Eigen::Vector3d u(val[m - 4], val[m - 3], val[m - 2]);
      for (int a = 0; a < m; ++a) Hgs.row(idx[a]) += w * val[a] * u.transpose();
      Hss += w * u * u.transpose();
      gs += w * u * r;
    }
    flush();
    if (used < 10) break;
    H += prior;
    g -= prior * (x - prior_mean);
    const Eigen::VectorXd step = H.ldlt().solve(g);
    if (!step.allFinite()) break;
    x += step;
    // The next pass: weights from the RMS, the gate at 4 robust σ.
    const double dof = std::max(1, used - P);
    const double within_r2 = sum_r2 - explained * sigma_w * sigma_w;
    sigma_w = std::max(1e-5, std::sqrt(std::max(0.0, within_r2) / dof));
    out.robust_sigma_m = 1.4826 * UpperMedian(abs_residuals, 0.0);
    gate_m = std::max(4.0 * out.robust_sigma_m, 1e-3);
  }

  RangeModel& model = out.model;
  model.beams_used = used;
  model.beams_rejected = rejected;
  model.stations = num_stations;
  model.mount_given = setup.mount_given;
  model.mount_sigma_given = setup.mount_sigma_given;
  if (used < 10) return out;
  // The covariance at the solution (weights from the final σ).
  const Eigen::MatrixXd cov = H.ldlt().solve(Eigen::MatrixXd::Identity(P, P));
  for (double& v : mean_h) v /= used;
  auto unit = [P](int i) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(P);
    e[i] = 1.0;
    return e;
  };
  const double n = x[iN];
  Eigen::VectorXd grad_c = unit(iC);  // session-mean offset c + mean drift
  double c_mean = x[iC];
  for (int k = 0; k < num_knots; ++k) {
    grad_c[iD + k] = mean_h[k];
    c_mean += mean_h[k] * x[iD + k];
  }
  model.n = ValueOf(n, unit(iN), cov);
  model.c_m = ValueOf(c_mean, grad_c, cov);
  const Eigen::VectorXd grad_k = -unit(iN) / (n * n);
  const Eigen::VectorXd grad_b = unit(iN) * (c_mean / (n * n)) - grad_c / n;
  model.k = ValueOf(1.0 / n, grad_k, cov);
  model.b_m = ValueOf(-c_mean / n, grad_b, cov);
  model.corr_k_b = model.k.sigma > 0 && model.b_m.sigma > 0
                       ? grad_k.dot(cov * grad_b) / (model.k.sigma * model.b_m.sigma)
                       : 0.0;
  model.mount_x_m = ValueOf(x[iM], unit(iM), cov);
  model.mount_y_m = ValueOf(x[iM + 1], unit(iM + 1), cov);
  model.mount_yaw_rad = ValueOf(x[iM + 2], unit(iM + 2), cov);
  model.corr_b_mount_x = model.b_m.sigma > 0 && model.mount_x_m.sigma > 0
                             ? grad_b.dot(cov * unit(iM)) / (model.b_m.sigma * model.mount_x_m.sigma)
                             : 0.0;
  // Noise: the residual variance within each scan, after removing what the scan's pose error
  // does to all its beams (a shift along the wall normal and a turn: the GNSS error wanders
  // during a dwell, Gauss–Markov, and moves every beam of a scan together), less the quantum's
  // q²/12 (Sheppard's correction); its σ from the residuals' fourth moment, Var(s²) ≈ (m4 − s⁴)/N.
  const double gate_final = gate_m;
  double within_rss = 0.0, within_r4 = 0.0;
  int64_t within_dof = 0, within_n = 0;
  for (size_t b0 = 0; b0 < num_beams;) {
    size_t b1 = b0;
    while (b1 < num_beams && set.beams[b1].scan == set.beams[b0].scan) ++b1;
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Eigen::Vector2d v = Eigen::Vector2d::Zero();
    int count = 0;
    for (size_t b = b0; b < b1; ++b) {
      const double r = out.residual_m[b];
      if (!std::isfinite(r) || std::abs(r) > gate_final || shape_offset[b] == 0.0) continue;
      const Eigen::Vector2d u(shape_offset[b], shape_angle[b]);
      A += u * u.transpose();
      v += u * r;
      ++count;
    }
    if (count >= 5) {
      const Eigen::Vector2d a = A.ldlt().solve(v);
      for (size_t b = b0; b < b1; ++b) {
        const double r = out.residual_m[b];
        if (!std::isfinite(r) || std::abs(r) > gate_final || shape_offset[b] == 0.0) continue;
        const double e = r - a.dot(Eigen::Vector2d(shape_offset[b], shape_angle[b]));
        out.noise_residual_m[b] = static_cast<float>(e);
        within_rss += e * e;
        within_r4 += e * e * e * e;
      }
      within_dof += count - 2;
      within_n += count;
    }
    b0 = b1;
  }
  model.residual_rms_m = std::sqrt(sum_r2 / std::max(1, used - P));
  const double s2 = within_dof > 0 ? within_rss / within_dof : sum_r2 / std::max(1, used - P);
  sum_r4 = within_n > 0 ? within_r4 : sum_r4;
  used = within_n > 0 ? static_cast<int>(within_n) : used;
  const double q2 = setup.quantum_m * setup.quantum_m / 12.0;
  const double noise2 = std::max(0.0, s2 - q2);
  const double var_s2 = std::max(0.0, sum_r4 / used - s2 * s2) / used;
  model.sigma_m = {std::sqrt(noise2),
                   noise2 > 0.0 ? std::sqrt(var_s2) / (2.0 * std::sqrt(noise2)) : std::sqrt(q2)};
  if (num_knots > 0) {
    model.drift_fitted = true;
    model.drift_knots_s = knots;
    model.drift_at_knots_m.push_back({0.0, 0.0});
    for (int k = 0; k < num_knots; ++k) {
      model.drift_at_knots_m.push_back(ValueOf(x[iD + k], unit(iD + k), cov));
    }
    model.drift_span_s = std::min(kHour_s, set.span_s);
    DriftWeights(knots, model.drift_span_s, &h);
    Eigen::VectorXd grad = Eigen::VectorXd::Zero(P);
    double drift = 0.0;
    for (int k = 0; k < num_knots; ++k) {
      grad[iD + k] = h[k];
      drift += h[k] * x[iD + k];
    }
    model.drift_first_hour_m = ValueOf(drift, grad, cov);
  }
  return out;
}

}  // namespace wallcal::characterise
