#pragma once
// The steps RunCalibration takes, one function each (pipeline/calibration.cc strings them
// together). Internal to pipeline/.

#include <atomic>
#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "calib/detection_pass.h"
#include "calib/survey_tie.h"
#include "calib/time_alignment.h"
#include "io/types.h"
#include "pipeline/calibration.h"

namespace wallcal::pipeline {

// What the steps read once and share.
struct RunInputs {
  std::vector<io::SurveyPoint> survey;
  calib::SurveyTie tie;
  io::NmeaLog gnss;
  io::NmeaLog headings;  // the heading log (a copy of gnss when it is the same file)
  std::vector<const io::GnssFix*> used_fixes;  // into gnss.fixes
  std::unique_ptr<calib::PoseInterpolator> poses;
  calib::PassContext pass;
  int64_t scans_in_log = 0;  // scan records the first pass read (the second pass's total)
  std::optional<io::PreviousOffsets> previous;  // the --compare file, read before the work
  // Moving scans are in the passes only by alignment.moving_scans_in_stop_and_go: the solve
  // drops them again unless the clock offset comes out determined (Solve).
  bool moving_by_default = false;
  // A preview solves on a thinned set (ThinForPreview): each observation stands for this many.
  double observation_weight = 1.0;
  // Scans taken while driving that the solve dropped (their timing was not determined).
  int64_t drives_dropped = 0;
  // The inputs' SHA-256 digests for the provenance (StartDigests): computed on their own
  // thread while the passes run when there is more than one thread, else when Decide asks.
  std::shared_future<std::vector<io::InputFileDigest>> digests;
  // Set when the run ends (declared after `digests`, so destroyed first): a run that fails
  // early does not wait for the digests of a large log.
  struct CancelOnExit {
    std::shared_ptr<std::atomic<bool>> flag = std::make_shared<std::atomic<bool>>(false);
    ~CancelOnExit() { flag->store(true); }
  } cancel_digests;
};

// Reports a stage to `progress` (may be empty).
void Say(const ProgressFn& progress, Stage stage, const std::string& text);

// session.yaml, the options and the scanner preset.
void LoadSessionAndOptions(const CalibrateRequest& request, CalibrationResult* result,
                           RunInputs* inputs);
// Starts the SHA-256 digests of the inputs (after LoadSessionAndOptions).
void StartDigests(const CalibrateRequest& request, const CalibrationResult& result,
                  RunInputs* inputs);
// The survey, its tie to UTM and the walls as lines in the local frame. swap_survey_axes: the
// survey's x and y exchanged first (the mirrored-survey probe of RunCalibration).
void TieSurveyAndFitWalls(CalibrationResult* result, RunInputs* inputs,
                          bool swap_survey_axes = false);
// GNSS fixes and headings, the pose interpolator and the dwells.
void ReadPoses(CalibrationResult* result, RunInputs* inputs);
// How the detection passes read scans and which scans they use.
void PreparePasses(const CalibrateRequest& request, CalibrationResult* result, RunInputs* inputs);
// First pass (wide gates, subsample) and the start estimate. False when the run stops here
// (result->estimate then says why).
bool FirstPass(const CalibrateRequest& request, const ProgressFn& progress,
               CalibrationResult* result, RunInputs* inputs);
// Second pass (every scan, tight gates) and its accounting; a preview's also tallies every scan
// read (result->scan_log).
void SecondPass(const CalibrateRequest& request, const ProgressFn& progress,
                CalibrationResult* result, RunInputs* inputs);
// The warning that `scans` scans taken while driving were left out.
std::string DrivesNotUsedWarning(int64_t scans);
// The final solve by the requested method (with the clock-offset rounds).
void Solve(const CalibrateRequest& request, const ProgressFn& progress,
           CalibrationResult* result, RunInputs* inputs);
// Residual analysis and repeatability of a usable estimate.
void Analyse(const CalibrateRequest& request, const ProgressFn& progress,
             CalibrationResult* result);
// Scans used, GNSS slices, heading and vehicle-to-wall angle extents.
void CountCoverage(CalibrationResult* result);
// The site map, stations and scan panels of the report (pipeline/report_collect.cc).
void CollectReportData(CalibrationResult* result, const RunInputs& inputs);

// After the solve: the closed form's σ dropped (no error model), the estimate checked against
// scanner.mount_guess's tolerance (refused unless forced).
void FinishEstimate(const CalibrateRequest& request, CalibrationResult* result);
// The error budget of a ceres estimate (usable or refused for its σ); a σ refusal whose
// variance one source dominates gets advice about that source.
void BudgetAndAdvice(const CalibrateRequest& request, CalibrationResult* result);
// The verdict, the change since the previous calibration and the provenance (last step).
void Decide(const CalibrateRequest& request, CalibrationResult* result, const RunInputs& inputs);

// The gates of the second pass, from the first pass's covariance.
calib::Gates TightGates(const CalibrationResult& result);

}  // namespace wallcal::pipeline
