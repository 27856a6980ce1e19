// SPDX-License-Identifier: Apache-2.0
#pragma once
// The steps of a calibration run, one function each; pipeline::CalibrationSession
// (pipeline/session.h) calls them in order and keeps each one's result. A step reads the
// results of the steps before it (const) and what the run shares but does not report
// (RunState), and returns its own result. Internal to pipeline/.

#include <Eigen/Core>
#include <atomic>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "calib/detection_pass.h"
#include "io/types.h"
#include "pipeline/calibration.h"
#include "pipeline/run_warnings.h"
#include "recording/recording_streams.h"

namespace wallcal::pipeline {

// What the steps share that the result does not show.
struct RunState {
  std::optional<io::PreviousOffsets> previous;  // the --compare file, read before the work
  io::NmeaLog gnss;
  io::NmeaLog headings;  // the heading log (a copy of gnss when it is the same file)
  io::NmeaLog attitudes;  // the session's attitude stream (attitude:), its offset applied
  std::vector<const io::GnssFix*> used_fixes;  // into gnss.fixes
  std::vector<Eigen::Vector2d> track_local_m;  // the fixes used, in the local frame
  calib::PassContext pass;                     // how the passes read scans (set by PreparePasses)
  bool passes_prepared = false;
  // The second pass's detections, until the solve takes them.
  std::vector<calib::WallObservation> detections;
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

// session.yaml, the options and the scanner preset; the --compare file into state->previous
// (a bad one fails before the work).
LoadResult Load(const CalibrateRequest& request, RunState* state);
// Starts the SHA-256 digests of the inputs (after Load).
void StartDigests(const CalibrateRequest& request, const LoadResult& loaded, RunState* state);

// The survey, its tie to UTM and the walls as lines in the local frame. swap_survey_axes: the
// survey's x and y exchanged first (ProbeMirroredSurvey).
SurveyResult TieSurveyAndFitWalls(const io::SessionSpec& session,
                                  const solvers::SolverOptions& solver,
                                  bool swap_survey_axes = false);

// The GNSS and heading logs (read by the caller: whole by calibrate, on as they grow by the
// guide) as poses: the interpolator, its dwells, the white noise in use. Keeps the logs and the
// track in *state. Throws io::InputError for what the logs hold.
PoseResult PosesFromLogs(const CalibrationResult& so_far, recording::PoseLogs logs,
                         RunState* state);

// The site's 3-D geometry from the session and the pose logs (pipeline/site_step.cc).
SiteResult SiteFromPoses(const CalibrationResult& so_far, const RunState& state);

// The corrections already in the observations: made on `site` with `walls` at `mount`.
struct SiteCorrectionsMade {
  const SiteResult* site = nullptr;
  const std::vector<calib::WallGeometry>* walls = nullptr;
  calib::Mount mount;
};
// Moves each observation into the level model at `mount` (calib::LevelCorrection subtracted
// from its rho_m and theta_rad; `made`, when given, the corrections made before put back
// first) and sets the variance the attitude's noise adds; nothing on a site not corrected
// (pipeline/site_solve.cc).
void ApplySiteCorrections(const SiteResult& site, const std::vector<calib::WallGeometry>& walls,
                          const calib::Mount& mount,
                          std::vector<calib::WallObservation>* observations,
                          const SiteCorrectionsMade* made = nullptr);

// After the solve on a corrected site (or a graded one without scanner.z_m): the site's
// systematic terms into step->site_terms and step->estimate.covariance, the bias an unknown
// scanner height could cause into step->unknown_height_bias. `corrected_at`: the mount the
// observations' corrections were made at.
void PropagateSiteTerms(const CalibrationResult& so_far, const calib::Mount& corrected_at,
                        SolveResult* step);

// The reasons for REVIEW the site gives `estimate` (pipeline/site_step.cc): a graded yard whose
// grade, with scanner.z_m not given, could move the mount by more than a third of its σ; an
// attitude stream that disagrees with the yard.
std::vector<std::string> SiteReviews(const CalibrationResult& run,
                                     const solvers::MountEstimate& estimate);

// Which scans taken while moving the passes use, for a session with `num_dwells` dwells:
// use_moving (the passes detect them) and moving_by_default (DetectionResult).
struct MovingScans {
  bool use_moving = false;
  bool moving_by_default = false;
};
MovingScans ChooseMovingScans(const CalibrateOptions& options, int num_dwells);

// How the detection passes read scans (into state->pass: the scan log or recording, checked
// against the preset) and which scans they use.
struct PassSetup {
  bool moving_by_default = false;
  std::string scanner_from_data;
  Warnings warnings;
};
PassSetup PreparePasses(const CalibrateRequest& request, const CalibrationResult& so_far,
                        RunState* state);

// First pass (wide gates, subsample) and the start estimate.
struct FirstPassStep {
  // The refined start; when `stopped`, the estimate that says why the run stops here.
  solvers::MountEstimate estimate;
  bool stopped = false;
  int64_t scans_in_log = 0;  // scan records read
  int64_t scans_total = 0;   // scan records + malformed scan lines (set when stopped)
};
FirstPassStep FirstPass(const CalibrateRequest& request, const ProgressFn& progress,
                        const CalibrationResult& so_far, const RunState& state);

// The gates of the second pass, from the first pass's covariance.
calib::Gates TightGates(const CalibrationResult& so_far);
// The second pass's request: tight gates around the first pass's estimate.
calib::PassRequest TightPass(const CalibrationResult& so_far);

// Second pass (every scan, tight gates) and its accounting; a preview's also tallies every scan
// read (scan_log). Its detections go to state->detections.
struct SecondPassStep {
  std::map<calib::ScanSkip, int64_t> scans_skipped;
  io::SkipCounts scan_lines_skipped;
  int64_t scans_total = 0;
  std::optional<calib::ScanLogTally> scan_log;
  Warnings warnings;
};
SecondPassStep SecondPass(const CalibrateRequest& request, const ProgressFn& progress,
                          const CalibrationResult& so_far, RunState* state);

// The solve by the requested method (with the clock-offset rounds) on `observations`, started
// at `start`: the drives dropped when their timing is not determined, the closed form's σ
// dropped, the estimate checked against scanner.mount_guess. A preview solves on every k-th
// observation weighted by k and gives back every detection. When the passes stopped, the first
// pass's refusal.
SolveResult Solve(const CalibrateRequest& request, const ProgressFn& progress,
                  const CalibrationResult& so_far, std::vector<calib::WallObservation> observations,
                  const calib::Mount& start);

// Residual analysis and repeatability of a usable estimate, the error budget with the refusal
// advice it supports, and the coverage of the observations.
FinishResult Finish(const CalibrateRequest& request, const ProgressFn& progress,
                    const CalibrationResult& so_far);

// Throws io::InputError naming a mirrored survey when no scan sees the surveyed wall where the
// survey puts it, but with the survey's x and y exchanged the scans determine the mount (two
// control points fit a mirrored survey as well as the right one).
void ProbeMirroredSurvey(const CalibrateRequest& request, const CalibrationResult& so_far,
                         const RunState& state);

// The verdict, the change since the previous calibration and the provenance.
DecideResult Decide(const CalibrateRequest& request, const CalibrationResult& so_far,
                    const RunState& state);

// The site map, stations and scan panels of the report (pipeline/report_collect.cc).
ReportData CollectReportData(const CalibrationResult& so_far, const RunState& state);

// The warning that `scans` scans taken while driving were left out.
Warning DrivesNotUsedWarning(int64_t scans);

// ---- What the steps share (pipeline/step_counts.cc) ----
std::string FileName(const std::string& path);  // the path's last part
// "file: N lines skipped (reason: n, first at line L; ...)" for the problem reasons; empty
// when there are none.
std::string DescribeSkips(const std::string& file, const io::SkipCounts& skips);
// How many distinct values `values` holds (sorted in place). An hour's observations name
// 300 000 scans: one sort of their indices instead of a std::set node (an allocation) per scan.
int64_t CountDistinct(std::vector<int>* values);

}  // namespace wallcal::pipeline
