// SPDX-License-Identifier: Apache-2.0
#pragma once
// One calibration run as an object that owns the run's state and steps through it: load,
// survey, poses, detection, solve, finish, the mirrored-survey probe, decide, the report's
// data. Each step keeps its result in result() under its own name (pipeline/step_results.h)
// and reads only the results of the steps before it. calibrate runs every step (Run, which
// RunCalibration calls); the guide runs load and survey once and then, at each refresh of logs
// that grow, the poses on the logs as they are, the detection of the scans the log gained and a
// preview solve (the methods under "Logs that grow"); several scanners run one session per
// scanner (pipeline/multi_scanner.h).
//
// Every step throws io::InputError for bad input. A step called before the one it needs is a
// programming error (assert).

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "calib/detection_pass.h"
#include "io/scan_source.h"
#include "pipeline/calibration.h"
#include "recording/recording_streams.h"

namespace wallcal::pipeline {

struct RunState;

class CalibrationSession {
 public:
  // `progress` (may be empty) is called at each stage and every 2000 scans of a pass.
  explicit CalibrationSession(CalibrateRequest request, ProgressFn progress = nullptr);
  ~CalibrationSession();
  CalibrationSession(const CalibrationSession&) = delete;
  CalibrationSession& operator=(const CalibrationSession&) = delete;

  // Every step in order, then the result (moved out: the session is spent).
  CalibrationResult Run();

  // ---- The steps, in order ----
  const LoadResult& Load();         // session.yaml, the options, the preset, the --compare file
  const SurveyResult& Survey();     // the survey tied to UTM, the walls
  const PoseResult& Poses();        // the GNSS and heading logs, read whole
  const SiteResult& Site();         // the vehicle's attitude, the yard, the scanner's height
  const DetectionResult& Detect();  // both detection passes over the scan log
  const SolveResult& Solve();       // on the second pass's detections
  const FinishResult& Finish();     // residuals, repeatability, error budget, coverage
  void ProbeMirroredSurvey();       // throws io::InputError for a survey with x and y exchanged
  const DecideResult& Decide();
  void CollectReport();  // the report's drawings (when the request asks for them)

  // ---- Logs that grow (the guide) ----
  // Poses on logs the caller read (as they are now); again at each refresh.
  const PoseResult& Poses(recording::PoseLogs logs);
  // The passes read the scans `open` gives from here on (the first time, after the preset is
  // checked against the scan log), using the drives as a fresh read would for the dwells the
  // poses hold now. After Poses.
  using ScanOpener = std::function<std::unique_ptr<io::ScanSource>()>;
  void ReadScansFrom(ScanOpener open);
  // The first pass over the scans (wide gates): the start estimate, or why there is none yet
  // (DetectionResult::stopped).
  const DetectionResult& FirstPass();
  // The second pass's gates (around the first pass's estimate) over the scans `open` gives:
  // their observations in file order, scan_index counted from the first scan `open` gives.
  calib::PassOutcome DetectWithTightGates(ScanOpener open);
  // The solve on `observations` (every detection so far), started at `start` (empty: the first
  // pass's estimate); when the first pass stopped, its refusal.
  const SolveResult& Solve(std::vector<calib::WallObservation> observations,
                           const std::optional<calib::Mount>& start);

  const CalibrationResult& result() const { return result_; }
  const CalibrateRequest& request() const { return request_; }

 private:
  CalibrateRequest request_;
  ProgressFn progress_;
  CalibrationResult result_;
  std::unique_ptr<RunState> state_;
};

}  // namespace wallcal::pipeline
