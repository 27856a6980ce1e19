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

}  // namespace

CalibrationResult RunCalibration(const CalibrateRequest& request, const ProgressFn& progress) {
  const auto start = std::chrono::steady_clock::now();
  CalibrationResult result;
  RunInputs inputs;
  LoadSessionAndOptions(request, &result, &inputs);
  if (!request.preview) StartDigests(request, result, &inputs);
  TieSurveyAndFitWalls(&result, &inputs);
  ReadPoses(&result, &inputs);
  PreparePasses(request, &result, &inputs);
  if (FirstPass(request, progress, &result, &inputs)) {
    SecondPass(request, progress, &result, &inputs);
    std::vector<calib::WallObservation> all_detections;
    if (request.preview) ThinForPreview(&result, &inputs, &all_detections);
    Solve(request, progress, &result, &inputs);
    FinishEstimate(request, &result);
    // A thinned set's residuals are not the session's: one observation in a GNSS-error slice
    // is mostly absorbed by its bias, so no residual analysis of them.
    if (inputs.observation_weight == 1.0) Analyse(request, progress, &result);
    if (request.preview) RestoreDetections(inputs, &result, &all_detections);
    if (!request.preview) {
      Say(progress, Stage::kErrorBudget, "error budget: what the σ is made of");
      BudgetAndAdvice(request, &result);
    }
    CountCoverage(&result);
  }
  Decide(request, &result, inputs);
  if (request.collect_report_data) {
    Say(progress, Stage::kReportData, "collecting the report's scans and site map");
    CollectReportData(&result, inputs);
  }
  Say(progress, Stage::kDone, "done");
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

std::string DefaultOutputPath(const io::SessionSpec& session) {
  return (std::filesystem::path(session.dir) / "offsets.yaml").string();
}

}  // namespace wallcal::pipeline
