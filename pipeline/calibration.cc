#include "pipeline/calibration.h"

#include <chrono>
#include <filesystem>

#include "pipeline/steps.h"

namespace wallcal::pipeline {

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
    SecondPass(progress, &result, &inputs);
    Solve(request, progress, &result, &inputs);
    FinishEstimate(request, &result);
    Analyse(request, progress, &result);
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
