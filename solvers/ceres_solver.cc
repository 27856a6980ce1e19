// SPDX-License-Identifier: Apache-2.0
// The joint mount adjustment: Barawid 2007's wall geometry (Eq. 8-10) written as one least-squares
// problem over every scan, with the things Barawid 2007 treats as exact made uncertain instead:
// the surveyed wall lines (offset and direction) and the RTK-GNSS error that is common to all
// scans of one station. Estimating those nuisance parameters with their priors is what keeps
// the mount σ honest: thousands of scans at one station share one GNSS error, so the σ must
// not shrink as 1/√N.

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "solvers/information.h"
#include "solvers/mount_problem.h"
#include "solvers/mount_solver.h"
#include "solvers/observability.h"
#include "solvers/prior_cost.h"
#include "solvers/wall_line_cost.h"

namespace wallcal::solvers {

namespace {

// Whitened residual norm beyond which an observation counts as rejected (reported only; the
// Huber loss is what down-weights it).
constexpr double kRejectWhitenedNorm = 3.0;

// When the solution's (x, y) is this far from the mount the noise model's lever arms were
// computed with, the problem is rebuilt with the solution's lever arms and solved once more.
constexpr double kLeverRebuildDistanceM = 0.05;

// See SolveMountProblem: the change of cost (whitened, ½χ²) below which the solve has converged,
// and Ceres's default relative tolerance, kept for small problems.
constexpr double kCostChangeTolerance = 1e-4;
constexpr double kDefaultFunctionTolerance = 1e-6;
// ... or when two iterations in a row moved the mount by less than this (m; rad for the yaw).
constexpr double kMountStepTolerance = 1e-6;
// Ceres's initial trust region is 1e4 (a damping of 1e-4 of the scaled diagonal); the problem is
// nearly linear, so the first steps are allowed to be Gauss–Newton steps (a failed step still
// shrinks the region).
constexpr double kInitialTrustRegionRadius = 1e8;

// Fewer independent GNSS-error realisations than this (all stations within about one τ): warn.
constexpr double kMinIndependentStations = 1.5;

Mount MountFromArray(const std::array<double, 3>& values) {
  Mount mount;
  mount.x_m = values[0];
  mount.y_m = values[1];
  mount.yaw_rad = values[2];
  return mount;
}

// Stops the solve once the mount has settled: two successful iterations in a row that moved
// it by less than kMountStepTolerance. Needed on long sessions, where the cost keeps falling
// slowly along the split between the clock offset and the heading delay (each step lowering it
// by twice what the model predicts, docs/notes.md): on the 4-hour bench session 100 iterations
// moved the yaw by 1.5e-5 rad (0.02 σ) in steps of 1e-7 rad, and the cost criterion alone
// never stopped it.
class MountSettled : public ceres::IterationCallback {
 public:
  explicit MountSettled(const std::array<double, 3>* mount) : mount_(mount), last_(*mount) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (!summary.step_is_successful || summary.iteration == 0) return ceres::SOLVER_CONTINUE;
    const std::array<double, 3>& now = *mount_;
    const bool small = std::abs(now[0] - last_[0]) < kMountStepTolerance &&
                       std::abs(now[1] - last_[1]) < kMountStepTolerance &&
                       std::abs(now[2] - last_[2]) < kMountStepTolerance;
    last_ = now;
    settled_ = small ? settled_ + 1 : 0;
    return settled_ >= 2 ? ceres::SOLVER_TERMINATE_SUCCESSFULLY : ceres::SOLVER_CONTINUE;
  }

 private:
  const std::array<double, 3>* mount_;
  std::array<double, 3> last_;
  int settled_ = 0;
};

}  // namespace

