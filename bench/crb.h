#pragma once
// The Cramér–Rao bound of the scanner mount (x, y, yaw) for a simulated session, from the
// simulator's own noise model (calib/simulator.h, configs/simulate/bench_*.yaml). Used by
// bench/accuracy_bench; the derivation is in docs/results.md.
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
// CRB = (Jᵀ C⁻¹ J)⁻¹ with J the Jacobian of the observations with respect to the mount (and,
// optionally, a scanner-clock offset as a fourth parameter, whose row/column is then
// marginalised). Frames: the simulator's local ENU (the mount does not depend on the frame).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "io/options.h"
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
  kAllSources = 63u,
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
};

struct CrbResult {
  bool ok = false;
  std::string message;          // why not ok
  Eigen::Matrix3d crb = Eigen::Matrix3d::Zero();  // x, y, yaw covariance bound (m, m, rad)
  int observations_used = 0;    // after subsampling and dropping lines with < 2 wall beams
  int observations_given = 0;
  bool subsampled = false;
  // When every used observation has a residual: the linear GLS estimate with the true C,
  // δm = (Jᵀ C⁻¹ J)⁻¹ Jᵀ C⁻¹ r (the estimate minus the truth). Over many runs its RMS should
  // match the bound if C describes the simulation: a check of the bound itself.
  bool has_oracle = false;
  Eigen::Vector3d oracle_error = Eigen::Vector3d::Zero();
};

// The bound for `observations` (any order). At most max_observations are used (an even
// subsample by time when more are given: C is dense, 2N × 2N). `sources`: CrbSource flags;
// kLineFit should always be among them (without it C is singular). With estimate_time_offset
// a common scanner-clock offset is a fourth unknown (its information comes from the motion).
CrbResult ComputeCrb(const io::SimulationConfig& config, const io::ScannerPreset& preset,
                     const std::vector<CrbObservation>& observations, unsigned sources,
                     bool estimate_time_offset, int max_observations);

}  // namespace wallcal::bench
