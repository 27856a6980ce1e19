// SPDX-License-Identifier: Apache-2.0
#pragma once
// A whole calibration run as one library call, so that the programs, the tests and another
// program (a ROS node) run the same steps in-process:
//   io/ reads the session -> calib/ makes wall observations (two detection passes) ->
//   solvers/ estimates the mount -> analysis/ examines it. Nothing is written here: outputs/
//   turns the result into offsets.yaml, the summary, the emitted transforms and the report.
// RunCalibration runs a pipeline::CalibrationSession (pipeline/session.h) to its end.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/report_data.h"
#include "pipeline/step_results.h"
#include "solvers/solve_policy.h"

namespace wallcal::pipeline {

struct CalibrateRequest {
  std::string session_path;  // session.yaml or its folder
  std::string config_path;   // calibrate options YAML; empty: built-in defaults
  solvers::Method method = solvers::Method::kCeres;
  bool force = false;  // write an estimate the observability checks refuse, with a warning
  bool collect_report_data = false;  // fill CalibrationResult::report (one more scan pass)
  std::string compare_path;  // an earlier offsets.yaml to compare with; empty: none
  std::vector<std::string> command_line;  // argv, recorded in offsets.yaml's provenance
  // Threads for wall detection, the solve and the information matrix; 0: every core. The
  // result does not depend on it (beyond round-off in the solve, far below 1e-9 m).
  int threads = 0;
  // A preview (inspect): the mount and its σ only, solved on every k-th observation weighted
  // by k (at most analysis::kMaxRefitObservations, as the repeatability's re-solves); no
  // repeatability re-solves, no error budget, no input digests. SolveResult::observations are
  // still every detection of the second pass.
  bool preview = false;
  // A session with `scanners:`: the index of the scanner this run calibrates alone
  // (io::SessionForScanner); -1 for a one-scanner session. RunSeveralScanners sets it.
  int scanner_index = -1;
  // A session with `scanners:` given to a command that takes one scanner (guide,
  // characterise): the id of that scanner (--scanner ID); empty: none chosen.
  std::string scanner_id;
};

// The stages of a run, in order.
enum class Stage {
  kReadingInputs,
  kFirstPass,
  kSecondPass,
  kSolving,
  kClockOffsetRound,
  kResidualAnalysis,
  kRepeatability,
  kErrorBudget,
  kReportData,
  kDone,
};

// Progress of a long run: the stage, a line for people, and within a scan pass how far it got
// (total == 0 when the total is not known: the first pass over the scan log).
struct Progress {
  Stage stage = Stage::kReadingInputs;
  std::string text;
  int64_t done = 0;
  int64_t total = 0;
  bool counted = false;  // done/total are meaningful (a scan pass)
};
using ProgressFn = std::function<void(const Progress&)>;

// Everything calibrate learned, for the summary, offsets.yaml and the report: one result per
// step of the run, in step order (pipeline/step_results.h), each written by its step alone.
struct CalibrationResult {
  LoadResult loaded;
  SurveyResult survey;
  PoseResult poses;
  SiteResult site;
  DetectionResult detection;
  SolveResult solve;
  FinishResult finish;
  DecideResult decided;
  ReportData report;     // filled when the request asked for it
  double seconds = 0.0;  // wall-clock run time, for the summary

  // Every step's warnings, in step order.
  Warnings AllWarnings() const;
  // Every scan skipped, by reason: the passes' and the solve's.
  std::map<calib::ScanSkip, int64_t> ScansSkipped() const;
  // Why the estimate is not usable: the finish step's advice when it has one, else the
  // estimate's own message.
  const std::string& Why() const;
  // The solver options the solve uses: the configured ones with the white noise in use (the
  // configured white noise before the poses step).
  solvers::SolverOptions SolverInUse() const;
};

// Runs the whole calibration. Writes nothing. Throws io::InputError for bad input; an
// estimate the data cannot support comes back with estimate.usable == false, its failure kind
// and a message. `progress` (may be empty) is called at each stage and every 2000 scans.
CalibrationResult RunCalibration(const CalibrateRequest& request,
                                 const ProgressFn& progress = nullptr);

// Default output path: offsets.yaml beside session.yaml.
std::string DefaultOutputPath(const io::SessionSpec& session);

}  // namespace wallcal::pipeline