MountEstimate SolveMountProblem(MountProblem& mp, const solvers::SolverOptions& options,
                                bool compute_covariance) {
  MountEstimate estimate;
  estimate.method = Method::kCeres;

  ceres::Solver::Options solver_options;
  // The unknowns: the mount, 2 per wall, 2 per 0.25 s GNSS-error slice (thousands in a long
  // session), 1 per station, the time block and the drift. The normal equations are sparse and
  // small beside the observations: formed and factored by a sparse Cholesky. Ceres forms them
  // from a list of the products of every residual block's Jacobian blocks, which with one block
  // per scan was the peak of the run's memory (36 products per observation, 130 MB on the
  // hour-long bench session); with one block per slice (wall_slice_cost.h) it is small. Measured
  // there (bench/, 2 cores, before the stopping rules below): solve 1.7 s, the repeatability
  // re-solves 1.3 s; SPARSE_SCHUR took 2.1 s and 2.2 s (its reduced matrix's bookkeeping
  // dominates the many small re-solves).
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.max_iterations;
  // Converged when an iteration lowers the cost (½χ², about half the number of residuals at the
  // solution) by less than about kCostChangeTolerance: a cost that far above its minimum is a
  // solution about 0.014 σ from it along its weakest direction. Ceres's default, 1e-6 of the
  // cost, allowed 0.24 on the hour-long bench session, which stopped 0.3 σ short in yaw.
  solver_options.function_tolerance =
      std::min(kDefaultFunctionTolerance,
               2.0 * kCostChangeTolerance / std::max(1, mp.problem.NumResiduals()));
  solver_options.initial_trust_region_radius = kInitialTrustRegionRadius;
  solver_options.num_threads = std::max(1, options.num_threads);
  MountSettled settled(&mp.mount);
  solver_options.update_state_every_iteration = true;  // for MountSettled
  solver_options.callbacks.push_back(&settled);
  solver_options.minimizer_progress_to_stdout = false;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &mp.problem, &summary);

  estimate.solver_report = summary.BriefReport();
  estimate.mount = MountFromArray(mp.mount);
  estimate.mount.yaw_rad = WrapAngle(estimate.mount.yaw_rad);
  estimate.time_offset_estimated = mp.time_offset_estimated;
  estimate.time_offset_s = mp.time_offset[0];
  estimate.heading_delay_estimated = mp.time_offset_estimated && mp.heading_delay_estimated;
  estimate.heading_delay_s = mp.time_offset[1];
  estimate.time_block_s = mp.time_offset;
  estimate.heading_delay_prior_sigma_s = options.heading_delay_sigma_s;
  estimate.heading_drift_estimated = mp.heading_drift_estimated;
  estimate.heading_drift_rad_per_s = mp.heading_drift[0];
  estimate.heading_reference_s = mp.heading_reference_s;
  for (size_t k = 0; k < mp.segment_order.size(); ++k) {
    const int index = mp.segment_order[k];
    estimate.segment_ids.push_back(mp.segment_ids[index]);
    estimate.segment_bias_m.emplace_back(mp.biases[index][0], mp.biases[index][1]);
    estimate.segment_bias_sigma_m.push_back(mp.bias_sigma_m[index]);
  }
  // Independent realisations of the GNSS error among the segments (Gauss–Markov): each
  // segment adds what it does not share with the previous one.
  if (!mp.segment_order.empty()) {
    estimate.independent_stations = 1.0;
    for (size_t k = 1; k < mp.segment_rho.size(); ++k) {
      estimate.independent_stations += 1.0 - mp.segment_rho[k] * mp.segment_rho[k];
    }
  }

  // Residuals at the solution, nuisance parameters applied.
  const int n = static_cast<int>(mp.measurements.size());
  estimate.residual_rho_m.resize(n);
  double sum_sq_m2 = 0.0;
  int rejected = 0;
  int counted = 0;
  for (int i = 0; i < n; ++i) {
    const WallLineCost cost(mp.measurements[i]);
    double error[2];
    double whitened[2];
    cost.Errors(mp.mount.data(), mp.wall_block[i], mp.bias_block[i], mp.time_offset.data(),
                mp.heading_block[i], mp.heading_drift.data(), error);
    cost(mp.mount.data(), mp.wall_block[i], mp.bias_block[i], mp.time_offset.data(),
         mp.heading_block[i], mp.heading_drift.data(), whitened);
    estimate.residual_rho_m[i] = -error[0];  // observed − predicted
    if (!(mp.weights[i] > 0.0)) continue;
    ++counted;
    if (std::hypot(whitened[0], whitened[1]) / std::sqrt(mp.weights[i]) > kRejectWhitenedNorm) {
      ++rejected;
    } else {
      sum_sq_m2 += error[0] * error[0];
    }
  }
  estimate.observations_rejected = rejected;
  estimate.observations_used = counted - rejected;
  estimate.residual_rms_m =
      estimate.observations_used > 0 ? std::sqrt(sum_sq_m2 / estimate.observations_used) : 0.0;

  if (!summary.IsSolutionUsable()) {
    estimate.failure = EstimateFailure::kSolveFailed;
    estimate.message = "the least-squares solve failed: " + summary.message;
    return estimate;
  }
  if (!compute_covariance) {
    estimate.usable = true;
    return estimate;
  }
  if (summary.termination_type != ceres::CONVERGENCE &&
      summary.termination_type != ceres::USER_SUCCESS) {
    // NO_CONVERGENCE is "usable" to Ceres, but an offset written from a solve that ran out of
    // iterations would be a silent guess.
    estimate.failure = EstimateFailure::kNotConverged;
    estimate.message = "the least-squares solve did not converge within " +
                       std::to_string(options.max_iterations) + " iterations (" + summary.message +
                       ")";
    return estimate;
  }

  // Covariance of the mount with every nuisance block free, so that the wall and GNSS bias
  // uncertainties propagate into it: the inverse of the marginal information of the mount, the
  // clock offset and the drift rate (solvers/information.h, the one information path; the
  // observability checks use the same matrix). Jacobians are evaluated with the Huber loss
  // applied: observations in the linear part of the loss count for less.
  std::vector<double*> kept = {mp.mount.data()};
  const bool dt_free = mp.time_offset_estimated &&
                       mp.problem.HasParameterBlock(mp.time_offset.data()) &&
                       !mp.problem.IsParameterBlockConstant(mp.time_offset.data());
  if (dt_free) kept.push_back(mp.time_offset.data());
  const bool drift_free = mp.heading_drift_estimated &&
                          mp.problem.HasParameterBlock(mp.heading_drift.data()) &&
                          !mp.problem.IsParameterBlockConstant(mp.heading_drift.data());
  if (drift_free) kept.push_back(mp.heading_drift.data());
  const Eigen::MatrixXd kept_information = MarginalInformation(mp, kept, options.num_threads);
  if (kept_information.rows() >= 3) {
    // The mount alone: the clock offset and the drift marginalised out of the kept blocks'
    // information (a Schur complement of a Schur complement is the Schur complement).
    const int extra = static_cast<int>(kept_information.rows()) - 3;
    Eigen::Matrix3d mount_information = kept_information.topLeftCorner(3, 3);
    if (extra > 0) {
      const Eigen::MatrixXd cross = kept_information.topRightCorner(3, extra);
      const Eigen::LDLT<Eigen::MatrixXd> ldlt(kept_information.bottomRightCorner(extra, extra));
      if (ldlt.info() == Eigen::Success) {
        mount_information -= cross * ldlt.solve(cross.transpose());
        mp.has_mount_information = true;
      }
    } else {
      mp.has_mount_information = true;
    }
    mp.mount_information = 0.5 * (mount_information + mount_information.transpose());
  }
  Eigen::MatrixXd covariance;
  if (!CovarianceOfKept(kept_information, &covariance)) {
    estimate.failure = EstimateFailure::kCovariance;
    estimate.message =
        "the mount covariance could not be computed: the Jacobian is rank deficient (a mount or "
        "nuisance direction is determined neither by the observations nor by the priors)";
    return estimate;
  }
  estimate.covariance = covariance.topLeftCorner(3, 3);
  int next = 3;
  if (dt_free) {
    const int dt_index = next;
    estimate.time_offset_sigma_s = std::sqrt(std::max(0.0, covariance(next, next)));
    estimate.time_covariance(0, 0) = covariance(next, next);
    ++next;
    if (estimate.heading_delay_estimated) {
      estimate.heading_delay_sigma_s = std::sqrt(std::max(0.0, covariance(next, next)));
      estimate.time_covariance(1, 1) = covariance(next, next);
      estimate.time_covariance(0, 1) = estimate.time_covariance(1, 0) = covariance(dt_index, next);
      ++next;
    }
  }
  if (drift_free) {
    estimate.heading_drift_sigma_rad_per_s = std::sqrt(std::max(0.0, covariance(next, next)));
  }
  if (!estimate.covariance.allFinite() || !(estimate.covariance.diagonal().minCoeff() > 0.0)) {
    estimate.failure = EstimateFailure::kCovariance;
    estimate.message = "the mount covariance is not finite and positive";
    return estimate;
  }
  estimate.usable = true;
  return estimate;
}

