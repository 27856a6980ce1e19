// SPDX-License-Identifier: Apache-2.0
#pragma once
// A whole calibration run as one library call, so that the programs, the tests and another
// program (a ROS node) run the same steps in-process:
//   io/ reads the session -> calib/ makes wall observations (two detection passes) ->
//   solvers/ estimates the mount -> analysis/ examines it. Nothing is written here: outputs/
//   turns the result into offsets.yaml, the summary, the emitted transforms and the report.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/repeatability.h"
#include "analysis/residual_analysis.h"
#include "calib/detection_pass.h"
#include "calib/gnss_epoch_time.h"
#include "calib/observation.h"
#include "calib/time_alignment.h"
#include "pipeline/calibrate_options.h"
#include "io/types.h"
#include "analysis/error_budget.h"
#include "calib/white_noise.h"
#include "pipeline/report_data.h"
#include "pipeline/run_warnings.h"
#include "pipeline/verdict.h"
#include "solvers/mount_solver.h"
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
  // repeatability re-solves, no error budget, no input digests. The result's observations are
  // still all the second pass detected.
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

// One stream's delay (docs/time-alignment.md). kNotEstimated: the data hold nothing about it
// (no moving scans; prior σ 0), value 0; kNotDetermined: estimated, but its σ is more than half
// its prior's (too few turns for the heading's): the value is the prior's pull, and the mount's
// σ carries it marginalised under the prior; kDetermined: the data fix it.
enum class DelayStatus { kNotEstimated, kNotDetermined, kDetermined };
const char* DelayStatusName(DelayStatus status);  // "not estimated", "not determined", ...
struct StreamDelay {
  DelayStatus status = DelayStatus::kNotEstimated;
  double value_s = 0.0;
  double sigma_s = 0.0;        // posterior 1σ; 0 when not estimated
  double prior_sigma_s = 0.0;  // the option's prior σ
};

// Everything calibrate learned, for the summary, offsets.yaml and the report.
struct CalibrationResult {
  io::SessionSpec session;
  io::ScannerPreset preset;
  pipeline::CalibrateOptions options;        // the options the run used
  solvers::MountEstimate first_pass;   // wide-gate pass on a subsample (Barawid start + Ceres)
  solvers::MountEstimate estimate;     // the final estimate by the requested method
  std::vector<calib::WallGeometry> walls;
  std::vector<calib::WallObservation> observations;  // second pass
  // The GNSS and heading streams the observations' poses were interpolated from (null when
  // the run stopped before reading them): a joint adjustment of several scanners
  // re-interpolates each scanner's poses at its own estimated scan time (multi_scanner.h).
  std::shared_ptr<const calib::PoseInterpolator> poses;
  // A preview's solve: how many observations it used (every k-th; 0 when not a preview).
  int64_t preview_observations_solved = 0;
  // A preview's tally of every scan the second pass read (inspect's scan-log summary); empty
  // when not a preview or when the run stopped before the second pass.
  std::optional<calib::ScanLogTally> scan_log;
  calib::LocalFrame frame;
  // The GNSS and heading white noise measured at the stops (calib/white_noise.h); with
  // solver.use_measured_white_noise, options.solver.gnss_white_sigma_m and heading_sigma_rad are
  // each its measure where there is one, and the configured_ values keep the configured ones.
  calib::MeasuredWhiteNoise measured_noise;
  double configured_gnss_white_sigma_m = 0.0;
  double configured_heading_sigma_rad = 0.0;
  double control_rms_m = 0.0;
  int num_control = 0;
  int num_dwells = 0;
  int num_segments_used = 0;
  // Scan accounting: every scan line of the log is in exactly one bucket.
  int64_t scans_total = 0;  // valid scan records read + malformed scan lines skipped
  int64_t scans_used = 0;   // scans with at least one wall observation in the final solve
  int64_t scans_used_moving = 0;  // of which taken while driving (the rest at stations)
  std::map<calib::ScanSkip, int64_t> scans_skipped;
  std::map<int, int64_t> fixes_by_quality;
  int64_t fixes_used = 0;
  int64_t headings_used = 0;
  io::SkipCounts gnss_skipped, heading_skipped, scan_lines_skipped;
  double heading_min_deg = 0.0, heading_max_deg = 0.0;  // grid headings of used scans
  double wall_angle_min_deg = 0.0, wall_angle_max_deg = 0.0;  // vehicle-to-wall angle φ
  analysis::ResidualAnalysis residual_analysis;
  analysis::Repeatability repeatability;
  double time_offset_s = 0.0;        // estimated scanner-to-GNSS clock offset (moving data)
  double time_offset_sigma_s = 0.0;  // 0 when not estimated
  // How well the timing the drives' poses need is known (s; solvers::DrivesTimingSigma): the
  // clock offset when driving towards a wall, offset + heading delay when turning in front of
  // it. 0 when no moving scan is used.
  double drives_timing_sigma_s = 0.0;
  // Per-stream delays. gnss_epochs: the GGA epochs mapped onto the logger clock
  // (offset_s = receiver latency + logger clock offset to UTC, jitter_s its scatter);
  // scanner_offset: time_offset_s above with its status (true scan time = stamp + dt, on the
  // GNSS-epoch clock); heading_delay: the heading stream's delay after the GNSS epochs.
  calib::GnssEpochMapping gnss_epochs;
  StreamDelay scanner_offset;
  StreamDelay heading_delay;
  bool forced = false;               // written despite a failed observability check
  // false: the method gives no σ (barawid): estimate.covariance is NaN, and offsets.yaml, the
  // summary and the emitted JSON say so.
  bool sigma_known = true;
  analysis::ErrorBudget budget;      // what the σ is made of (ceres)
  std::optional<Change> change;      // since the --compare file, when given and usable
  Decision decision;                 // ACCEPT / REVIEW / REJECT with the reasons
  Provenance provenance;
  // The scanner geometry taken from the scans where it differs from the preset's within the
  // family's limits ("681 beams (preset 682), range_max 5.600 m (preset 4.095 m)"); empty when
  // the scans have the preset's (io/scanner_geometry.h).
  std::string scanner_from_data;
  Warnings warnings;  // collected from the steps, in step order (pipeline/run_warnings.h)
  ReportData report;                 // filled when the request asked for it
  double seconds = 0.0;  // wall-clock run time, for the summary
};

// Runs the whole calibration. Writes nothing. Throws io::InputError for bad input; an
// estimate the data cannot support comes back with estimate.usable == false, its failure kind
// and a message. `progress` (may be empty) is called at each stage and every 2000 scans.
CalibrationResult RunCalibration(const CalibrateRequest& request,
                                 const ProgressFn& progress = nullptr);

// Default output path: offsets.yaml beside session.yaml.
std::string DefaultOutputPath(const io::SessionSpec& session);

}  // namespace wallcal::pipeline
