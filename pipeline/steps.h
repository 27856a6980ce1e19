// SPDX-License-Identifier: Apache-2.0
#pragma once
// The steps RunCalibration takes, one function each (pipeline/calibration.cc strings them
// together). Each step reads what the run has so far (const) and returns its own small result;
// the run moves those into the CalibrationResult and collects their warnings in step order.
// Internal to pipeline/.

#include <atomic>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "calib/detection_pass.h"
#include "calib/survey_tie.h"
#include "calib/time_alignment.h"
#include "calib/white_noise.h"
#include "io/types.h"
#include "pipeline/calibration.h"
#include "pipeline/run_warnings.h"
#include "recording/recording_streams.h"

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

// session.yaml, the options, the scanner preset and the --compare file.
struct Setup {
  io::SessionSpec session;
  CalibrateOptions options;
  io::ScannerPreset preset;
  std::optional<io::PreviousOffsets> previous;
};
Setup LoadSessionAndOptions(const CalibrateRequest& request);
// Starts the SHA-256 digests of the inputs (after LoadSessionAndOptions).
void StartDigests(const CalibrateRequest& request, const CalibrationResult& result,
                  RunInputs* inputs);

// The survey, its tie to UTM and the walls as lines in the local frame.
struct SurveyStep {
  std::vector<io::SurveyPoint> survey;  // repeated points averaged
  calib::SurveyTie tie;
  calib::LocalFrame frame;
  std::vector<calib::WallGeometry> walls;
  Warnings warnings;
};
// swap_survey_axes: the survey's x and y exchanged first (the mirrored-survey probe of
// RunCalibration).
SurveyStep TieSurveyAndFitWalls(const io::SessionSpec& session,
                                const solvers::SolverOptions& solver,
                                bool swap_survey_axes = false);

// GNSS fixes and headings, the pose interpolator and the dwells (needs the frame and walls).
struct PoseStep {
  io::NmeaLog gnss;
  io::NmeaLog headings;
  std::vector<const io::GnssFix*> used_fixes;  // into gnss.fixes
  std::unique_ptr<calib::PoseInterpolator> poses;
  calib::GnssEpochMapping gnss_epochs;
  int64_t fixes_used = 0;
  int64_t headings_used = 0;
  int num_dwells = 0;
  // The GNSS and heading white noise at the dwells (calib/white_noise.h).
  calib::MeasuredWhiteNoise measured_noise;
  Warnings warnings;
};
PoseStep ReadPoses(const CalibrationResult& result);
// ReadPoses on the GNSS and heading logs already read (ReadPoses reads them with
// recording::ReadPoseLogs; the guide reads them on as they grow). Throws io::InputError as
// ReadPoses does for what the logs hold.
PoseStep PosesFromLogs(const CalibrationResult& result, recording::PoseLogs logs);
// Sets result->measured_noise from `poses` and result->options.solver's GNSS and heading white
// noise: with solver.use_measured_white_noise, each the stops' measure where there is one, else
// `configured`'s (kept in result->configured_*). calibrate and the guide both call it, so the
// guide's σ is calibrate's on the same data.
void UseMeasuredWhiteNoise(const PoseStep& poses, const solvers::SolverOptions& configured,
                           CalibrationResult* result);

// Which scans taken while moving the passes use, for a session with `num_dwells` dwells:
// use_moving (the passes detect them) and moving_by_default (RunInputs::moving_by_default).
struct MovingScans {
  bool use_moving = false;
  bool moving_by_default = false;
};
MovingScans ChooseMovingScans(const CalibrateOptions& options, int num_dwells);

// How the detection passes read scans and which scans they use. The context points into
// `result` (preset, detector options, walls) and at `poses`: both outlive the passes.
struct PassSetup {
  calib::PassContext pass;
  bool moving_by_default = false;  // RunInputs::moving_by_default
  std::string scanner_from_data;   // CalibrationResult::scanner_from_data
  Warnings warnings;
};
PassSetup PreparePasses(const CalibrateRequest& request, const CalibrationResult& result,
                        const calib::PoseInterpolator& poses);

// First pass (wide gates, subsample) and the start estimate.
struct FirstPassStep {
  // The refined start; when `stopped`, the estimate that says why the run stops here.
  solvers::MountEstimate estimate;
  bool stopped = false;
  int64_t scans_in_log = 0;  // scan records read
  int64_t scans_total = 0;   // scan records + malformed scan lines (set when stopped)
};
FirstPassStep FirstPass(const CalibrateRequest& request, const ProgressFn& progress,
                        const CalibrationResult& result, const RunInputs& inputs);

