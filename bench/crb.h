// SPDX-License-Identifier: Apache-2.0
#pragma once
// The Cramér–Rao bound of the scanner mount (x, y, yaw) for a simulated session, from the
// simulator's own noise model (calib/simulator.h, configs/simulate/bench_*.yaml). Used by
// bench/accuracy_bench; the derivation is in docs/method.md ("The benchmarks' Cramér–Rao bound").
//
// Observations are per-scan wall lines (rho, theta) in the scanner frame. Everything else that
// is random in the simulation is marginalised into their covariance C, propagated linearly at
// the truth:
//   - the line fit: Fisher information of (rho, theta) from the beams that hit the wall
//     (noise-free ray cast, sim::TrueBeamHits), each with the range σ of the preset (after
//     the range correction, quantisation included) projected on the wall normal;
//   - the GNSS antenna error: Gauss–Markov bias (σ_b, τ: covariance σ_b² exp(−|Δt|/τ) between
//     scans) plus white noise at the GNSS epochs, interpolated linearly to the scan times;
//   - the heading error: white noise at the heading epochs, interpolated, plus the linear drift
//     (its sign is random: covariance r² t_k t_l);
//   - the wall lines: total-station noise on every surveyed point and on the control points,
//     RTK noise on the control points, through the two-point tie and the wall fit.
//   - on a 3-D site, the yard's grade or the attitude stream's noise and the walls' leans
//     (bench/crb_site.h);
//   - optionally, per-fix stamp jitter of the GNSS and heading streams (white, s): the pose is
//     off by velocity × jitter (position) and yaw rate × jitter (heading), interpolated.
// CRB = (Jᵀ C⁻¹ J + P)⁻¹ with J the Jacobian of the observations with respect to the mount and
// the delay unknowns (CrbDelays: the scanner clock offset, the GNSS stream's delay, the heading
// stream's delay, each with a zero-mean prior of information P), whose rows/columns are then
// marginalised (the top-left 3 × 3 of the inverse). Frames: the simulator's local ENU (the
// mount does not depend on the frame).
//
// Over which scans: ComputeCrb bounds any set of scans; AllSessionObservations gives every scan
// the simulated session holds (standing and moving, from the truth, not the scans calibrate
// chose), for the all-data bound.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "sim/simulation_config.h"
#include "io/types.h"