namespace {

// The warning of a check that failed but was forced past.
SolverWarning Forced(const std::string& message) {
  return {SolverWarningKind::kForcedObservability, "FORCED: " + message};
}

// The covariance from an information matrix that may be singular: eigenvalues below a floor
// (relative to the largest) are raised to it, so that an undetermined direction comes out with
// a huge but finite σ instead of a failure (used only for forced estimates and refits).
Eigen::Matrix3d CovarianceFromInformation(const Eigen::Matrix3d& information) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(information);
  const double largest = std::max(eigen.eigenvalues().cwiseAbs().maxCoeff(), 1e-300);
  Eigen::Vector3d inverse;
  for (int k = 0; k < 3; ++k) inverse[k] = 1.0 / std::max(eigen.eigenvalues()[k], 1e-12 * largest);
  return eigen.eigenvectors() * inverse.asDiagonal() * eigen.eigenvectors().transpose();
}

MountEstimate Refused(const Mount& initial, EstimateFailure failure, const std::string& message) {
  MountEstimate refused;
  refused.failure = failure;
  refused.method = Method::kCeres;
  refused.mount = initial;
  refused.message = message;
  return refused;
}

}  // namespace

MountEstimate SolveMountCeres(const std::vector<calib::WallObservation>& observations,
                              const std::vector<calib::WallGeometry>& walls,
                              const solvers::SolverOptions& options, const Mount& initial,
                              bool force, const WarmStart* warm, WarmStart* ended,
                              double observation_weight) {
  const std::vector<double> weights =
      observation_weight == 1.0 ? std::vector<double>()
                                : std::vector<double>(observations.size(), observation_weight);
  std::vector<SolverWarning> forced_warnings;
  const ObservabilityReport observability = CheckObservability(observations, walls, options);
  if (!observability.ok) {
    if (!force || !observability.solvable) return Refused(initial, EstimateFailure::kNotDetermined, observability.message);
    forced_warnings.push_back(Forced(observability.message));
  }
  std::string error;
  auto mp = BuildMountProblem(observations, walls, options, initial, initial, &error, weights);
  if (!mp) return Refused(initial, EstimateFailure::kBadInput, error);

  // Is every mount direction determined by this geometry and noise model, before solving (at
  // the initial values) and after (at the solution)? The check before is made only when the
  // check after fails, on the problem built again at the initial values: on a session that is
  // determined, the one where speed matters, the information of the whole problem is then
  // formed once (an hour's: 0.3 s of CPU). A warm-started round was checked by the round
  // before.
  if (warm != nullptr) ApplyWarmStart(*warm, mp.get());
  const bool check_before = warm == nullptr || !warm->checked;
  const auto check_at_initial = [&]() {
    DeterminationReport report;
    report.ok = true;
    if (!check_before) return report;
    auto at_initial =
        BuildMountProblem(observations, walls, options, initial, initial, &error, weights);
    if (!at_initial) return report;  // built once already: not reached
    if (warm != nullptr) ApplyWarmStart(*warm, at_initial.get());
    return CheckDetermination(MountInformation(*at_initial, options.num_threads), observations,
                              walls, options);
  };

  MountEstimate estimate = SolveMountProblem(*mp, options);
  const double moved_m =
      std::hypot(estimate.mount.x_m - initial.x_m, estimate.mount.y_m - initial.y_m);
  if (estimate.usable && moved_m > kLeverRebuildDistanceM) {
    // The heading-noise lever arms were computed from a mount far from the solution: rebuild
    // the noise model from the solution and solve again from there.
    // The first problem goes before the second is built: two of them would double the peak
    // memory of a long session. (Should the second not build, the first is built again.)
    const Mount first = estimate.mount;
    mp.reset();
    auto second = BuildMountProblem(observations, walls, options, first, first, &error, weights);
    if (second && warm != nullptr) ApplyWarmStart(*warm, second.get());
    if (second) {
      const std::string first_report = estimate.solver_report;
      estimate = SolveMountProblem(*second, options);
      estimate.solver_report = first_report + "\n" + estimate.solver_report;
      mp = std::move(second);
    } else {
      mp = BuildMountProblem(observations, walls, options, initial, initial, &error, weights);
      if (!mp) return Refused(initial, EstimateFailure::kBadInput, error);
      estimate = SolveMountProblem(*mp, options);
    }
  }
  estimate.solution_state = std::make_shared<const WarmStart>(WarmStartFrom(*mp));
  if (ended != nullptr) *ended = *estimate.solution_state;
  // After solving: the same check at the solution (the noise model's lever arms and the robust
  // loss's weights have changed).
  const Eigen::Matrix3d information = mp->has_mount_information
                                           ? mp->mount_information
                                           : MountInformation(*mp, options.num_threads);
  const DeterminationReport after = CheckDetermination(information, observations, walls, options);
  DeterminationReport before;
  before.ok = true;
  if (!after.ok) {
    // The problem solved goes first: two of them would double the peak memory.
    mp.reset();
    before = check_at_initial();
  }
  if (!before.ok) {
    if (!force) {
      MountEstimate refused = Refused(initial, EstimateFailure::kNotDetermined, before.message);
      refused.weak_direction = before.weak_direction;
      return refused;
    }
    if (observability.ok) forced_warnings.push_back(Forced(before.message));
  }
  if (!after.ok) {
    estimate.weak_direction = after.weak_direction;
    if (!force) {
      estimate.usable = false;
      estimate.failure = EstimateFailure::kNotDetermined;
      estimate.message = after.message;
      return estimate;
    }
    if (observability.ok && before.ok) forced_warnings.push_back(Forced(after.message));
  }
  if (!estimate.usable && force && !forced_warnings.empty() &&
      estimate.failure == EstimateFailure::kCovariance) {
    // Forced through a direction the data cannot tell: the solution exists (the priors hold the
    // nuisance parameters), its σ along that direction is huge.
    estimate.covariance = CovarianceFromInformation(information);
    estimate.usable = true;
    estimate.failure = EstimateFailure::kNone;
    estimate.message.clear();
  }
  if (!forced_warnings.empty()) {
    estimate.forced = true;
    estimate.warnings.insert(estimate.warnings.begin(), forced_warnings.begin(),
                             forced_warnings.end());
  }
  if (estimate.usable && estimate.independent_stations > 0.0 &&
      estimate.independent_stations < kMinIndependentStations) {
    char line[256];
    std::snprintf(line, sizeof line,
                  "the stations count as only %.1f independent GNSS errors (RTK error "
                  "correlation time %.0f s): spread the stations over a longer time for a "
                  "smaller σ",
                  estimate.independent_stations, options.gnss_bias_tau_s);
    estimate.warnings.push_back({SolverWarningKind::kFewIndependentGnssErrors, line});
  }
  return estimate;
}

