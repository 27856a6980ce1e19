// SPDX-License-Identifier: Apache-2.0
#include "pipeline/calibration.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <set>

#include "analysis/repeatability.h"
#include "pipeline/steps.h"

namespace wallcal::pipeline {
namespace {

// A preview (inspect) solves on every k-th observation, each weighted by k: the mount's
// information, hence its σ and the determination checks, stay about those of the whole set,
// at the cost of one small solve (an hour-long session: 3 000 instead of 270 000
// observations). The whole set is kept aside in *all for the detection counts.
void ThinForPreview(CalibrationResult* result, RunInputs* inputs,
                    std::vector<calib::WallObservation>* all) {
  analysis::ThinnedObservations thin = analysis::ThinForRefits(result->observations);
  if (thin.stride == 1.0) return;
  *all = std::move(result->observations);
  result->observations = std::move(thin.observations);
  inputs->observation_weight = thin.stride;
}

// Back to every detection once the preview's solve and residual analysis are done; the
// per-observation residuals belonged to the thinned set and go with it. When the solve left
// the drives out, they are left out of the whole set too, and counted there.
void RestoreDetections(const RunInputs& inputs, CalibrationResult* result,
                       std::vector<calib::WallObservation>* all) {
  result->preview_observations_solved = static_cast<int64_t>(result->observations.size());
  int64_t dropped = inputs.drives_dropped;
  if (!all->empty()) {
    result->observations = std::move(*all);
    result->estimate.residual_rho_m.clear();
    if (dropped > 0) {
      // The thinned set's count is replaced by the whole set's.
      std::vector<calib::WallObservation>& obs = result->observations;
      std::set<int> moving_scans;
      for (const calib::WallObservation& o : obs) {
        if (!o.pose.stationary) moving_scans.insert(o.scan_index);
      }
      obs.erase(std::remove_if(obs.begin(), obs.end(),
                               [](const calib::WallObservation& o) { return !o.pose.stationary; }),
                obs.end());
      result->scans_skipped[calib::ScanSkip::kVehicleMoving] +=
          static_cast<int64_t>(moving_scans.size()) - dropped;
      dropped = static_cast<int64_t>(moving_scans.size());
    }
  }
  if (dropped > 0) result->warnings.push_back(DrivesNotUsedWarning(dropped));
}

void AddSkips(const std::map<calib::ScanSkip, int64_t>& more,
              std::map<calib::ScanSkip, int64_t>* all) {
  for (const auto& [reason, count] : more) (*all)[reason] += count;
}

// The run's outcome when no scan sees the surveyed wall where the survey puts it: the first
// pass found no wall at all, or its estimate put the wall where no scan sees it.
bool SurveyDoesNotMatchSite(const CalibrationResult& result) {
  const bool first_pass_found_nothing =
      !result.first_pass.usable &&
      result.first_pass.failure == solvers::EstimateFailure::kWallNotDetected;
  return !result.estimate.usable && result.observations.empty() &&
         (result.first_pass.usable || first_pass_found_nothing);
}

CalibrationResult Run(const CalibrateRequest& request, const ProgressFn& progress,
                      bool swap_survey_axes);

// Two control points fit a mirrored survey (x and y swapped) by a rotation as well as the right
// one: their distance apart does not change. The scans tell: the walls reflected about the
// control points' line are where the scanner sees them. So when the run found no wall where the
// survey puts it, the same session is tried (as a preview) with the survey's axes swapped; a
// mount determined there is a mirrored survey, named as such (exit 2) instead of "not
// determined".
void RefuseMirroredSurvey(const CalibrateRequest& request, const CalibrationResult& result) {
  if (!SurveyDoesNotMatchSite(result) || result.num_control < 2) return;
  CalibrateRequest probe = request;
  probe.preview = true;
  probe.collect_report_data = false;
  CalibrationResult swapped;
  try {
    swapped = Run(probe, ProgressFn(), true);
  } catch (const io::InputError&) {
    return;  // the swapped survey fails too: not a mirror
  }
  if (!swapped.estimate.usable || swapped.observations.empty()) return;
  const io::SessionSpec& session = result.session;
  throw io::InputError(io::Where(
      session.file, session.control.empty() ? 0 : session.control.front().line,
      "mirrored survey: no scan sees the surveyed wall where the survey puts it, but with the "
      "survey's x and y (easting and northing) exchanged " +
          std::to_string(swapped.observations.size()) +
          " wall observations determine the mount; check whether the x and y (easting and "
          "northing) columns are swapped (survey.columns PNEZD against PENZD, or the header) in " +
          session.survey_points));
}

CalibrationResult Run(const CalibrateRequest& request, const ProgressFn& progress,
                      bool swap_survey_axes) {
  const auto start = std::chrono::steady_clock::now();
  CalibrationResult result;
  RunInputs inputs;
  {
    Setup setup = LoadSessionAndOptions(request);
    result.session = std::move(setup.session);
    result.options = std::move(setup.options);
    result.preset = std::move(setup.preset);
    inputs.previous = std::move(setup.previous);
  }
  if (!request.preview) StartDigests(request, result, &inputs);
  {
    SurveyStep survey =
        TieSurveyAndFitWalls(result.session, result.options.solver, swap_survey_axes);
    result.frame = survey.frame;
    result.control_rms_m = survey.tie.control_rms_m;
    result.num_control = survey.tie.num_control;
    result.walls = std::move(survey.walls);
    inputs.survey = std::move(survey.survey);
    inputs.tie = std::move(survey.tie);
    Append(&result.warnings, std::move(survey.warnings));
  }
  {
    PoseStep poses = ReadPoses(result);
    result.gnss_epochs = poses.gnss_epochs;
    result.fixes_by_quality = poses.gnss.fixes_by_quality;
    result.gnss_skipped = poses.gnss.skipped;
    result.heading_skipped = poses.headings.skipped;
    result.fixes_used = poses.fixes_used;
    result.headings_used = poses.headings_used;
    result.num_dwells = poses.num_dwells;
    // From here on the solver's white noise is the stops' where they measured it.
    result.measured_noise = poses.measured_noise;
    result.configured_gnss_white_sigma_m = result.options.solver.gnss_white_sigma_m;
    result.configured_heading_sigma_rad = result.options.solver.heading_sigma_rad;
    if (result.options.solver.use_measured_white_noise) {
      const calib::MeasuredWhiteNoise& m = poses.measured_noise;
      solvers::SolverOptions& solver = result.options.solver;
      if (m.gnss_white_sigma_m > 0.0) solver.gnss_white_sigma_m = m.gnss_white_sigma_m;
      if (m.heading_sigma_rad > 0.0) solver.heading_sigma_rad = m.heading_sigma_rad;
    }
    inputs.gnss = std::move(poses.gnss);  // used_fixes point into its fixes: they move along
    inputs.headings = std::move(poses.headings);
    inputs.used_fixes = std::move(poses.used_fixes);
    inputs.poses = std::move(poses.poses);
    Append(&result.warnings, std::move(poses.warnings));
  }
  {
    PassSetup passes = PreparePasses(request, result, *inputs.poses);
    inputs.pass = std::move(passes.pass);
    inputs.moving_by_default = passes.moving_by_default;
    result.scanner_from_data = std::move(passes.scanner_from_data);
    Append(&result.warnings, std::move(passes.warnings));
  }
  FirstPassStep first = FirstPass(request, progress, result, inputs);
  inputs.scans_in_log = first.scans_in_log;
  result.first_pass = first.estimate;
  if (first.stopped) {
    result.estimate = std::move(first.estimate);
    result.scans_total = first.scans_total;
  } else {
    SecondPassStep second = SecondPass(request, progress, result, inputs);
    result.observations = std::move(second.observations);
    result.scans_skipped = std::move(second.scans_skipped);
    result.scan_lines_skipped = std::move(second.scan_lines_skipped);
    result.scans_total = second.scans_total;
    result.scan_log = std::move(second.scan_log);
    Append(&result.warnings, std::move(second.warnings));

    std::vector<calib::WallObservation> all_detections;
    if (request.preview) ThinForPreview(&result, &inputs, &all_detections);
    SolveStep solved =
        Solve(request, progress, result, inputs, std::move(result.observations));
    result.observations = std::move(solved.observations);
    AddSkips(solved.scans_skipped, &result.scans_skipped);
    inputs.drives_dropped = solved.drives_dropped;
    result.forced = solved.forced;
    result.time_offset_s = solved.time_offset_s;
    result.time_offset_sigma_s = solved.time_offset_sigma_s;
    result.drives_timing_sigma_s = solved.drives_timing_sigma_s;
    result.scanner_offset = solved.scanner_offset;
    result.heading_delay = solved.heading_delay;
    Append(&result.warnings, std::move(solved.warnings));

    FinishedEstimate finished = FinishEstimate(request, result, std::move(solved.estimate));
    result.estimate = std::move(finished.estimate);
    result.sigma_known = finished.sigma_known;
    result.forced = result.forced || finished.forced;
    Append(&result.warnings, std::move(finished.warnings));
    // A thinned set's residuals are not the session's: one observation in a GNSS-error slice
    // is mostly absorbed by its bias, so no residual analysis of them.
    if (inputs.observation_weight == 1.0) {
      AnalysisStep analysed = Analyse(request, progress, result);
      result.residual_analysis = std::move(analysed.residual_analysis);
      result.repeatability = std::move(analysed.repeatability);
      Append(&result.warnings, std::move(analysed.warnings));
    }
    if (request.preview) RestoreDetections(inputs, &result, &all_detections);
    if (!request.preview) {
      Say(progress, Stage::kErrorBudget, "error budget: what the σ is made of");
      BudgetStep budget = BudgetAndAdvice(request, result);
      result.budget = std::move(budget.budget);
      if (budget.refusal_message) result.estimate.message = std::move(*budget.refusal_message);
    }
    const Coverage coverage = CountCoverage(result);
    result.scans_used = coverage.scans_used;
    result.scans_used_moving = coverage.scans_used_moving;
    result.num_segments_used = coverage.num_segments_used;
    result.heading_min_deg = coverage.heading_min_deg;
    result.heading_max_deg = coverage.heading_max_deg;
    result.wall_angle_min_deg = coverage.wall_angle_min_deg;
    result.wall_angle_max_deg = coverage.wall_angle_max_deg;
  }
  if (!swap_survey_axes) RefuseMirroredSurvey(request, result);
  {
    DecideStep decided = Decide(request, result, inputs);
    result.change = std::move(decided.change);
    result.decision = std::move(decided.decision);
    result.provenance = std::move(decided.provenance);
  }
  if (request.collect_report_data) {
    Say(progress, Stage::kReportData, "collecting the report's scans and site map");
    result.report = CollectReportData(result, inputs);
  }
  result.poses = std::move(inputs.poses);  // the passes that point at it are done
  Say(progress, Stage::kDone, "done");
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace

CalibrationResult RunCalibration(const CalibrateRequest& request, const ProgressFn& progress) {
  return Run(request, progress, false);
}

std::string DefaultOutputPath(const io::SessionSpec& session) {
  return (std::filesystem::path(session.dir) / "offsets.yaml").string();
}

}  // namespace wallcal::pipeline