namespace wallcal::bench {

// Noise sources, for breakdowns (bit flags).
enum CrbSource : unsigned {
  kLineFit = 1u,
  kGnssBias = 2u,
  kGnssWhite = 4u,
  kHeadingWhite = 8u,
  kHeadingDrift = 16u,
  kSurvey = 32u,
  kSite = 64u,  // a 3-D site's yard grade, attitude stream and wall lean (bench/crb_site.h)
  kAllSources = 127u,
  // Not among kAllSources: each unit's range model off the preset's by an offset and a scale
  // drawn from the preset's range_model_sigma (sim draw_unit_range_models), one draw per
  // scanner shared by all its lines. A bench adds it when the simulation draws them.
  kUnitRange = 128u,
};

// One wall observation to bound: the scan's true time (s since the start of the run) and the
// wall it saw, as an index into the SURVEYED walls of the config (calibrate's wall_index).
struct CrbObservation {
  double t_s = 0.0;
  int surveyed_wall = 0;
  // Optional, for the oracle check: observed minus predicted (rho m, theta rad) at the TRUE
  // mount from the measured pose and surveyed wall (calib::PredictRho/PredictTheta).
  bool has_residual = false;
  Eigen::Vector2d residual = Eigen::Vector2d::Zero();
  // Which scanner took it (ComputeJointCrb's scanner_configs index; 0 for ComputeCrb).
  int scanner = 0;
};

struct CrbResult {
  bool ok = false;
  std::string message;          // why not ok
  Eigen::Matrix3d crb = Eigen::Matrix3d::Zero();  // x, y, yaw covariance bound (m, m, rad)
  // ComputeJointCrb: the bound of every scanner's mount, [x_0, y_0, yaw_0, x_1, ...] (crb is
  // its top-left block).
  Eigen::MatrixXd joint_crb;
  // With kUnitRange: what an estimator that takes each unit's model as exact but carries its σ
  // in the covariance reaches (calibrate's joint adjustment, solvers/joint_mounts.h): the bound
  // without the units' terms plus the mounts' linear response to them. joint_crb estimates
  // them instead, as far as the data tell them apart.
  Eigen::MatrixXd joint_consider;
  int observations_used = 0;    // after subsampling and dropping lines with < 2 wall beams
  int observations_given = 0;
  bool subsampled = false;
  // When every used observation has a residual: the linear GLS estimate with the true C,
  // δm = (Jᵀ C⁻¹ J)⁻¹ Jᵀ C⁻¹ r (the estimate minus the truth). Over many runs its RMS should
  // match the bound if C describes the simulation: a check of the bound itself.
  bool has_oracle = false;
  Eigen::Vector3d oracle_error = Eigen::Vector3d::Zero();
  Eigen::VectorXd oracle_joint_error;  // every scanner's, [x_0, y_0, yaw_0, x_1, ...]
  // When the scanner offset and the heading delay are both unknowns: the bound (1σ, s) on the
  // timing calibrate reports, relative to the GNSS epochs: the position's time shift (calibrate's
  // scanner clock offset dt = offset − GNSS delay), the heading's delay after the positions
  // (δh = GNSS delay − heading delay) and the heading's time shift (dt + δh, what turns need).
  // The data fix these whatever the priors do with the common part.
  bool has_delay_bound = false;
  double delay_bound_dt_s = 0.0, delay_bound_dh_s = 0.0, delay_bound_sum_s = 0.0;
};

// The delays as unknowns. Each prior σ > 0 makes that delay an unknown of the bound with a
// zero-mean Gaussian prior of that σ (s), marginalised; 0: known exactly (no unknown). The
// three are not separable from the data alone (the scanner offset shifts the position and the
// heading alike, which a GNSS delay plus an equal heading delay also do): their priors decide
// how the common part is shared, the data decide the rest (a position shift from driving, a
// heading shift from turning). Jitter: white per-fix stamp noise (s, 1σ) of each stream.
struct CrbDelays {
  double scanner_offset_prior_sigma_s = 0.0;
  double gnss_delay_prior_sigma_s = 0.0;
  double heading_delay_prior_sigma_s = 0.0;
  double gnss_jitter_sigma_s = 0.0;
  double heading_jitter_sigma_s = 0.0;
};
// A prior this wide is flat for any session (an offset known to ±10 s carries no information).
inline constexpr double kFlatDelayPriorS = 10.0;

// The bound for `observations` (any order). At most max_observations are used (an even
// subsample by time when more are given: C is dense, 2N × 2N, O(N³) to factor; <= 0: all).
// `sources`: CrbSource flags; kLineFit should always be among them (without it C is singular).
CrbResult ComputeCrb(const sim::SimulationConfig& config, const io::ScannerPreset& preset,
                     const std::vector<CrbObservation>& observations, unsigned sources,
                     const CrbDelays& delays, int max_observations);

// The joint bound of several scanners on one vehicle: scanner_configs[k] is the session's
// configuration with scanner k's mount and clock (sim::ForScanner); every observation names its
// scanner. The vehicle's errors (GNSS, heading, survey) are common to all scanners' lines; each
// scanner has its own mount and, with a scanner-offset prior, its own clock offset; the GNSS and
// heading delays are shared. The delay bounds are filled for one scanner only.
CrbResult ComputeJointCrb(const std::vector<sim::SimulationConfig>& scanner_configs,
                          const io::ScannerPreset& preset,
                          const std::vector<CrbObservation>& observations, unsigned sources,
                          const CrbDelays& delays, int max_observations);

// Every scan the simulated session holds (each log_every_n-th scan of the preset's rate over the
// run, at its true time; lost scans are random and left in) paired with every surveyed wall it
// sees with at least min_wall_beams returned, unoccluded beams (sim::TrueBeamHits), standing
// and moving alike. No residuals (the truth has none).
std::vector<CrbObservation> AllSessionObservations(const sim::SimulationConfig& config,
                                                   const io::ScannerPreset& preset,
                                                   int min_wall_beams);

}  // namespace wallcal::bench
