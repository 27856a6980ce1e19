// SPDX-License-Identifier: Apache-2.0
#pragma once
// The joint mount adjustment as a Ceres problem, built apart from solving it.
// SolveMountCeres (mount_solver.h) is CheckObservability + BuildMountProblem + SolveMountProblem
// (+ one rebuild when the lever arm used for the noise model moved, see ceres_solver.cc).
// Exposed for the tests; the pipeline calls SolveMountCeres.

#include <ceres/ceres.h>

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "calib/observation.h"
#include "solvers/solver_options.h"
#include "solvers/mount_solver.h"
#include "solvers/wall_line_cost.h"

namespace wallcal::solvers {

// Where a solve ended, to start the next one from (the clock-offset rounds, solve_policy.cc):
// the nuisance parameters by what they belong to (wall index, GNSS slice id, station id), since
// a round's problem is built anew from re-interpolated observations.
struct WarmStart {
  std::vector<std::array<double, 2>> wall_deltas;    // per wall index
  std::map<int, std::array<double, 2>> biases;       // by GNSS slice id
  std::map<int, double> heading_offsets;             // by station id
  double heading_drift_rad_per_s = 0.0;
  // The time block: what of the clock offset and the heading delay the poses do not carry
  // (solve_policy.cc moves into the poses only what the data determine).
  double time_offset_s = 0.0;
  double heading_delay_s = 0.0;
  // The round before passed its checks without being forced: the check before this solve, on
  // the same geometry, is not made again.
  bool checked = false;
};

// Owns the Ceres problem and the parameter values it points into. Not copyable or movable
// (Ceres holds the addresses): handled through std::unique_ptr.
struct MountProblem {
  MountProblem() = default;
  MountProblem(const MountProblem&) = delete;
  MountProblem& operator=(const MountProblem&) = delete;