MountEstimate ClockRoundStep(const std::vector<calib::WallObservation>& observations,
                             const std::vector<calib::WallGeometry>& walls,
                             const solvers::SolverOptions& options, const MountEstimate& before,
                             const WarmStart& warm, WarmStart* ended, double observation_weight) {
  const std::vector<double> weights =
      observation_weight == 1.0 ? std::vector<double>()
                                : std::vector<double>(observations.size(), observation_weight);
  std::string error;
  // The noise model's lever arms from the mount before, as the full solve would take them.
  auto mp = BuildMountProblem(observations, walls, options, before.mount, before.mount, &error,
                              weights);
  if (!mp) return Refused(before.mount, EstimateFailure::kBadInput, error);
  ApplyWarmStart(warm, mp.get());
  solvers::SolverOptions step_options = options;
  step_options.max_iterations = kClockRoundSteps;
  MountEstimate estimate = SolveMountProblem(*mp, step_options, /*compute_covariance=*/false);
  if (!estimate.usable) return estimate;
  // The solve before's uncertainty and checks (see the header).
  estimate.covariance = before.covariance;
  estimate.time_covariance = before.time_covariance;
  estimate.time_offset_sigma_s = before.time_offset_sigma_s;
  estimate.heading_delay_sigma_s = before.heading_delay_sigma_s;
  estimate.heading_drift_sigma_rad_per_s = before.heading_drift_sigma_rad_per_s;
  estimate.forced = before.forced;
  estimate.warnings = before.warnings;
  estimate.weak_direction = before.weak_direction;
  estimate.solution_state = std::make_shared<const WarmStart>(WarmStartFrom(*mp));
  if (ended != nullptr) *ended = *estimate.solution_state;
  return estimate;
}

