// SPDX-License-Identifier: Apache-2.0
// What BuildMountProblem and ExtendMountProblem make of each observation
// (solvers/internal/observation_rows.h).
#include "solvers/internal/observation_rows.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>

#include "calib/wall_geometry.h"
#include "solvers/mount_problem.h"

namespace wallcal::solvers::internal {
namespace {

// Slices closer in time than ~τ/10⁵ are one GNSS error: ρ is capped so that the chain step's
// σ (σ_b √(1 − ρ²) ≥ 0.0045 σ_b) stays a usable weight. Slices are 0.25 s by default, so
// ρ = 0.99958 at τ = 600 s must pass uncapped.
constexpr double kMaxSegmentCorrelation = 0.99999;

// Scans in one residual block at most (wall_slice_cost.h): a 0.25 s slice of a 75 Hz scanner
// has 19; the cap bounds a block's Jacobian when slices are long.
constexpr size_t kScansPerResidualBlock = 32;

}  // namespace

double DwellHeading::yaw_rad() const {
  return pose_samples > 0 ? pose_yaw_rad : std::atan2(sin_sum, cos_sum);
}
double DwellHeading::mid_s() const { return pose_samples > 0 ? pose_mid_s : stamp_sum / count; }
int DwellHeading::samples() const { return pose_samples > 0 ? pose_samples : count; }

std::map<int, DwellHeading> DwellHeadings(const std::vector<calib::WallObservation>& observations) {
  std::map<int, DwellHeading> dwells;
  for (const auto& observation : observations) {
    if (!UsesDwellHeading(observation)) continue;
    DwellHeading& entry = dwells[observation.pose.segment];
    entry.sin_sum += std::sin(observation.pose.yaw_rad);
    entry.cos_sum += std::cos(observation.pose.yaw_rad);
    entry.stamp_sum += observation.pose.stamp_s;
    entry.count += 1;
    if (observation.pose.dwell_yaw_samples > 0) {
      entry.pose_yaw_rad = observation.pose.dwell_yaw_rad;
      entry.pose_mid_s = observation.pose.dwell_mid_s;
      entry.pose_samples = observation.pose.dwell_yaw_samples;
    }
  }
  return dwells;
}

void SegmentSums::Add(const calib::WallObservation& observation, const SolverOptions& options) {
  if (options.use_gst_sigma && observation.pose.gnss_sigma_m > 0.0) {
    gst_sum += observation.pose.gnss_sigma_m;
    gst_count += 1;
  }
  stamp_sum += observation.pose.stamp_s;
  count += 1;
}

double SegmentSums::sigma_m(const SolverOptions& options) const {
  return gst_count > 0 ? gst_sum / gst_count : options.gnss_bias_sigma_m;
}

double SliceCorrelation(double dt_s, const SolverOptions& options) {
  return options.gnss_bias_tau_s > 0.0
             ? std::min(kMaxSegmentCorrelation,
                        std::exp(-std::max(0.0, dt_s) / options.gnss_bias_tau_s))
             : 0.0;
}

bool MakeMeasurement(const calib::WallObservation& observation, size_t index,
                     const calib::WallGeometry& wall, const SolverOptions& options,
                     const Mount& lever_mount, double weight, double scans_per_fix,
                     const std::map<int, DwellHeading>& dwells, double reference_s,
                     WallLineMeasurement* measurement, std::string* error) {
  const calib::OrientedWall oriented = calib::OrientWall(wall, observation.pose.antenna_local_m);
  // An observation of weight 0 gets no residual block: its noise model is never used (the
  // re-solves of the repeatability pass most observations with weight 0).
  Eigen::Matrix2d sqrt_information = Eigen::Matrix2d::Identity();
  if (weight > 0.0) {
    const double bias_sigma_m = options.use_gst_sigma && observation.pose.gnss_sigma_m > 0.0
                                    ? observation.pose.gnss_sigma_m
                                    : options.gnss_bias_sigma_m;
    const Eigen::Matrix2d covariance =
        ObservationCovariance(observation, wall, options, lever_mount, bias_sigma_m, scans_per_fix);
    const Eigen::LLT<Eigen::Matrix2d> llt(covariance);
    if (llt.info() != Eigen::Success || !(llt.matrixLLT().diagonal().minCoeff() > 0.0)) {
      if (error != nullptr) {
        *error = "observation " + std::to_string(index) + " (scan " +
                 std::to_string(observation.scan_index) +
                 ") has no usable noise model: its covariance is not positive definite (line "
                 "fit σ and every noise σ in the options are zero?)";
      }
      return false;
    }
    sqrt_information =
        std::sqrt(weight) * Eigen::Matrix2d(llt.matrixL().solve(Eigen::Matrix2d::Identity()));
  }
  WallLineMeasurement m;
  m.antenna_local_m = observation.pose.antenna_local_m;
  m.vehicle_yaw_rad = observation.pose.yaw_rad;
  m.drift_time_s = observation.pose.stamp_s - reference_s;
  m.velocity_local_mps = observation.pose.velocity_local_mps;
  m.yaw_rate_rps = observation.pose.yaw_rate_rps;
  if (UsesDwellHeading(observation)) {
    // The true yaw is constant over a dwell: use the dwell's mean heading (and its time for
    // the drift), not this scan's noisy sample. A per-scan heading in the lever-arm rotation
    // would correlate the mount's Jacobian with the residual (errors in variables) and bias
    // x in proportion to the number of scans (docs/results.md, solver scaling).
    // The dwell's yaw is constant by definition: no yaw-rate term (a rate from a window that
    // reaches past the dwell's end would tie the clock offset to the dwell's exact heading).
    m.yaw_rate_rps = 0.0;
    m.velocity_local_mps.setZero();
    const DwellHeading& entry = dwells.at(observation.pose.segment);
    m.vehicle_yaw_rad = entry.yaw_rad();
    m.drift_time_s = entry.mid_s() - reference_s;
  }
  m.sign = oriented.sign;
  m.wall_normal_local = wall.normal_local;
  // The rotation centre: the middle of the surveyed extent, projected onto the line.
  const Eigen::Vector2d middle = 0.5 * (wall.end_a_local + wall.end_b_local);
  m.wall_centre_local_m =
      middle - (wall.normal_local.dot(middle) - wall.offset_m) * wall.normal_local;
  m.wall_normal_angle_rad = oriented.normal_angle_rad;
  m.rho_m = observation.rho_m;
  m.theta_rad = observation.theta_rad;
  m.sqrt_information = sqrt_information;
  if (weight > 0.0) m.weight = weight;
  *measurement = m;
  return true;
}

std::vector<std::vector<int>> ResidualGroups(const std::vector<double*>& wall_block,
                                             const std::vector<double*>& bias_block,
                                             const std::vector<double*>& heading_block,
                                             const std::vector<double>& weights) {
  std::map<std::array<const double*, 3>, size_t> open_group;  // (wall, bias, heading) -> group
  std::vector<std::vector<int>> groups;
  for (size_t i = 0; i < weights.size(); ++i) {
    if (!(weights[i] > 0.0)) continue;
    const std::array<const double*, 3> key = {wall_block[i], bias_block[i], heading_block[i]};
    auto found = open_group.find(key);
    if (found == open_group.end() || groups[found->second].size() >= kScansPerResidualBlock) {
      found = open_group.insert_or_assign(key, groups.size()).first;
      groups.emplace_back();
    }
    groups[found->second].push_back(static_cast<int>(i));
  }
  return groups;
}

}  // namespace wallcal::solvers::internal