  std::array<double, 3> mount{};  // [x_m, y_m, yaw_rad], starts at the initial mount
  // Per wall (same index as the walls vector): [δd_m, δα_rad], starts at 0. A wall no
  // observation refers to is not in the problem.
  std::vector<std::array<double, 2>> wall_deltas;
  // Per GNSS segment: the pose.segment ids (ascending), their bias [east_m, north_m] (starts at
  // 0) and the prior σ_b used (m). A segment with σ_b = 0 is held constant at 0.
  std::vector<int> segment_ids;
  std::vector<std::array<double, 2>> biases;
  std::vector<double> bias_sigma_m;
  std::vector<double> segment_mid_s;  // mean stamp of each segment's observations
  // Segment indices (into segment_ids) in time order, and the Gauss–Markov correlation ρ
  // between each and the previous one in that order (0 for the first).
  std::vector<int> segment_order;
  std::vector<double> segment_rho;
  // Scanner clock offset and heading delay [dt_s, δh_s]; constant at 0 unless
  // time_offset_estimated (δh also held at 0 when options.heading_delay_sigma_s is 0).
  std::array<double, 2> time_offset{};
  bool time_offset_estimated = false;
  bool heading_delay_estimated = false;
  // Heading errors (docs/method.md, "Heading errors"). Per segment (same index as segment_ids):
  // the heading offset h [rad] common to a dwell's scans (true yaw = dwell mean yaw − h − r·τ),
  // starting at 0, and its prior σ (σ_heading / √(heading samples averaged)); 0 for a moving
  // segment, whose scans use their own interpolated yaw and keep the white heading noise in
  // their covariance (they share the constant zero block no_heading_offset).
  std::vector<std::array<double, 1>> heading_offsets;
  std::vector<double> heading_offset_sigma_rad;
  std::vector<int> heading_station_ids;  // the station (pose.segment) of each heading offset
  // The heading drift rate r [rad/s], one for the session, with the prior
  // options.heading_drift_sigma_rad_per_s (held at 0 when that is 0), and the reference time
  // t_ref [s] (the earliest observation's stamp) at which the heading error is taken as the
  // zero of the mount yaw.
  std::array<double, 1> heading_drift{};
  bool heading_drift_estimated = false;
  double heading_reference_s = 0.0;
  std::array<double, 1> no_heading_offset{};
  // Held constant at 0: the bias of observations without a segment (their GNSS error is in
  // their white noise instead).
  std::array<double, 2> no_bias{};
  // Per observation, input order.
  std::vector<WallLineMeasurement> measurements;
  std::vector<double> weights;       // information multiplier (0: no residual block)
  std::vector<double*> wall_block;  // the wall block each observation uses
  std::vector<double*> bias_block;  // the bias block each observation uses (maybe no_bias)
  std::vector<double*> heading_block;  // the heading-offset block (maybe no_heading_offset)
  // The mount's marginal information at the last solution, when the solve computed it (with
  // its covariance): the checks after the solve use it instead of evaluating the Jacobian again.
  bool has_mount_information = false;
  Eigen::Matrix3d mount_information = Eigen::Matrix3d::Zero();
  // Declared last so that it goes first, while the values it points into still exist.
  ceres::Problem problem;
};

// The joint prior covariance of the wall nuisance parameters [δd_0, δα_0, δd_1, δα_1, ...]
// (m², m·rad, rad²) of walls[indices[0]], walls[indices[1]], ...: each wall's own σ's and
// cov_offset_angle on the diagonal blocks; between two walls the part of the survey tie they
// share (WallGeometry::tie_*: the same translation, seen along each wall's normal, and the same
// rotation about the control centroid). Walls made without a tie share nothing.
Eigen::MatrixXd WallPriorCovariance(const std::vector<calib::WallGeometry>& walls,
                                    const std::vector<int>& indices);

// Builds the problem (see wall_line_cost.h and prior_cost.h for the residuals). The noise model
// of each observation uses `lever_mount` for the lever arm that turns heading noise into rho
// noise; the parameters start at `initial`. Assumes CheckObservability passed (wall indices in
// range). Returns nullptr and sets *error when an observation's covariance is not positive
// definite (all its σ zero). `weights` (empty, or one per observation, >= 0) multiplies each
// observation's information (0: left out), for the bootstrap. The segment biases form a
// Gauss–Markov chain in time (options.gnss_bias_tau_s); the time offset is estimated (prior
// options.time_offset_sigma_s) when at least kMinMovingObservations observations are not
// stationary.
inline constexpr int kMinMovingObservations = 20;

// True when the observation was taken at a station (stationary, segment >= 0): the solver then
// uses the dwell's mean heading (pose.dwell_yaw_rad, or the mean of the segment's observed yaws
// when that is not filled) instead of the scan's own noisy yaw.
inline bool UsesDwellHeading(const calib::WallObservation& observation) {
  return observation.pose.stationary && observation.pose.segment >= 0;
}
std::unique_ptr<MountProblem> BuildMountProblem(
    const std::vector<calib::WallObservation>& observations,
    const std::vector<calib::WallGeometry>& walls, const solvers::SolverOptions& options,
    const Mount& lever_mount, const Mount& initial, std::string* error,
    const std::vector<double>& weights = {});

// Sets the problem's parameters from `warm` where it has them, and reads them back into a
// WarmStart.
void ApplyWarmStart(const WarmStart& warm, MountProblem* mp);
WarmStart WarmStartFrom(const MountProblem& mp);

// The information matrix of the mount: solvers/information.h.

// The 2x2 covariance (m², m·rad, rad²) of one observation's [rho; theta] error before the
// nuisance parameters: line fit + GNSS white noise along the normal (plus the bias σ when the
// observation has no segment) + heading white noise through the lever arm, the last only for
// an observation that uses its own per-scan yaw (moving, see UsesDwellHeading): a dwell's
// scans use the dwell's mean heading, whose error is the segment's heading-offset parameter.
// `bias_sigma_m` is the σ that goes into the white part for segment −1 (ignored otherwise).
// A moving observation (one that does not use its dwell's heading) also gets
// MovingPoseCovariance, and its GNSS white variance times scans_per_gnss_fix (>= 1; the scans
// between two fixes share their noise: MovingScansPerGnssFix).
//
// `shared` leaves out the white noise the joint adjustment of several scanners carries as
// parameters shared by every scanner's scans between the same samples (solvers/joint_mounts.cc,
// solvers/epoch_noise_cost.h): the GNSS white noise (with its scans-per-fix factor) and the
// heading white noise of a moving observation.
struct SharedWhiteNoise {
  bool gnss_fixes = false;
  bool heading_samples = false;
};
Eigen::Matrix2d ObservationCovariance(const calib::WallObservation& observation,
                                      const calib::WallGeometry& wall,
                                      const solvers::SolverOptions& options, const Mount& lever_mount,
                                      double bias_sigma_m, double scans_per_gnss_fix = 1.0,
                                      SharedWhiteNoise shared = SharedWhiteNoise());

// The σ of the correlated GNSS error an observation without a GNSS-error slice carries in its
// own covariance (m): the GST σ when the log has one and the options allow it, the configured
// bias σ otherwise (the `bias_sigma_m` BuildMountProblem gives ObservationCovariance).
double PoseBiasSigma(const calib::VehiclePose& pose, const solvers::SolverOptions& options);

// The pose uncertainty of a moving scan in its [rho; theta] (m², m·rad, rad²); zero for a scan
// that uses its dwell's heading. The position and the heading samples each off in time by
// options.moving_timing_sigma_s (white): rho by (n·v) δ, the heading by ω δ' (through the lever
// arm's along-wall part ell_m into rho too); plus linear interpolation between GNSS fixes on a
// curve, RMS |v| |ω| T² / (2 √30) with T = pose.gnss_period_s, into rho. normal_local: the
// wall's normal oriented from the scanner to the wall.
Eigen::Matrix2d MovingPoseCovariance(const calib::WallObservation& observation,
                                     const Eigen::Vector2d& normal_local, double ell_m,
                                     const solvers::SolverOptions& options);

// How well the time block fixes the drives' poses (s): the σ of the rho shift that the
// uncertainty of [clock offset dt, heading delay δh] (time_covariance, s²) puts on the moving
// observations, over their sensitivity to dt. A moving scan's rho moves by (n·v + ℓω)·dt +
// ℓω·δh and its theta by ω·(dt + δh) (wall_line_cost.h; theta counted in metres at the
// observation's range): driving towards a wall needs dt itself, turning in front of it only
// dt + δh, which the turns fix even when dt and δh are not separable (drives along one wall).
// 0 when no observation is moving.
double DrivesTimingSigma(const std::vector<calib::WallObservation>& observations,
                         const std::vector<calib::WallGeometry>& walls, const Mount& lever_mount,
                         const Eigen::Matrix2d& time_covariance);

// How many of the moving observations fall between two GNSS fixes, on the median: the GNSS
// period (pose.gnss_period_s) over the median step between distinct moving scan stamps;
// >= 1, 1 when there are no moving observations or no period.
double MovingScansPerGnssFix(const std::vector<calib::WallObservation>& observations);

// Solves and fills the estimate (mount, covariance from the mount's marginal information with
// every nuisance block free (solvers/information.cc), residuals, report). Never throws; failures come back as usable = false.
// compute_covariance false: stop after the solve and the residuals (usable = converged).
MountEstimate SolveMountProblem(MountProblem& problem, const solvers::SolverOptions& options,
                                bool compute_covariance = true);

}  // namespace wallcal::solvers
