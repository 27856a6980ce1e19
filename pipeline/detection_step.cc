// SPDX-License-Identifier: Apache-2.0
// The detection step of a calibration run (pipeline/internal/steps.h): the passes set up on the
// scan log (checked against the preset), the first pass on a subsample with wide gates for a
// start estimate, the second over every scan with tight gates around it.

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/angles.h"
#include "common/format.h"
#include "pipeline/checks.h"
#include "pipeline/internal/steps.h"
#include "solvers/mount_solver.h"

namespace wallcal::pipeline {
namespace {

// Stops the run after the first pass: the estimate says why.
FirstPassStep StopAfterFirstPass(solvers::MountEstimate estimate, const calib::PassOutcome& pass) {
  FirstPassStep step;
  step.estimate = std::move(estimate);
  step.stopped = true;
  step.scans_in_log = pass.scans_read;
  step.scans_total = pass.scans_read + pass.line_skips.Problems();
  return step;
}

}  // namespace

calib::Gates TightGates(const CalibrationResult& so_far) {
  const Eigen::Matrix3d& c1 = so_far.detection.first_pass.covariance;
  const calib::DetectorOptions& detector = so_far.loaded.options.detector;
  return calib::Gates{
      std::max(detector.tight_angle_gate_rad, 5.0 * std::sqrt(std::max(0.0, c1(2, 2)))),
      std::max(detector.tight_offset_gate_m, 5.0 * std::sqrt(std::max(0.0, c1(0, 0) + c1(1, 1)))),
      true, detector.tight_min_inliers};
}

MovingScans ChooseMovingScans(const CalibrateOptions& options, int num_dwells) {
  MovingScans moving;
  // Moving scans: when asked for, or when the engineer drove continuously (too few dwells to
  // calibrate from stations alone). The solver then estimates the scanner clock offset too.
  moving.use_moving =
      options.alignment.use_moving_scans ||
      (options.alignment.moving_scans_if_few_stations && num_dwells < options.solver.min_stations);
  // Stop-and-go: the drives between the stops too, kept if the clock offset is determined.
  moving.moving_by_default = !moving.use_moving && options.alignment.moving_scans_in_stop_and_go;
  moving.use_moving = moving.use_moving || moving.moving_by_default;
  return moving;
}

PassSetup PreparePasses(const CalibrateRequest& request, const CalibrationResult& so_far,
                        RunState* state) {
  PassSetup setup;
  const LoadResult& loaded = so_far.loaded;
  const CalibrateOptions& options = loaded.options;
  calib::PassContext& pass = state->pass;
  // A CARMEN log, or a recording's LaserScan topic checked against the preset. The context
  // points into `so_far` (preset, detector options, walls, poses): they outlive the passes.
  pass.open_scans = recording::MakeScanOpener(loaded.session, &loaded.preset);
  pass.scanner_time_offset_s = loaded.session.scanner_time_offset_s;
  pass.preset = &loaded.preset;
  pass.detector = &options.detector;
  pass.walls = &so_far.survey.walls;
  pass.poses = so_far.poses.interpolator.get();
  // A preset that does not fit the scans (beams, step, range) misplaces every beam: refuse
  // before the detection passes, naming both, unless forced.
  const PresetFit fit = CheckPresetAgainstScans(pass.open_scans, loaded.preset);
  EnforcePresetFit(fit, loaded.preset, loaded.session, request.force, &setup.warnings);
  setup.scanner_from_data = fit.taken_from_data;
  pass.threads = options.solver.num_threads;
  const int dwells = so_far.poses.num_dwells;
  const MovingScans moving = ChooseMovingScans(options, dwells);
  pass.use_moving = moving.use_moving;
  setup.moving_by_default = moving.moving_by_default;
  if (pass.use_moving && !options.alignment.use_moving_scans && !setup.moving_by_default) {
    setup.warnings.push_back(
        {WarningKind::kMovingScansUsed,
         "only " + std::to_string(dwells) +
             " stations (dwells) found: scans taken while moving are used, with "
             "an estimated scanner clock offset (stop-and-go is more accurate)"});
  }
  return setup;
}

FirstPassStep FirstPass(const CalibrateRequest& request, const ProgressFn& progress,
                        const CalibrationResult& so_far, const RunState& state) {
  const io::SessionSpec& session = so_far.loaded.session;
  const CalibrateOptions& options = so_far.loaded.options;
  const calib::PoseInterpolator& poses = *so_far.poses.interpolator;
  calib::PassRequest pass;
  if (session.mount_guess) {
    pass.mount = calib::Mount{session.mount_guess->x_m, session.mount_guess->y_m,
                              session.mount_guess->yaw_rad};
  }
  pass.gates = calib::Gates{options.detector.wide_angle_gate_rad,
                            options.detector.wide_offset_gate_m, false};
  pass.min_interval_s =
      (poses.end_s() - poses.start_s()) / std::max(1, options.first_pass_max_scans);
  if (progress) {
    pass.progress = [&progress](int64_t done) {
      progress(Progress{Stage::kFirstPass, "first pass", done, 0, true});
    };
  }
  Say(progress, Stage::kFirstPass, "first pass: wall detection on a subsample with wide gates");
  const calib::PassOutcome first = calib::DetectionPass(state.pass, pass);
  if (first.scans_read == 0) {
    std::string why = "no scan records";
    if (const std::string w = DescribeSkips(session.scanner_log, first.line_skips); !w.empty()) {
      why += "; " + w;
    }
    throw io::InputError(io::Where(session.scanner_log, 0,
                                   why + "; expected CARMEN RAWLASER1/ROBOTLASER1/FLASER lines"));
  }
  if (first.observations.empty()) {
    // A scan log wholly outside the GNSS/heading time span is bad input (wrong file, wrong
    // clock), not a geometry the data cannot decide.
    bool only_outside = !first.skipped.empty();
    for (const auto& [reason, count] : first.skipped) {
      only_outside = only_outside && (reason == calib::ScanSkip::kNoPoseBeforeLogs ||
                                      reason == calib::ScanSkip::kNoPoseAfterLogs);
    }
    if (only_outside) {
      throw io::InputError(io::Where(
          session.scanner_log, 0,
          Format("the scans (%.3f..%.3f s) do not overlap the GNSS and heading logs "
                 "(%.3f..%.3f s); expected logs from the same run on the same clock "
                 "(check scanner.time_offset_s)",
                 first.first_stamp_s, first.last_stamp_s, poses.start_s(), poses.end_s())));
    }
    // The key of the guess: scanner.mount_guess, or mount_guess of a scanners: entry.
    const std::string guess_key = session.scanner_id.empty()
                                      ? "scanner.mount_guess"
                                      : "mount_guess of scanner '" + session.scanner_id + "'";
    bool never_in_field = false;
    for (const auto& [reason, count] : first.skipped) {
      if (reason == calib::ScanSkip::kWallOutsideField) never_in_field = true;
    }
    for (const auto& [reason, count] : first.skipped) {
      if (reason == calib::ScanSkip::kWallNotDetected ||
          reason == calib::ScanSkip::kScannerBehindWall) {
        never_in_field = false;
      }
    }
    std::ostringstream why;
    if (never_in_field && session.mount_guess) {
      why << "the wall was never in the scanner's field of view from any station ("
          << first.scans_examined << " sampled scans), with the scanner where " << guess_key
          << " puts it; check that guess (its yaw first), or stop with the scanner facing a "
             "surveyed wall";
    } else {
      why << "the wall was not detected in any of " << first.scans_examined << " sampled scans (";
      bool first_reason = true;
      for (const auto& [reason, count] : first.skipped) {
        why << (first_reason ? "" : "; ") << calib::ScanSkipName(reason) << ": " << count;
        first_reason = false;
      }
      why << "); check the walls' survey codes, the scanner model, the time overlap of the logs, "
          << (session.mount_guess ? "or " + guess_key + " (its yaw first)"
                                  : "or give " + guess_key);
    }
    solvers::MountEstimate none;
    none.failure = solvers::EstimateFailure::kWallNotDetected;
    none.message = why.str();
    return StopAfterFirstPass(std::move(none), first);
  }
  // The first pass only starts the second: the σ limits (a refusal of the final estimate, with
  // every scan counted) do not apply to it.
  solvers::SolverOptions first_solver = so_far.SolverInUse();
  first_solver.max_sigma_xy_m = 1e3;  // finite: the check scales the information by them
  first_solver.max_sigma_yaw_rad = 1e3;
  const solvers::MountEstimate start = solvers::SolveMountBarawid(
      first.observations, so_far.survey.walls, first_solver, request.force);
  if (!start.usable) {
    return StopAfterFirstPass(start, first);
  }
  const solvers::MountEstimate refined = solvers::SolveMountCeres(
      first.observations, so_far.survey.walls, first_solver, start.mount, request.force);
  if (!refined.usable) {
    return StopAfterFirstPass(refined, first);
  }
  FirstPassStep step;
  step.scans_in_log = first.scans_read;
  Say(progress, Stage::kFirstPass,
      "first pass: " + std::to_string(first.observations.size()) + " observations, mount x " +
          Format("%.3f", refined.mount.x_m) + " m, y " + Format("%.3f", refined.mount.y_m) +
          " m, yaw " + Format("%.2f", refined.mount.yaw_rad * kRadToDeg) + " deg");
  step.estimate = refined;
  return step;
}

calib::PassRequest TightPass(const CalibrationResult& so_far) {
  const solvers::MountEstimate& first = so_far.detection.first_pass;
  calib::PassRequest pass;
  pass.mount = first.mount;
  pass.gates = TightGates(so_far);
  pass.gate_time_offset_s = first.time_offset_estimated ? first.time_offset_s : 0.0;
  return pass;
}

SecondPassStep SecondPass(const CalibrateRequest& request, const ProgressFn& progress,
                          const CalibrationResult& so_far, RunState* state) {
  SecondPassStep step;
  const io::SessionSpec& session = so_far.loaded.session;
  calib::PassRequest pass = TightPass(so_far);
  Say(progress, Stage::kSecondPass, "second pass: wall detection in every scan with tight gates");
  calib::PassOutcome second;
  if (progress) {
    // The total is known from the first pass: every scan is read again.
    const int64_t total = so_far.detection.scans_in_log;
    pass.progress = [&progress, total](int64_t done) {
      progress(Progress{Stage::kSecondPass, "second pass", done, total, true});
    };
  }
  calib::ScanLogTally tally;
  if (request.preview) pass.tally = &tally;  // inspect's scan-log summary
  second = calib::DetectionPass(state->pass, pass);
  if (request.preview) step.scan_log = std::move(tally);
  if (progress) {
    // The pass reports every 2000 scans: the last count is said here.
    progress(Progress{Stage::kSecondPass, "second pass", second.scans_read,
                      std::max(so_far.detection.scans_in_log, second.scans_read), true});
  }
  state->detections = std::move(second.observations);
  // The vector grew by doubling: up to half of it is spare capacity, held through the solve.
  state->detections.shrink_to_fit();
  step.scans_skipped = second.skipped;
  step.scan_lines_skipped = second.line_skips;
  step.scans_total = second.scans_read + second.line_skips.Problems();
  if (const std::string w = DescribeSkips(session.scanner_log, second.line_skips); !w.empty()) {
    step.warnings.push_back({WarningKind::kLinesSkipped, w});
    step.scans_skipped[calib::ScanSkip::kMalformedLine] += second.line_skips.Problems();
  }
  if (second.not_increasing > 0) {
    step.warnings.push_back({WarningKind::kScansOutOfOrder,
                             FileName(session.scanner_log) + ": " +
                                 std::to_string(second.not_increasing) +
                                 " scans not later than the scan before them (first at line " +
                                 std::to_string(second.first_not_increasing_line) +
                                 "); each was used at its own time"});
  }
  if (second.beam_count_mismatch > 0) {
    step.warnings.push_back({WarningKind::kBeamCountMismatch,
                             std::to_string(second.beam_count_mismatch) + " scans have " +
                                 std::to_string(second.first_mismatch_beams) + " beams, preset " +
                                 so_far.loaded.preset.name + " has " +
                                 std::to_string(so_far.loaded.preset.num_beams) +
                                 ": check scanner.model"});
  }
  return step;
}

}  // namespace wallcal::pipeline
