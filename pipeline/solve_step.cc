// SPDX-License-Identifier: Apache-2.0
// The solve step of a calibration run (pipeline/internal/steps.h): the estimate by the requested
// method with its clock-offset rounds, the drives kept only where their timing is determined,
// the closed form's σ dropped and the estimate checked against the mount guess. A preview
// solves on a thinned set and gives back every detection.

#include <algorithm>
#include <limits>
#include <utility>

#include "analysis/repeatability.h"
#include "common/format.h"
#include "pipeline/checks.h"
#include "pipeline/internal/steps.h"
#include "pipeline/stream_delays.h"
#include "solvers/mount_problem.h"
#include "solvers/solve_policy.h"

namespace wallcal::pipeline {
namespace {

WarningKind KindOf(solvers::SolverWarningKind kind) {
  switch (kind) {
    case solvers::SolverWarningKind::kForcedObservability:
      return WarningKind::kForcedObservability;
    case solvers::SolverWarningKind::kFewIndependentGnssErrors:
      return WarningKind::kFewIndependentGnssErrors;
  }
  return WarningKind::kForcedObservability;
}

// Drops the observations of moving scans; returns how many scans that was.
int64_t DropMoving(std::vector<calib::WallObservation>* observations) {
  std::vector<calib::WallObservation>& obs = *observations;
  const auto moving = std::stable_partition(
      obs.begin(), obs.end(), [](const calib::WallObservation& o) { return o.pose.stationary; });
  std::vector<int> scans;
  scans.reserve(static_cast<size_t>(obs.end() - moving));
  for (auto it = moving; it != obs.end(); ++it) scans.push_back(it->scan_index);
  obs.erase(moving, obs.end());
  return CountDistinct(&scans);
}

// After the solve: the closed form's σ dropped (no error model), the estimate checked against
// scanner.mount_guess's tolerance (refused unless forced).
void CheckEstimate(const CalibrateRequest& request, const CalibrationResult& so_far,
                   SolveResult* step) {
  solvers::MountEstimate& e = step->estimate;
  if (request.method == solvers::Method::kBarawid && e.usable) {
    // The closed form's σ treats every scan as independent (no survey, control-point or
    // correlated GNSS error): far too small. No σ is better than a wrong one.
    step->sigma_known = false;
    e.covariance.setConstant(std::numeric_limits<double>::quiet_NaN());
    step->warnings.push_back(
        {WarningKind::kNoSigma,
         "no σ: the closed form (--method barawid) has no error model for the survey, the "
         "control points or the correlated GNSS error; run the adjustment (--method ceres) for "
         "the σ"});
  }
  if (!e.usable && so_far.detection.first_pass.usable && step->observations.empty()) {
    // The wide-gate pass saw a line where the survey predicts one, but nothing is left near
    // the estimate it gave: the scans and the survey disagree, more stations will not help.
    e.message +=
        "; the first pass matched a line with wide gates, but no scan sees the surveyed "
        "wall where that estimate puts it: the survey does not match the site — check "
        "whether its x and y (easting and northing) are swapped (survey.columns, a "
        "mirrored survey cannot be told from two control points), the control points, "
        "and the walls' survey codes";
  }
  const std::optional<io::MountGuess>& guess = so_far.loaded.session.mount_guess;
  if (e.usable && guess) {
    const std::string outside = CheckMountGuess(*guess, e.mount);
    if (!outside.empty()) {
      if (request.force) {
        step->forced = true;
        step->warnings.push_back({WarningKind::kForcedMountGuess, "FORCED: " + outside});
      } else {
        e.usable = false;
        e.failure = solvers::EstimateFailure::kOutsideMountGuess;
        e.message = outside;
      }
    }
  }
}

// A preview's every detection back once its thinned set is solved; the per-observation
// residuals belonged to the thinned set and go with it. When the solve left the drives out,
// they are left out of the whole set too, and counted there.
void RestoreDetections(std::vector<calib::WallObservation> all, SolveResult* step) {
  step->preview_observations_solved = static_cast<int64_t>(step->observations.size());
  if (all.empty()) return;
  step->observations = std::move(all);
  step->estimate.residual_rho_m.clear();
  if (step->drives_dropped == 0) return;
  std::vector<calib::WallObservation>& obs = step->observations;
  std::vector<int> moving_scans;
  for (const calib::WallObservation& o : obs) {
    if (!o.pose.stationary) moving_scans.push_back(o.scan_index);
  }
  const int64_t moving = CountDistinct(&moving_scans);
  obs.erase(std::remove_if(obs.begin(), obs.end(),
                           [](const calib::WallObservation& o) { return !o.pose.stationary; }),
            obs.end());
  // The thinned set's count is replaced by the whole set's.
  step->scans_skipped[calib::ScanSkip::kVehicleMoving] += moving - step->drives_dropped;
  step->drives_dropped = moving;
}

}  // namespace

Warning DrivesNotUsedWarning(int64_t scans) {
  return {WarningKind::kDrivesNotUsed,
          std::to_string(scans) +
              " scans taken while driving were not used: the timing their poses need (scanner "
              "clock offset, heading delay) was not determined (σ above "
              "alignment.moving_max_time_offset_sigma_s)"};
}

SolveResult Solve(const CalibrateRequest& request, const ProgressFn& progress,
                  const CalibrationResult& so_far, std::vector<calib::WallObservation> observations,
                  const calib::Mount& start) {
  SolveResult step;
  if (so_far.detection.stopped) {
    step.estimate = so_far.detection.first_pass;  // why the run stopped at the first pass
    return step;
  }
  // A preview solves on every k-th observation, each weighted by k: the mount's information,
  // hence its σ and the determination checks, stay about those of the whole set, at the cost of
  // one small solve (an hour-long session: 3 000 instead of 270 000 observations).
  std::vector<calib::WallObservation> all;
  if (request.preview) {
    analysis::ThinnedObservations thin = analysis::ThinForRefits(observations);
    if (thin.stride != 1.0) {
      all = std::move(observations);
      observations = std::move(thin.observations);
      step.preview_weight = thin.stride;
    }
  }
  std::vector<calib::WallObservation>& obs = step.observations;
  obs = std::move(observations);
  // Into the level model the adjustment works in (nothing on a level site).
  ApplySiteCorrections(so_far.site, so_far.survey.walls, start, &obs);
  Say(progress, Stage::kSolving,
      std::string("solving (") + solvers::MethodName(request.method) + ") on " +
          std::to_string(obs.size()) + " observations");
  const auto on_round = [&progress](double shift_s) {
    Say(progress, Stage::kClockOffsetRound,
        "clock offset " + Format("%.4f", shift_s) +
            " s so far: poses (and headings by the heading delay) interpolated at the shifted "
            "scan times, solving again");
  };
  const std::vector<calib::WallGeometry>& walls = so_far.survey.walls;
  const calib::PoseInterpolator& poses = *so_far.poses.interpolator;
  const solvers::SolverOptions solver = so_far.SolverInUse();
  const auto solve = [&]() {
    return solvers::SolveWithPolicy(request.method, &obs, walls, solver, start, request.force,
                                    poses, on_round, step.preview_weight);
  };
  const bool moving_by_default = so_far.detection.moving_by_default;
  // Moving scans by default only where their clock offset is estimated: not for barawid.
  int64_t moving_dropped = 0;
  if (moving_by_default && request.method != solvers::Method::kCeres) {
    moving_dropped = DropMoving(&obs);
  }
  solvers::PolicyOutcome outcome = solve();
  int64_t unshift_dropped = 0;  // observations without a pose at their own stamp
  const double max_offset_sigma_s = so_far.loaded.options.alignment.moving_max_time_offset_sigma_s;
  if (moving_by_default && moving_dropped == 0 &&
      !(outcome.estimate.time_offset_estimated &&
        solvers::DrivesTimingSigma(obs, walls, outcome.estimate.mount,
                                   outcome.estimate.time_covariance) <= max_offset_sigma_s)) {
    // The timing the drives' poses need (the clock offset when driving towards a wall, the
    // clock offset plus the heading delay when turning in front of it) is not determined: their
    // scans would misplace the wall by speed × offset. Standing scans alone, back at the poses
    // of their own stamps (the clock rounds moved every observation by the same shift).
    if (!obs.empty() &&
        (obs.front().pose.clock_shift_s != 0.0 || obs.front().pose.heading_shift_s != 0.0)) {
      unshift_dropped = calib::ShiftObservations(poses, -obs.front().pose.clock_shift_s,
                                                 -obs.front().pose.heading_shift_s, &obs);
    }
    moving_dropped = DropMoving(&obs);
    if (moving_dropped > 0) {
      step.drives_dropped = moving_dropped;
      outcome = solve();
    }
  }
  if (moving_dropped > 0) step.scans_skipped[calib::ScanSkip::kVehicleMoving] += moving_dropped;
  if (outcome.dropped_at_shifted_time + unshift_dropped > 0) {
    step.scans_skipped[calib::ScanSkip::kNoPoseAtShiftedTime] +=
        outcome.dropped_at_shifted_time + unshift_dropped;
  }
  step.estimate = std::move(outcome.estimate);
  const solvers::MountEstimate& estimate = step.estimate;
  step.forced = estimate.usable && estimate.forced;
  if (estimate.time_offset_estimated) {
    step.drives_timing_sigma_s =
        solvers::DrivesTimingSigma(obs, walls, estimate.mount, estimate.time_covariance);
  }
  const double clock_prior_s = solver.time_offset_sigma_s;
  const double heading_prior_s =
      estimate.heading_delay_estimated ? estimate.heading_delay_prior_sigma_s : 0.0;
  const auto determined = [&](int index) {
    return solvers::DelayDetermined(estimate.time_covariance, clock_prior_s, heading_prior_s,
                                    index);
  };
  step.scanner_offset = ClassifyDelay(estimate.time_offset_estimated, estimate.time_offset_s,
                                      estimate.time_offset_sigma_s, clock_prior_s, determined(0));
  step.heading_delay =
      ClassifyDelay(estimate.heading_delay_estimated, estimate.heading_delay_s,
                    estimate.heading_delay_sigma_s, heading_prior_s, determined(1));
  if (request.method == solvers::Method::kCeres) {
    // A preview keeps the corrections made at the start (its thinned, weighted set is not
    // stepped again) but carries the site's terms: the guide predicts with them.
    calib::Mount corrected_at = start;
    if (!request.preview && so_far.site.corrected && step.estimate.usable &&
        step.estimate.solution_state) {
      // The corrections again at the solution (they were made at the start, off by the first
      // pass's error times the tilt), and the two Gauss–Newton steps of a clock round from it.
      const SiteCorrectionsMade made{&so_far.site, &walls, start};
      corrected_at = step.estimate.mount;
      ApplySiteCorrections(so_far.site, walls, corrected_at, &obs, &made);
      solvers::MountEstimate again = solvers::ClockRoundStep(
          obs, walls, solver, step.estimate, *step.estimate.solution_state, nullptr);
      if (again.usable) step.estimate = std::move(again);
    }
    PropagateSiteTerms(so_far, corrected_at, &step);
  }
  CheckEstimate(request, so_far, &step);
  if (request.preview) RestoreDetections(std::move(all), &step);
  // The drives left out first, then what the estimate says of itself, then the checks after it.
  Warnings warnings;
  if (step.drives_dropped > 0) warnings.push_back(DrivesNotUsedWarning(step.drives_dropped));
  for (const solvers::SolverWarning& w : step.estimate.warnings) {
    warnings.push_back({KindOf(w.kind), w.message});
  }
  Append(&warnings, std::move(step.warnings));
  step.warnings = std::move(warnings);
  return step;
}

}  // namespace wallcal::pipeline
