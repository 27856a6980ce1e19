// SPDX-License-Identifier: Apache-2.0
// Building the mount adjustment as a Ceres problem (solvers/mount_problem.h): the noise model
// of each observation, the joint prior of the walls, the GNSS-error chain, the heading offsets.
// Solving it is solvers/ceres_solver.cc.

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "solvers/internal/observation_rows.h"
#include "solvers/mount_problem.h"
#include "solvers/prior_cost.h"
#include "solvers/wall_line_cost.h"
#include "solvers/wall_slice_cost.h"

namespace wallcal::solvers {
double PoseBiasSigma(const calib::VehiclePose& pose, const solvers::SolverOptions& options) {
  if (options.use_gst_sigma && pose.gnss_sigma_m > 0.0) return pose.gnss_sigma_m;
  return options.gnss_bias_sigma_m;
}

double MovingScansPerGnssFix(const std::vector<calib::WallObservation>& observations) {
  std::vector<double> stamps;
  double period_s = 0.0;
  for (const auto& o : observations) {
    if (UsesDwellHeading(o)) continue;
    stamps.push_back(o.pose.stamp_s);
    period_s = std::max(period_s, o.pose.gnss_period_s);
  }
  std::sort(stamps.begin(), stamps.end());
  std::vector<double> steps;
  for (size_t i = 1; i < stamps.size(); ++i) {
    if (stamps[i] > stamps[i - 1]) steps.push_back(stamps[i] - stamps[i - 1]);
  }
  if (steps.empty() || !(period_s > 0.0)) return 1.0;
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  return std::max(1.0, period_s / steps[steps.size() / 2]);
}

Eigen::Matrix2d MovingPoseCovariance(const calib::WallObservation& observation,
                                     const Eigen::Vector2d& normal_local, double ell_m,
                                     const solvers::SolverOptions& options) {
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  if (UsesDwellHeading(observation)) return covariance;
  const calib::VehiclePose& pose = observation.pose;
  // Timing: the position sample late by δ puts the antenna −v δ off (rho: n·v δ), the heading
  // sample late by δ' turns the vehicle by −ω δ' (rho: ℓ ω δ', theta: ω δ'); the two streams'
  // timing errors independent, σ each.
  const double sigma_t2 = options.moving_timing_sigma_s * options.moving_timing_sigma_s;
  const Eigen::Vector2d g_position(normal_local.dot(pose.velocity_local_mps), 0.0);
  const Eigen::Vector2d g_heading(ell_m * pose.yaw_rate_rps, pose.yaw_rate_rps);
  covariance += sigma_t2 * (g_position * g_position.transpose() +
                            g_heading * g_heading.transpose());
  // Linear interpolation between GNSS fixes T apart on a path curving with acceleration
  // a = |v| |ω|: off by a T² f (1 − f) / 2 at fraction f, RMS a T² / (2 √30) over f (taken
  // along the normal in full: the direction of a is not kept). The poses of moving scans are
  // cubics through the fixes (calib::PoseInterpolator::CubicAt), whose error is of order
  // jerk·T³; this term is kept for the linear fallback at gaps and is an over-estimate (a few
  // tenths of a mm) otherwise.
  const double a_mps2 = pose.velocity_local_mps.norm() * std::abs(pose.yaw_rate_rps);
  const double interp_m = a_mps2 * pose.gnss_period_s * pose.gnss_period_s / (2.0 * std::sqrt(30.0));
  covariance(0, 0) += interp_m * interp_m;
  return covariance;
}

namespace {

// ℓ: the along-wall part of the lever arm R(ψ)(x, y), i.e. d rho_pred/dψ = −ℓ (J the 90°
// rotation: ℓ = n·(J R(ψ)(x, y))).
double AlongWallLever(const calib::VehiclePose& pose, const Eigen::Vector2d& normal_local,
                      const Mount& lever_mount) {
  const double c = std::cos(pose.yaw_rad), s = std::sin(pose.yaw_rad);
  const Eigen::Vector2d lever(c * lever_mount.x_m - s * lever_mount.y_m,
                              s * lever_mount.x_m + c * lever_mount.y_m);
  return normal_local.dot(Eigen::Vector2d(-lever.y(), lever.x()));
}

}  // namespace

double DrivesTimingSigma(const std::vector<calib::WallObservation>& observations,
                         const std::vector<calib::WallGeometry>& walls, const Mount& lever_mount,
                         const Eigen::Matrix2d& time_covariance) {
  double shift_m2 = 0.0, sensitivity_m2_per_s2 = 0.0;
  for (const calib::WallObservation& observation : observations) {
    if (UsesDwellHeading(observation)) continue;
    const calib::VehiclePose& pose = observation.pose;
    const calib::OrientedWall oriented =
        calib::OrientWall(walls[observation.wall_index], pose.antenna_local_m);
    const double ell_m = AlongWallLever(pose, oriented.normal_local, lever_mount);
    const double turn_mps = ell_m * pose.yaw_rate_rps;
    const double arc_mps = observation.rho_m * pose.yaw_rate_rps;
    const Eigen::Vector2d rho_row(oriented.normal_local.dot(pose.velocity_local_mps) + turn_mps,
                                  turn_mps);
    const Eigen::Vector2d theta_row(arc_mps, arc_mps);
    shift_m2 += rho_row.dot(time_covariance * rho_row) + theta_row.dot(time_covariance * theta_row);
    sensitivity_m2_per_s2 += rho_row.x() * rho_row.x() + theta_row.x() * theta_row.x();
  }
  return sensitivity_m2_per_s2 > 0.0 ? std::sqrt(shift_m2 / sensitivity_m2_per_s2) : 0.0;
}

Eigen::Matrix2d ObservationCovariance(const calib::WallObservation& observation,
                                      const calib::WallGeometry& wall,
                                      const solvers::SolverOptions& options, const Mount& lever_mount,
                                      double bias_sigma_m, double scans_per_gnss_fix,
                                      SharedWhiteNoise shared) {
  const calib::OrientedWall oriented = calib::OrientWall(wall, observation.pose.antenna_local_m);
  Eigen::Matrix2d covariance;
  covariance << observation.sigma_rho_m * observation.sigma_rho_m, observation.cov_rho_theta,
      observation.cov_rho_theta, observation.sigma_theta_rad * observation.sigma_theta_rad;

  // GNSS white noise moves the scanner along the normal one-for-one: rho only. Without a
  // segment there is no bias block, so the correlated part is counted here as if it were white
  // (optimistic for that observation, but such observations are rare: moving scans outside
  // any segment).
  double position_variance_m2 = options.gnss_white_sigma_m * options.gnss_white_sigma_m;
  if (shared.gnss_fixes) position_variance_m2 = 0.0;
  // A moving scan: the scans between the same two fixes share their white noise (the bias
  // slices, tied by the Gauss–Markov chain, do not take it up). Counted as white at the
  // variance times the scans per fix, the mean over those scans gets the fix's variance.
  if (!UsesDwellHeading(observation)) position_variance_m2 *= std::max(1.0, scans_per_gnss_fix);
  if (calib::GnssSegment(observation) < 0) {
    position_variance_m2 += bias_sigma_m * bias_sigma_m;
  }

  // Heading noise δψ turns the lever arm R(ψ)(x, y): d rho_pred/dψ = −n·(J R(ψ)(x, y)) = −ℓ,
  // with J the 90° rotation, i.e. ℓ is the along-wall component of the lever arm; and
  // d theta_pred/dψ = −1. Hence the block σ_h² [ℓ², ℓ; ℓ, 1]. The lever uses `lever_mount`
  // (the initial mount, then the solution: SolveMountCeres rebuilds once when it moved).
  const double ell_m = AlongWallLever(observation.pose, oriented.normal_local, lever_mount);
  // A dwell's scans use the dwell's mean heading: its error is common to the dwell and lives
  // in the segment's heading-offset parameter (which turns the lever arm in the cost itself),
  // not in each scan's covariance.
  const double heading_variance = UsesDwellHeading(observation) || shared.heading_samples
                                      ? 0.0
                                      : options.heading_sigma_rad * options.heading_sigma_rad;

  // The vehicle attitude's noise (an attitude stream's; 0 on a level site).
  covariance(0, 0) += position_variance_m2 + ell_m * ell_m * heading_variance +
                      observation.attitude_var_rho_m2;
  covariance(0, 1) += ell_m * heading_variance;
  covariance(1, 0) += ell_m * heading_variance;
  covariance(1, 1) += heading_variance;
  return covariance + MovingPoseCovariance(observation, oriented.normal_local, ell_m, options);
}

Eigen::MatrixXd WallPriorCovariance(const std::vector<calib::WallGeometry>& walls,
                                    const std::vector<int>& indices) {
  const int n = static_cast<int>(indices.size());
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (int i = 0; i < n; ++i) {
    const calib::WallGeometry& a = walls[indices[i]];
    covariance(2 * i, 2 * i) = a.sigma_offset_m * a.sigma_offset_m;
    covariance(2 * i + 1, 2 * i + 1) = a.sigma_angle_rad * a.sigma_angle_rad;
    covariance(2 * i, 2 * i + 1) = covariance(2 * i + 1, 2 * i) = a.cov_offset_angle;
    for (int j = 0; j < n; ++j) {
      if (j == i) continue;
      const calib::WallGeometry& b = walls[indices[j]];
      // The shared tie: translation t (σ_t per axis) and rotation r (σ_r) about the control
      // centroid; δd = n·t + ℓ r, δα = r. Walls without tie information share nothing.
      const double st = std::min(a.tie_sigma_translation_m, b.tie_sigma_translation_m);
      const double sr = std::min(a.tie_sigma_rotation_rad, b.tie_sigma_rotation_rad);
      const double sr2 = sr * sr;
      covariance(2 * i, 2 * j) =
          st * st * a.normal_local.dot(b.normal_local) + sr2 * a.tie_lever_m * b.tie_lever_m;
      covariance(2 * i, 2 * j + 1) = sr2 * a.tie_lever_m;
      covariance(2 * i + 1, 2 * j) = sr2 * b.tie_lever_m;
      covariance(2 * i + 1, 2 * j + 1) = sr2;
    }
  }
  return covariance;
}

std::unique_ptr<MountProblem> BuildMountProblem(
    const std::vector<calib::WallObservation>& observations,
    const std::vector<calib::WallGeometry>& walls, const solvers::SolverOptions& options,
    const Mount& lever_mount, const Mount& initial, std::string* error,
    const std::vector<double>& weights) {
  auto mp = std::make_unique<MountProblem>();
  mp->mount = {initial.x_m, initial.y_m, initial.yaw_rad};
  mp->wall_deltas.assign(walls.size(), {0.0, 0.0});
  const auto weight_of = [&weights](size_t i) {
    return i < weights.size() ? std::max(0.0, weights[i]) : 1.0;
  };

  // The dwells' headings (over every observation whatever its weight), the drift's zero time
  // (the earliest stamp) and the GNSS slices (their σ and mean time, for the Gauss–Markov chain
  // below).
  // Every dwell's scans use the dwell's heading, also when moving scans and a clock offset are
  // in the problem. (Until the dwells got their end guard, alignment.dwell_guard_s, the scans
  // of a turn's last moments sat in the dwells, and with this model the offset came out 0.093 s
  // for a true 0.15 s; a per-scan heading model was used for such sessions then.)
  const std::map<int, internal::DwellHeading> dwell_headings =
      internal::DwellHeadings(observations);
  double reference_s = std::numeric_limits<double>::infinity();
  for (const auto& observation : observations) {
    reference_s = std::min(reference_s, observation.pose.stamp_s);
  }
  if (!std::isfinite(reference_s)) reference_s = 0.0;
  mp->heading_reference_s = reference_s;
  std::map<int, internal::SegmentSums> sums;
  int moving = 0;
  for (size_t i = 0; i < observations.size(); ++i) {
    const auto& observation = observations[i];
    if (!(weight_of(i) > 0.0)) continue;
    if (!observation.pose.stationary) ++moving;
    const int segment = calib::GnssSegment(observation);
    if (segment < 0) continue;
    sums[segment].Add(observation, options);
  }
  std::map<int, int> segment_index;
  for (const auto& [segment, entry] : sums) {
    segment_index[segment] = static_cast<int>(mp->segment_ids.size());
    mp->segment_ids.push_back(segment);
    mp->bias_sigma_m.push_back(entry.sigma_m(options));
    mp->segment_mid_s.push_back(entry.mid_s());
  }
  mp->biases.assign(mp->segment_ids.size(), {0.0, 0.0});
  // Heading offsets: a dwell's mean heading is off by the mean of its samples' white errors,
  // σ_h / √n (Barawid 2007's FOG: 0.05° white at 20 Hz, 60 s dwell -> 0.002°). Moving segments get
  // none (σ 0: the zero block): their scans' heading errors are white and in their covariance.
  // One per station (pose.segment), whatever its GNSS-error slices.
  std::map<int, int> heading_index;
  for (const auto& [station, entry] : dwell_headings) {
    heading_index[station] = static_cast<int>(mp->heading_offsets.size());
    mp->heading_offsets.push_back({0.0});
    mp->heading_station_ids.push_back(station);
    const int samples = entry.samples();
    mp->heading_offset_sigma_rad.push_back(options.heading_sigma_rad /
                                           std::sqrt(std::max(1, samples)));
  }
  mp->heading_drift_estimated = options.heading_drift_sigma_rad_per_s > 0.0;
  // Time order and the correlation with the previous segment in it: ρ = exp(−Δt/τ).
  mp->segment_order.resize(mp->segment_ids.size());
  for (size_t k = 0; k < mp->segment_order.size(); ++k) mp->segment_order[k] = static_cast<int>(k);
  std::stable_sort(mp->segment_order.begin(), mp->segment_order.end(), [&mp](int a, int b) {
    return mp->segment_mid_s[a] < mp->segment_mid_s[b];
  });
  mp->segment_rho.assign(mp->segment_order.size(), 0.0);
  for (size_t k = 1; k < mp->segment_order.size(); ++k) {
    const double dt_s = mp->segment_mid_s[mp->segment_order[k]] -
                        mp->segment_mid_s[mp->segment_order[k - 1]];
    mp->segment_rho[k] = internal::SliceCorrelation(dt_s, options);
  }
  mp->time_offset_estimated = options.time_offset_sigma_s > 0.0 && moving >= kMinMovingObservations;
  const double scans_per_fix = MovingScansPerGnssFix(observations);

  // Everything fixed per observation, including W = L⁻¹ of its covariance, before the problem
  // takes any ownership (so that a bad covariance leaves nothing half-built).
  mp->measurements.reserve(observations.size());
  mp->wall_block.reserve(observations.size());
  mp->bias_block.reserve(observations.size());
  bool uses_no_bias = false;
  std::set<int> walls_used;
  for (size_t i = 0; i < observations.size(); ++i) {
    const calib::WallObservation& observation = observations[i];
    const calib::WallGeometry& wall = walls[observation.wall_index];
    const double weight = weight_of(i);
    WallLineMeasurement m;
    if (!internal::MakeMeasurement(observation, i, wall, options, lever_mount, weight,
                                   scans_per_fix, dwell_headings, reference_s, &m, error)) {
      return nullptr;
    }
    mp->measurements.push_back(m);
    mp->weights.push_back(weight);
    if (weight > 0.0) walls_used.insert(observation.wall_index);

    mp->wall_block.push_back(mp->wall_deltas[observation.wall_index].data());
    double* bias = mp->no_bias.data();
    const int segment = calib::GnssSegment(observation);
    const auto found = segment_index.find(segment);
    if (segment >= 0 && found != segment_index.end()) {
      // A segment whose σ_b is 0 has no error to estimate: it shares the constant zero block.
      if (mp->bias_sigma_m[found->second] > 0.0) bias = mp->biases[found->second].data();
    }
    if (weight > 0.0) uses_no_bias = uses_no_bias || bias == mp->no_bias.data();
    mp->bias_block.push_back(bias);
    double* heading = mp->no_heading_offset.data();
    const auto station = heading_index.find(observation.pose.segment);
    if (UsesDwellHeading(observation) && station != heading_index.end() &&
        mp->heading_offset_sigma_rad[station->second] > 0.0) {
      heading = mp->heading_offsets[station->second].data();
    }
    mp->heading_block.push_back(heading);
  }

  // Observation blocks, robustified scan by scan in whitened units (wall_slice_cost.h): the
  // observations that share every parameter block, up to kScansPerResidualBlock of them, form
  // one residual block. Observations of weight 0 get none.
  std::vector<std::vector<int>> groups =
      internal::ResidualGroups(mp->wall_block, mp->bias_block, mp->heading_block, mp->weights);
  for (std::vector<int>& group : groups) {
    const int first = group.front();
    mp->problem.AddResidualBlock(
        new WallSliceCost(mp->measurements, std::move(group), options.huber_scale),
        nullptr, mp->mount.data(), mp->wall_block[first], mp->bias_block[first],
        mp->time_offset.data(), mp->heading_block[first], mp->heading_drift.data());
  }

  // Wall priors, joint over the walls in the problem (they share the survey tie, see
  // WallPriorCovariance). A σ of 0 means the survey is taken as exact in that coordinate: the
  // coordinate is held constant (the whole block when both are 0) rather than given an
  // infinite weight, and is left out of the prior.
  std::vector<int> prior_walls;
  std::vector<std::pair<int, int>> prior_coordinates;  // (index into prior_walls, 0 d / 1 α)
  for (int w : walls_used) {
    double* block = mp->wall_deltas[w].data();
    const bool offset_free = walls[w].sigma_offset_m > 0.0;
    const bool angle_free = walls[w].sigma_angle_rad > 0.0;
    if (!offset_free && !angle_free) {
      mp->problem.SetParameterBlockConstant(block);
      continue;
    }
    if (!offset_free || !angle_free) {
      mp->problem.SetManifold(block, new ceres::SubsetManifold(2, {offset_free ? 1 : 0}));
    }
    const int index = static_cast<int>(prior_walls.size());
    prior_walls.push_back(w);
    if (offset_free) prior_coordinates.emplace_back(index, 0);
    if (angle_free) prior_coordinates.emplace_back(index, 1);
  }
  if (!prior_coordinates.empty()) {
    const Eigen::MatrixXd full = WallPriorCovariance(walls, prior_walls);
    const int k = static_cast<int>(prior_coordinates.size());
    Eigen::MatrixXd covariance(k, k);
    for (int r = 0; r < k; ++r) {
      for (int c = 0; c < k; ++c) {
        covariance(r, c) = full(2 * prior_coordinates[r].first + prior_coordinates[r].second,
                                2 * prior_coordinates[c].first + prior_coordinates[c].second);
      }
    }
    Eigen::LLT<Eigen::MatrixXd> llt(covariance);
    if (llt.info() != Eigen::Success || !(llt.matrixLLT().diagonal().minCoeff() > 0.0)) {
      // Not positive definite (inconsistent σ's of hand-made walls): the marginals alone.
      covariance = Eigen::MatrixXd(covariance.diagonal().asDiagonal());
      llt.compute(covariance);
    }
    const Eigen::MatrixXd whitening =
        llt.matrixL().solve(Eigen::MatrixXd::Identity(k, k));
    std::vector<double*> blocks;
    for (int w : prior_walls) blocks.push_back(mp->wall_deltas[w].data());
    mp->problem.AddResidualBlock(
        new JointPriorCost(whitening, prior_coordinates, std::vector<int>(blocks.size(), 2)),
        nullptr, blocks);
  }
  // GNSS bias priors: a first-order Gauss–Markov chain in time (the RTK error is correlated
  // over τ, and stations are often closer in time than that: independent priors per station
  // would count them as independent draws and make σ too small). The first segment of each
  // chain gets the marginal prior; a segment with σ_b = 0 (not in the problem, see above)
  // breaks the chain. ρ = exp(−Δt/τ) between segment mean times.
  int previous = -1;
  for (size_t k = 0; k < mp->segment_order.size(); ++k) {
    const int index = mp->segment_order[k];
    const double sigma_m = mp->bias_sigma_m[index];
    if (!(sigma_m > 0.0)) {
      previous = -1;
      continue;
    }
    const double rho = mp->segment_rho[k];
    if (previous < 0 || !(rho > 0.0)) {
      mp->problem.AddResidualBlock(GaussianPriorCost::Create(Eigen::Vector2d(sigma_m, sigma_m)),
                                   nullptr, mp->biases[index].data());
    } else {
      const double a = rho * sigma_m / mp->bias_sigma_m[previous];
      const double sigma_w = sigma_m * std::sqrt(1.0 - rho * rho);
      mp->problem.AddResidualBlock(GaussMarkovStepCost::Create(a, sigma_w), nullptr,
                                   mp->biases[previous].data(), mp->biases[index].data());
    }
    previous = index;
  }
  // Heading offsets of the dwells in the problem: zero-mean priors of σ_h / √n, independent
  // (white heading noise averaged over disjoint dwells).
  for (size_t k = 0; k < mp->heading_offsets.size(); ++k) {
    double* block = mp->heading_offsets[k].data();
    if (!(mp->heading_offset_sigma_rad[k] > 0.0) || !mp->problem.HasParameterBlock(block)) continue;
    mp->problem.AddResidualBlock(ScalarPriorCost::Create(mp->heading_offset_sigma_rad[k]), nullptr,
                                 block);
  }
  if (mp->problem.HasParameterBlock(mp->no_heading_offset.data())) {
    mp->problem.SetParameterBlockConstant(mp->no_heading_offset.data());
  }
  // The heading drift rate: prior σ_r; the data tell it through the trend of the wall's
  // direction in the scans over the session (the constant part is in the mount yaw).
  if (mp->problem.HasParameterBlock(mp->heading_drift.data())) {
    if (mp->heading_drift_estimated) {
      mp->problem.AddResidualBlock(
          ScalarPriorCost::Create(options.heading_drift_sigma_rad_per_s), nullptr,
          mp->heading_drift.data());
    } else {
      mp->problem.SetParameterBlockConstant(mp->heading_drift.data());
    }
  }
  // The zero bias of observations without a segment is data, not an estimate.
  if (uses_no_bias) mp->problem.SetParameterBlockConstant(mp->no_bias.data());
  // The clock offset: a prior of σ_dt when moving scans can tell it; otherwise held at 0 (at
  // a station the pose does not change with time, so dt is not in the data).
  // The heading delay rides in the same block: estimated with a prior of σ_δh beside dt (only
  // turns tell it, through ω), held at 0 when σ_δh is 0 (a constant coordinate, its prior
  // residual then a constant 0).
  // The priors are on the totals: what the poses already carry (the clock rounds' shifts,
  // pose.clock_shift_s and heading_shift_s, the same for every observation) is taken off their
  // centre, so that a round does not restart them where the last one ended.
  if (mp->problem.HasParameterBlock(mp->time_offset.data())) {
    if (mp->time_offset_estimated) {
      mp->heading_delay_estimated = options.heading_delay_sigma_s > 0.0;
      const calib::VehiclePose& carried = observations.front().pose;
      mp->problem.AddResidualBlock(
          GaussianPriorCost::Create(
              Eigen::Vector2d(options.time_offset_sigma_s,
                              mp->heading_delay_estimated ? options.heading_delay_sigma_s : 1.0),
              Eigen::Vector2d(-carried.clock_shift_s,
                              mp->heading_delay_estimated ? -carried.heading_shift_s : 0.0)),
          nullptr, mp->time_offset.data());
      if (!mp->heading_delay_estimated) {
        mp->problem.SetManifold(mp->time_offset.data(), new ceres::SubsetManifold(2, {1}));
      }
    } else {
      mp->problem.SetParameterBlockConstant(mp->time_offset.data());
    }
  }
  return mp;
}

void ApplyWarmStart(const WarmStart& warm, MountProblem* mp) {
  if (warm.wall_deltas.size() == mp->wall_deltas.size()) mp->wall_deltas = warm.wall_deltas;
  for (size_t k = 0; k < mp->segment_ids.size(); ++k) {
    const auto found = warm.biases.find(mp->segment_ids[k]);
    if (found != warm.biases.end()) mp->biases[k] = found->second;
  }
  for (size_t k = 0; k < mp->heading_station_ids.size(); ++k) {
    const auto found = warm.heading_offsets.find(mp->heading_station_ids[k]);
    if (found != warm.heading_offsets.end()) mp->heading_offsets[k][0] = found->second;
  }
  if (mp->heading_drift_estimated) mp->heading_drift[0] = warm.heading_drift_rad_per_s;
  if (mp->time_offset_estimated) {
    mp->time_offset[0] = warm.time_offset_s;
    if (mp->heading_delay_estimated) mp->time_offset[1] = warm.heading_delay_s;
  }
}

WarmStart WarmStartFrom(const MountProblem& mp) {
  WarmStart warm;
  warm.wall_deltas = mp.wall_deltas;
  for (size_t k = 0; k < mp.segment_ids.size(); ++k) warm.biases[mp.segment_ids[k]] = mp.biases[k];
  for (size_t k = 0; k < mp.heading_station_ids.size(); ++k) {
    warm.heading_offsets[mp.heading_station_ids[k]] = mp.heading_offsets[k][0];
  }
  warm.heading_drift_rad_per_s = mp.heading_drift[0];
  warm.time_offset_s = mp.time_offset[0];
  warm.heading_delay_s = mp.time_offset[1];
  return warm;
}

}  // namespace wallcal::solvers