// Second pass (every scan, tight gates) and its accounting; a preview's also tallies every scan
// read (scan_log).
struct SecondPassStep {
  std::vector<calib::WallObservation> observations;
  std::map<calib::ScanSkip, int64_t> scans_skipped;
  io::SkipCounts scan_lines_skipped;
  int64_t scans_total = 0;
  std::optional<calib::ScanLogTally> scan_log;
  Warnings warnings;
};
SecondPassStep SecondPass(const CalibrateRequest& request, const ProgressFn& progress,
                          const CalibrationResult& result, const RunInputs& inputs);
// The warning that `scans` scans taken while driving were left out.
Warning DrivesNotUsedWarning(int64_t scans);

// The final solve by the requested method (with the clock-offset rounds) on `observations`.
struct SolveStep {
  std::vector<calib::WallObservation> observations;  // those the solve used, at their poses
  solvers::MountEstimate estimate;
  bool forced = false;  // usable only because of --force
  std::map<calib::ScanSkip, int64_t> scans_skipped;  // added to the second pass's
  int64_t drives_dropped = 0;  // moving scans dropped for undetermined timing
  double time_offset_s = 0.0;
  double time_offset_sigma_s = 0.0;
  double drives_timing_sigma_s = 0.0;
  StreamDelay scanner_offset;
  StreamDelay heading_delay;
  Warnings warnings;
};
SolveStep Solve(const CalibrateRequest& request, const ProgressFn& progress,
                const CalibrationResult& result, const RunInputs& inputs,
                std::vector<calib::WallObservation> observations);

// After the solve: the closed form's σ dropped (no error model), the estimate checked against
// scanner.mount_guess's tolerance (refused unless forced).
struct FinishedEstimate {
  solvers::MountEstimate estimate;
  bool sigma_known = true;
  bool forced = false;  // outside the mount guess, written because of --force
  Warnings warnings;
};
FinishedEstimate FinishEstimate(const CalibrateRequest& request, const CalibrationResult& result,
                                solvers::MountEstimate estimate);

// Residual analysis and repeatability of a usable estimate.
struct AnalysisStep {
  analysis::ResidualAnalysis residual_analysis;
  analysis::Repeatability repeatability;
  Warnings warnings;
};
AnalysisStep Analyse(const CalibrateRequest& request, const ProgressFn& progress,
                     const CalibrationResult& result);

// The error budget of a ceres estimate (usable or refused for its σ); a σ refusal whose
// variance one source dominates gets advice about that source (refusal_message).
struct BudgetStep {
  analysis::ErrorBudget budget;
  std::optional<std::string> refusal_message;  // replaces estimate.message when set
};
BudgetStep BudgetAndAdvice(const CalibrateRequest& request, const CalibrationResult& result);

// Scans used, GNSS slices, heading and vehicle-to-wall angle extents.
struct Coverage {
  int64_t scans_used = 0;
  int64_t scans_used_moving = 0;
  int num_segments_used = 0;
  double heading_min_deg = 0.0, heading_max_deg = 0.0;
  double wall_angle_min_deg = 0.0, wall_angle_max_deg = 0.0;
};
Coverage CountCoverage(const CalibrationResult& result);

// The verdict, the change since the previous calibration and the provenance (last step).
struct DecideStep {
  std::optional<Change> change;
  Decision decision;
  Provenance provenance;
};
DecideStep Decide(const CalibrateRequest& request, const CalibrationResult& result,
               const RunInputs& inputs);

// The site map, stations and scan panels of the report (pipeline/report_collect.cc).
ReportData CollectReportData(const CalibrationResult& result, const RunInputs& inputs);

// The report's drawings again around `mount` (a scanner's joint mount among several): the
// scanner at each station, each panel's gate and detection from the scan points it kept, the
// Hough view; nothing is read. The site map's track and survey do not depend on the mount.
// `data` must come from CollectReportData on `result` (not collected: left as it is).
void RedrawReportWithMount(const CalibrationResult& result, const calib::Mount& mount,
                           const std::string& mount_source, ReportData* data);

// The gates of the second pass, from the first pass's covariance.
calib::Gates TightGates(const CalibrationResult& result);

}  // namespace wallcal::pipeline
