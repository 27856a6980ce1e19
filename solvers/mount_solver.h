// SPDX-License-Identifier: Apache-2.0
#pragma once
// Estimating the scanner mount (vehicle_T_scanner = [x_m, y_m, yaw_rad]) from wall
// observations. Two methods on the same observations:
//  - SolveMountCeres: the joint least-squares adjustment (robust loss, nuisance parameters for
//    the wall lines and the correlated GNSS error per segment; the covariance is the inverse of
//    the mount's marginal information, solvers/information.cc);
//  - SolveMountBarawid: the closed form of Barawid 2007 (Eq. 8-16), for comparison.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/observation.h"
#include "solvers/solver_options.h"

namespace wallcal::solvers {

// The two methods on the same observations (solvers/solve_policy.h runs the one asked for).
enum class Method { kCeres, kBarawid };
const char* MethodName(Method method);  // "ceres", "barawid"

struct WarmStart;  // solvers/mount_problem.h

// The mount estimated: vehicle_T_scanner (calib/observation.h).
using calib::Mount;


// Why an estimate is not usable: typed, for the callers' decisions (the message is for people).
enum class EstimateFailure {
  kNone,
  kWallNotDetected,  // no wall observation at all (set by the caller that looked for them)
  kNotDetermined,    // an observability check refused: too few stations, headings, ...
  kBadInput,         // observations that cannot form a problem (bad wall index, ...)
  kSolveFailed,      // Ceres could not solve
  kNotConverged,     // ran out of iterations
  kCovariance,       // the mount covariance could not be computed or is not positive
  kOutsideMountGuess,  // farther from scanner.mount_guess than its tolerance (set by pipeline/)
};

// What weakens an estimate without refusing it, typed: the kind says what a caller may act on,
// the message is for people. A forced kind's message starts with "FORCED: ".
enum class SolverWarningKind {
  kForcedObservability,       // force: an observability or determination check failed
  kFewIndependentGnssErrors,  // the stations count as few independent GNSS-error realisations
};
struct SolverWarning {
  SolverWarningKind kind = SolverWarningKind::kForcedObservability;
  std::string message;
};

struct MountEstimate {
  Mount mount;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // x, y, yaw (m, m, rad)
  bool usable = false;  // false: do not write offsets; `failure` and `message` say why
  EstimateFailure failure = EstimateFailure::kNone;
  std::string message;
  std::optional<Method> method;  // empty: no solve made this estimate (the run stopped before)
  int observations_used = 0;
  int observations_rejected = 0;  // down-weighted as outliers by the robust loss (> 3σ)
  double residual_rms_m = 0.0;    // RMS of the distance residuals of used observations
  std::vector<double> residual_rho_m;  // per observation (same order as the input), metres
  std::string solver_report;  // Ceres' brief report, or a line for barawid
  // Observability (ceres; barawid fills what its checks know). forced: an observability check
  // failed but the caller asked for the estimate anyway (usable stays true; `warnings` then
  // starts with the kForcedObservability ones and the covariance says how little is known).
  bool forced = false;
  std::vector<SolverWarning> warnings;
  std::string weak_direction;  // e.g. "lateral offset y"; empty when every direction is fine
  // Stations counted as independent GNSS-error realisations (Gauss–Markov, τ): 1 + Σ (1 − ρ²)
  // over consecutive segments with ρ = exp(−Δt/τ).
  double independent_stations = 0.0;
  // Scanner clock offset (true scan time = stamped + dt), estimated when moving scans are used.
  bool time_offset_estimated = false;
  double time_offset_s = 0.0;
  double time_offset_sigma_s = 0.0;
  // The heading stream's delay relative to the GNSS epochs (s; see wall_line_cost.h), estimated
  // beside the clock offset when solver.heading_delay_sigma_s > 0; its prior σ, for the
  // determination check (pipeline: determined when σ < half the prior).
  bool heading_delay_estimated = false;
  double heading_delay_s = 0.0;
  double heading_delay_sigma_s = 0.0;
  double heading_delay_prior_sigma_s = 0.0;
  // Covariance (s²) of [clock offset, heading delay] when the clock offset is estimated (the
  // heading delay's row and column zero when it is not): what the drives' poses depend on
  // (DrivesTimingSigma).
  Eigen::Matrix2d time_covariance = Eigen::Matrix2d::Zero();
  // The last solve's time block as it stands: [clock offset left after the poses were shifted
  // (solve_policy.h), heading delay] (s). What the repeatability's re-solves hold.
  std::array<double, 2> time_block_s{};
  // Where the adjustment ended: every nuisance parameter by what it belongs to, for re-solves
  // to start from (the repeatability's; null when no Ceres problem was solved).
  std::shared_ptr<const WarmStart> solution_state;
  // Heading drift rate (rad/s, true yaw = used yaw − r·(t − t_ref)) and the reference time t_ref
  // (s, the earliest observation) at which the mount yaw is relative to the heading sensor's
  // zero. Estimated (ceres) when options.heading_drift_sigma_rad_per_s > 0.
  bool heading_drift_estimated = false;
  double heading_drift_rad_per_s = 0.0;
  double heading_drift_sigma_rad_per_s = 0.0;
  double heading_reference_s = 0.0;
  // Estimated GNSS bias per segment (ceres): pose.segment id, bias [east, north] (m) and its
  // prior σ (m), in time order.
  std::vector<int> segment_ids;
  std::vector<Eigen::Vector2d> segment_bias_m;
  std::vector<double> segment_bias_sigma_m;
};

// The estimate's method as offsets.yaml, the summary and the JSON write it ("ceres",
// "barawid"); "" when no solve made it.
inline const char* MethodText(const MountEstimate& estimate) {
  return estimate.method ? MethodName(*estimate.method) : "";
}

// `force`: when an observability check fails (before or after the solve), solve anyway and
// return the estimate as usable with forced = true and a kForcedObservability warning, instead
// of refusing. Checks that make a solve impossible (no observations, bad wall index) still refuse.

// The clock-offset rounds (solve_policy.h) pass `warm`, where the round before ended: the
// nuisance parameters start there, and with warm->checked the determination check before the
// solve is not made again (the round before passed it on the same geometry; the check after the
// solve still is). `ended`, when given, receives where this solve ended.
// `observation_weight` multiplies every observation's information: a preview (inspect) solves
// on every k-th observation with weight k (analysis::ThinForRefits), which keeps the mount's
// information, and so its σ and the checks on it, about those of the whole set.
MountEstimate SolveMountCeres(const std::vector<calib::WallObservation>& observations,
                              const std::vector<calib::WallGeometry>& walls,
                              const solvers::SolverOptions& options, const Mount& initial,
                              bool force = false, const WarmStart* warm = nullptr,
                              WarmStart* ended = nullptr, double observation_weight = 1.0);

// A clock round's re-solve (solve_policy.h) after the observations' poses were moved to the
// shifted times: the problem built anew at before.mount, started at `warm`, and taken
// kClockRoundSteps Gauss–Newton steps (Ceres's trust region opened to a damping of 1e-8), with
// the covariance, the time block's covariance, the σ's and the checks of `before` (the solve on
// the same observations before the shift, usable). A round moves the estimate of a delay by the
// linear model's error over it (a few of its σ at most): the Jacobian hardly changes, so a step
// from where the solve before ended lands on the new minimum to second order, and the
// information there is that of the solve before to the same order; a full solve would add more
// iterations and the covariance, about the main solve's cost. Two steps: where a round moves the
// moving scans' residuals past the robust loss's corner (a small session, few moving scans,
// a large σ), the first step's weights are those of the start; the second redoes them
// (ClockRoundStepTest: 3 σ of dt off, x 0.12 σ from the full solve after one step, 0.04 σ after
// two). Not usable (failure kSolveFailed) when a step cannot be evaluated. `ended` receives
// where the steps ended.
inline constexpr int kClockRoundSteps = 2;
MountEstimate ClockRoundStep(const std::vector<calib::WallObservation>& observations,
                             const std::vector<calib::WallGeometry>& walls,
                             const solvers::SolverOptions& options, const MountEstimate& before,
                             const WarmStart& warm, WarmStart* ended,
                             double observation_weight = 1.0);

MountEstimate SolveMountBarawid(const std::vector<calib::WallObservation>& observations,
                                const std::vector<calib::WallGeometry>& walls,
                                const solvers::SolverOptions& options, bool force = false);

// A quick re-solve for repeatability (split sessions, bootstrap): the Ceres adjustment with
// each observation's information multiplied by weights[i] (>= 0; 0 drops it; weights empty:
// all 1), started from `initial`, at most `max_iterations`, no Ceres covariance. `covariance`
// is the mount covariance from the information matrix (nuisance parameters marginalised),
// `determined` whether it passes options.max_sigma_*. held_time_block: when the problem has a
// time block, it is held at these values (the full solution's clock, MountEstimate::time_block_s)
// instead of re-estimated from the subset. warm: the nuisance parameters start there (the full
// solution's, MountEstimate::solution_state) instead of at 0. Never throws.
struct Refit {
  bool converged = false;
  bool determined = false;
  Mount mount;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};
Refit RefitMount(const std::vector<calib::WallObservation>& observations,
                 const std::vector<calib::WallGeometry>& walls, const solvers::SolverOptions& options,
                 const Mount& initial, const std::vector<double>& weights, int max_iterations,
                 const std::array<double, 2>* held_time_block = nullptr,
                 const WarmStart* warm = nullptr);

}  // namespace wallcal::solvers
