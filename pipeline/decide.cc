// SPDX-License-Identifier: Apache-2.0
// The last steps of a run (pipeline/steps.h): the closed form's σ, the mount-guess check, the
// error budget with the refusal advice it supports, and the verdict with its provenance.

#include <cmath>
#include <filesystem>
#include <future>
#include <limits>

#include "common/angles.h"
#include "common/format.h"
#include "io/version.h"
#include "pipeline/checks.h"
#include "pipeline/config_dirs.h"
#include "pipeline/several_verdict.h"
#include "pipeline/steps.h"

namespace wallcal::pipeline {
namespace {

// What to do when one source dominates an axis' variance.
const char* AdviceFor(analysis::ErrorSource source) {
  switch (source) {
    case analysis::ErrorSource::kSurvey:
      return "survey more points along the wall, over a longer stretch of it";
    case analysis::ErrorSource::kControl:
      return "improve the survey's tie: measure the control points longer in RTK fixed, add a "
             "third, or place them farther apart";
    case analysis::ErrorSource::kGnss:
      return "spread the stations over more time (the RTK error is correlated for about "
             "solver.gnss_bias_tau_s) or add stations";
    case analysis::ErrorSource::kHeading:
      return "add stations, or use a heading sensor with less noise";
    case analysis::ErrorSource::kScanner:
      return "stay longer at each station (more scans), or use a scanner with less range noise";
    case analysis::ErrorSource::kRover:
      return "measure more rover points along the wall, over a longer stretch of it, each held "
             "longer in RTK fixed (docs/field-guide.md)";
  }
  return "";
}

const char* kAxisNames[3] = {"forward offset x", "lateral offset y", "yaw"};

}  // namespace

FinishedEstimate FinishEstimate(const CalibrateRequest& request, const CalibrationResult& result,
                                solvers::MountEstimate estimate) {
  FinishedEstimate finished;
  finished.estimate = std::move(estimate);
  solvers::MountEstimate& e = finished.estimate;
  if (request.method == solvers::Method::kBarawid && e.usable) {
    // The closed form's σ treats every scan as independent (no survey, control-point or
    // correlated GNSS error): far too small. No σ is better than a wrong one.
    finished.sigma_known = false;
    e.covariance.setConstant(std::numeric_limits<double>::quiet_NaN());
    finished.warnings.push_back(
        {WarningKind::kNoSigma,
         "no σ: the closed form (--method barawid) has no error model for the survey, the "
         "control points or the correlated GNSS error; run the adjustment (--method ceres) for "
         "the σ"});
  }
  if (!e.usable && result.first_pass.usable && result.observations.empty()) {
    // The wide-gate pass saw a line where the survey predicts one, but nothing is left near
    // the estimate it gave: the scans and the survey disagree, more stations will not help.
    e.message += "; the first pass matched a line with wide gates, but no scan sees the surveyed "
                 "wall where that estimate puts it: the survey does not match the site — check "
                 "whether its x and y (easting and northing) are swapped (survey.columns, a "
                 "mirrored survey cannot be told from two control points), the control points, "
                 "and the walls' survey codes";
  }
  const std::optional<io::MountGuess>& guess = result.session.mount_guess;
  if (e.usable && guess) {
    const std::string outside = CheckMountGuess(*guess, e.mount);
    if (!outside.empty()) {
      if (request.force) {
        finished.forced = true;
        finished.warnings.push_back({WarningKind::kForcedMountGuess, "FORCED: " + outside});
      } else {
        e.usable = false;
        e.failure = solvers::EstimateFailure::kOutsideMountGuess;
        e.message = outside;
      }
    }
  }
  return finished;
}

BudgetStep BudgetAndAdvice(const CalibrateRequest& request, const CalibrationResult& result) {
  BudgetStep step;
  const solvers::MountEstimate& e = result.estimate;
  if (request.method != solvers::Method::kCeres || result.observations.empty() ||
      !e.covariance.allFinite()) {
    return step;
  }
  if (!e.usable && e.failure != solvers::EstimateFailure::kNotDetermined) return step;
  step.budget = analysis::ComputeErrorBudget(result.observations, result.walls,
                                             result.options.solver, e.mount);
  const analysis::ErrorBudget& b = step.budget;
  if (e.usable || !b.done) return step;
  // The axis furthest beyond its limit; when one source explains most of its variance, the
  // advice is about that source, not about the stations' geometry.
  const solvers::SolverOptions& s = result.options.solver;
  const double limits[3] = {s.max_sigma_xy_m, s.max_sigma_xy_m, s.max_sigma_yaw_rad};
  // A refused estimate may carry no covariance: the budget's linearised one then stands in.
  const bool have_covariance = e.covariance.diagonal().minCoeff() > 0.0;
  const Eigen::Vector3d variance = have_covariance ? Eigen::Vector3d(e.covariance.diagonal())
                                                   : b.total_variance;
  int worst = 0;
  double worst_ratio = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double ratio = std::sqrt(std::max(0.0, variance[k])) / limits[k];
    if (ratio > worst_ratio) {
      worst_ratio = ratio;
      worst = k;
    }
  }
  if (worst_ratio <= 1.0 || b.dominant_share[worst] < 0.5) return step;  // geometry: keep it
  const double sigma = std::sqrt(variance[worst]);
  const bool yaw = worst == 2;
  step.refusal_message = Format("%s is not determined: σ %.4f %s, more than solver.max_sigma_%s %.4f %s; "
                     "%.0f %% of its variance comes from the %s: ",
                     kAxisNames[worst], yaw ? sigma * kRadToDeg : sigma, yaw ? "°" : "m",
                     yaw ? "yaw_deg" : "xy_m", yaw ? limits[2] * kRadToDeg : limits[worst],
                     yaw ? "°" : "m", 100.0 * b.dominant_share[worst],
                     analysis::ErrorSourceName(b.dominant[worst])) +
              AdviceFor(b.dominant[worst]);
  return step;
}

DecideStep Decide(const CalibrateRequest& request, const CalibrationResult& result,
                  const RunInputs& inputs) {
  DecideStep step;
  if (inputs.previous && result.estimate.usable) {
    step.change = CompareMounts(result.estimate, *inputs.previous);
  }
  step.decision = DecideCalibration(result, step.change);

  Provenance& p = step.provenance;
  p.created_utc = NowUtcIso8601();
  p.tool_version = io::kToolVersion;
  p.command_line = request.command_line;
  if (request.preview) return step;
  p.inputs = inputs.digests.valid()
                 ? inputs.digests.get()
                 : DigestInputs(result.session, request.config_path, result.preset.file,
                                request.compare_path);
  return step;
}

void StartDigests(const CalibrateRequest& request, const CalibrationResult& result,
                  RunInputs* inputs) {
  const io::SessionSpec session = result.session;
  const std::string config_path = request.config_path;
  const std::string preset_path = result.preset.file;  // the file actually read
  const std::string compare_path = request.compare_path;
  const auto policy = result.options.solver.num_threads > 1 ? std::launch::async
                                                            : std::launch::deferred;
  const std::shared_ptr<std::atomic<bool>> cancel = inputs->cancel_digests.flag;
  inputs->digests =
      std::async(policy, [session, config_path, preset_path, compare_path, cancel]() {
        return DigestInputs(session, config_path, preset_path, compare_path, cancel.get());
      }).share();
}

}  // namespace wallcal::pipeline