Refit RefitMount(const std::vector<calib::WallObservation>& observations,
                 const std::vector<calib::WallGeometry>& walls, const solvers::SolverOptions& options,
                 const Mount& initial, const std::vector<double>& weights, int max_iterations,
                 const std::array<double, 2>* held_time_block, const WarmStart* warm) {
  Refit refit;
  refit.mount = initial;
  std::string error;
  auto mp = BuildMountProblem(observations, walls, options, initial, initial, &error, weights);
  if (!mp || !mp->problem.HasParameterBlock(mp->mount.data())) return refit;
  if (warm != nullptr) ApplyWarmStart(*warm, mp.get());
  if (held_time_block != nullptr && mp->problem.HasParameterBlock(mp->time_offset.data())) {
    mp->time_offset = *held_time_block;
    mp->problem.SetParameterBlockConstant(mp->time_offset.data());
  }
  solvers::SolverOptions quick = options;
  quick.max_iterations = std::max(1, max_iterations);
  const MountEstimate estimate = SolveMountProblem(*mp, quick, /*compute_covariance=*/false);
  if (!estimate.usable) return refit;
  refit.converged = true;
  refit.mount = estimate.mount;
  const Eigen::Matrix3d information = MountInformation(*mp, options.num_threads);
  refit.covariance = CovarianceFromInformation(information);
  std::vector<calib::WallObservation> used;
  for (size_t i = 0; i < observations.size(); ++i) {
    if (i >= weights.size() || weights[i] > 0.0) used.push_back(observations[i]);
  }
  refit.determined = CheckDetermination(information, used, walls, options).ok;
  return refit;
}

}  // namespace wallcal::solvers
