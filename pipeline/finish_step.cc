// SPDX-License-Identifier: Apache-2.0
// The finish step of a calibration run (pipeline/internal/steps.h): what is learned about the
// estimate after the solve: residual trends, repeatability, the error budget with the advice a
// σ refusal gets, the coverage of the observations.

#include <algorithm>
#include <cmath>

#include "common/angles.h"
#include "common/circular.h"
#include "common/format.h"
#include "pipeline/internal/steps.h"

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

// Residual analysis and repeatability of a usable estimate (into step).
void Analyse(const CalibrateRequest& request, const ProgressFn& progress,
             const CalibrationResult& so_far, FinishResult* step) {
  const solvers::MountEstimate& estimate = so_far.solve.estimate;
  const std::vector<calib::WallObservation>& observations = so_far.solve.observations;
  const std::vector<calib::WallGeometry>& walls = so_far.survey.walls;
  if (!estimate.usable) return;
  Say(progress, Stage::kResidualAnalysis, "residual analysis");
  step->residual_analysis =
      analysis::AnalyseResiduals(observations, walls, estimate, so_far.loaded.preset);
  for (const std::string& flag : step->residual_analysis.flags) {
    step->warnings.push_back({WarningKind::kResiduals, "residuals: " + flag});
  }
  const solvers::SolverOptions solver = so_far.SolverInUse();
  if (request.method == solvers::Method::kCeres && solver.bootstrap_samples >= 0 &&
      !request.preview) {
    Say(progress, Stage::kRepeatability,
        "repeatability: split halves and " + std::to_string(solver.bootstrap_samples) +
            " bootstrap resamples of the stations");
    step->repeatability = analysis::AssessRepeatability(
        observations, walls, solver, estimate.mount, solver.bootstrap_samples, 2007,
        estimate.time_offset_estimated ? &estimate.time_block_s : nullptr,
        estimate.solution_state.get());
  }
}

// The error budget of a ceres estimate (usable or refused for its σ); a σ refusal whose
// variance one source dominates gets advice about that source (into step).
void BudgetAndAdvice(const CalibrateRequest& request, const CalibrationResult& so_far,
                     FinishResult* step) {
  const solvers::MountEstimate& e = so_far.solve.estimate;
  const std::vector<calib::WallObservation>& observations = so_far.solve.observations;
  if (request.method != solvers::Method::kCeres || observations.empty() ||
      !e.covariance.allFinite()) {
    return;
  }
  if (!e.usable && e.failure != solvers::EstimateFailure::kNotDetermined) return;
  const solvers::SolverOptions s = so_far.SolverInUse();
  step->budget = analysis::ComputeErrorBudget(observations, so_far.survey.walls, s, e.mount);
  const analysis::ErrorBudget& b = step->budget;
  if (e.usable || !b.done) return;
  // The axis furthest beyond its limit; when one source explains most of its variance, the
  // advice is about that source, not about the stations' geometry.
  const double limits[3] = {s.max_sigma_xy_m, s.max_sigma_xy_m, s.max_sigma_yaw_rad};
  // A refused estimate may carry no covariance: the budget's linearised one then stands in.
  const bool have_covariance = e.covariance.diagonal().minCoeff() > 0.0;
  const Eigen::Vector3d variance =
      have_covariance ? Eigen::Vector3d(e.covariance.diagonal()) : b.total_variance;
  int worst = 0;
  double worst_ratio = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double ratio = std::sqrt(std::max(0.0, variance[k])) / limits[k];
    if (ratio > worst_ratio) {
      worst_ratio = ratio;
      worst = k;
    }
  }
  if (worst_ratio <= 1.0 || b.dominant_share[worst] < 0.5) return;  // geometry: keep it
  const double sigma = std::sqrt(variance[worst]);
  const bool yaw = worst == 2;
  step->refusal_advice =
      Format(
          "%s is not determined: σ %.4f %s, more than solver.max_sigma_%s %.4f %s; "
          "%.0f %% of its variance comes from the %s: ",
          kAxisNames[worst], yaw ? sigma * kRadToDeg : sigma, yaw ? "°" : "m",
          yaw ? "yaw_deg" : "xy_m", yaw ? limits[2] * kRadToDeg : limits[worst], yaw ? "°" : "m",
          100.0 * b.dominant_share[worst], analysis::ErrorSourceName(b.dominant[worst])) +
      AdviceFor(b.dominant[worst]);
}

// Scans used, GNSS slices, heading and vehicle-to-wall angle extents.
Coverage CountCoverage(const CalibrationResult& so_far) {
  const std::vector<calib::WallObservation>& observations = so_far.solve.observations;
  Coverage coverage;
  std::vector<int> used_scans, used_segments, moving_scans;
  std::vector<double> grid_headings, wall_angles;
  const size_t n = observations.size();
  used_scans.reserve(n);
  used_segments.reserve(n);
  grid_headings.reserve(n);
  wall_angles.reserve(n);
  for (const calib::WallObservation& o : observations) {
    used_scans.push_back(o.scan_index);
    if (!o.pose.stationary) moving_scans.push_back(o.scan_index);
    used_segments.push_back(calib::GnssSegment(o));
    grid_headings.push_back(HeadingFromYaw(o.pose.yaw_rad));
    const calib::WallGeometry& wall = so_far.survey.walls[o.wall_index];
    // φ of Barawid 2007, Eq. 8: the wall normal (towards the wall) in the vehicle frame.
    const double side =
        (wall.offset_m - wall.normal_local.dot(o.pose.antenna_local_m)) >= 0 ? 1 : -1;
    wall_angles.push_back(WrapAngle(
        std::atan2(side * wall.normal_local.y(), side * wall.normal_local.x()) - o.pose.yaw_rad));
  }
  coverage.scans_used = CountDistinct(&used_scans);
  coverage.scans_used_moving = CountDistinct(&moving_scans);
  coverage.num_segments_used = static_cast<int>(CountDistinct(&used_segments));
  const CircularExtent headings = CircularExtentOf(grid_headings);
  const CircularExtent angles = CircularExtentOf(wall_angles);
  if (!headings.empty) {
    coverage.heading_min_deg = WrapTwoPi(headings.min_rad) * kRadToDeg;
    coverage.heading_max_deg = WrapTwoPi(headings.max_rad) * kRadToDeg;
  }
  if (!angles.empty) {
    coverage.wall_angle_min_deg = WrapAngle(angles.min_rad) * kRadToDeg;
    coverage.wall_angle_max_deg = WrapAngle(angles.max_rad) * kRadToDeg;
  }
  return coverage;
}

}  // namespace

FinishResult Finish(const CalibrateRequest& request, const ProgressFn& progress,
                    const CalibrationResult& so_far) {
  FinishResult step;
  if (so_far.detection.stopped) return step;  // nothing was solved
  // A thinned set's residuals are not the session's: one observation in a GNSS-error slice is
  // mostly absorbed by its bias, so no residual analysis of them.
  if (so_far.solve.preview_weight == 1.0) Analyse(request, progress, so_far, &step);
  if (!request.preview) {
    Say(progress, Stage::kErrorBudget, "error budget: what the σ is made of");
    BudgetAndAdvice(request, so_far, &step);
  }
  step.coverage = CountCoverage(so_far);
  return step;
}

}  // namespace wallcal::pipeline
