// SPDX-License-Identifier: Apache-2.0
// The steps of a calibration run (pipeline/steps.h).

#include "pipeline/steps.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <thread>

#include "calib/geodesy.h"
#include "calib/gnss_epoch_time.h"
#include "calib/pose_samples.h"
#include "common/angles.h"
#include "common/circular.h"
#include "common/format.h"
#include "io/config/offsets_reader.h"
#include "io/config/session_reader.h"
#include "io/survey/survey_reader.h"
#include "io/text/carmen_reader.h"
#include "io/text/nmea_reader.h"
#include "pipeline/checks.h"
#include "pipeline/config_dirs.h"
#include "pipeline/stream_delays.h"
#include "recording/recording_streams.h"
#include "solvers/mount_problem.h"
#include "solvers/solve_policy.h"

namespace wallcal::pipeline {
namespace {

namespace fs = std::filesystem;

std::string FileName(const std::string& path) { return fs::path(path).filename().string(); }

// "file: N lines skipped (reason: n, first at line L; ...)" for the problem reasons; empty
// when there are none.
std::string DescribeSkips(const std::string& file, const io::SkipCounts& skips) {
  if (skips.Problems() == 0) return std::string();
  return FileName(file) + ": " + std::to_string(skips.Problems()) + " lines skipped (" +
         skips.ListReasons(true) + ")";
}

// How many distinct values `values` holds (sorted in place). An hour's observations name 300 000
// scans: one sort of their indices instead of a std::set node (an allocation) per scan.
int64_t CountDistinct(std::vector<int>* values) {
  std::sort(values->begin(), values->end());
  return static_cast<int64_t>(std::unique(values->begin(), values->end()) - values->begin());
}

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

void Say(const ProgressFn& progress, Stage stage, const std::string& text) {
  if (progress) progress(Progress{stage, text, 0, 0, false});
}

calib::Gates TightGates(const CalibrationResult& result) {
  const Eigen::Matrix3d& c1 = result.first_pass.covariance;
  const calib::DetectorOptions& detector = result.options.detector;
  return calib::Gates{
      std::max(detector.tight_angle_gate_rad, 5.0 * std::sqrt(std::max(0.0, c1(2, 2)))),
      std::max(detector.tight_offset_gate_m, 5.0 * std::sqrt(std::max(0.0, c1(0, 0) + c1(1, 1)))),
      true, detector.tight_min_inliers};
}

Setup LoadSessionAndOptions(const CalibrateRequest& request) {
  Setup setup;
  setup.session = io::ReadSession(request.session_path);
  if (request.scanner_index >= 0) {
    setup.session = io::SessionForScanner(setup.session, request.scanner_index);
  } else if (!request.scanner_id.empty()) {
    setup.session = io::SessionForScannerId(setup.session, request.scanner_id);
  } else if (!setup.session.scanners.empty()) {
    throw io::InputError(io::Where(
        setup.session.file, setup.session.scanners.front().line,
        "scanners: lists several scanners; expected --scanner ID for this command (ID one of " +
            io::ScannerIds(setup.session) +
            "), or wallcal calibrate, which takes them all"));
  }
  if (!request.config_path.empty()) setup.options = ReadCalibrateOptions(request.config_path);
  setup.options.Validate();
  setup.options.solver.num_threads =
      request.threads > 0 ? request.threads
                          : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  // A measured preset beside the session (characterise writes <session>/scanners/NAME.yaml)
  // is found first, then the shipped ones (config_dirs.h).
  setup.preset = LoadSessionPreset(setup.session.scanner_model, setup.session.dir);
  // The previous calibration is read now: a bad --compare file fails before the work.
  if (!request.compare_path.empty()) setup.previous = io::ReadPreviousOffsets(request.compare_path);
  return setup;
}

PoseStep ReadPoses(const CalibrationResult& result) {
  // Text logs or recording topics (one pass when GNSS and heading share a recording).
  return PosesFromLogs(result, recording::ReadPoseLogs(result.session));
}

PoseStep PosesFromLogs(const CalibrationResult& result, recording::PoseLogs logs) {
  PoseStep step;
  const io::SessionSpec& session = result.session;
  const CalibrateOptions& options = result.options;
  const bool one_log = session.heading_log == session.gnss_log;
  step.gnss = std::move(logs.gnss);
  step.headings = std::move(logs.headings);
  for (std::string& w : logs.warnings) step.warnings.push_back({WarningKind::kPoseLog, std::move(w)});
  // Each GGA at its epoch on the logger clock, not at its jittered arrival (docs/time-alignment.md).
  step.gnss_epochs =
      calib::MapGnssEpochs(&step.gnss.fixes, options.alignment.gnss_epoch_time);
  if (step.gnss_epochs.status == calib::EpochMappingStatus::kInconsistent ||
      step.gnss_epochs.status == calib::EpochMappingStatus::kTooFew) {
    step.warnings.push_back(
        {WarningKind::kGnssEpochTime,
        "GNSS epoch time " + std::string(calib::EpochMappingStatusName(step.gnss_epochs.status)) +
        ": logger stamp − UTC over " + std::to_string(step.gnss_epochs.fixes) +
        " fixes has scatter " + Format("%.1f", 1000.0 * step.gnss_epochs.jitter_s) +
        " ms, drift " + Format("%.0f", 1e6 * step.gnss_epochs.drift) + " ppm, " +
        std::to_string(step.gnss_epochs.outliers) +
        " outliers; the fixes keep their arrival stamps"});
  }
  if (const std::string w = DescribeSkips(session.gnss_log, step.gnss.skipped); !w.empty()) {
    step.warnings.push_back({WarningKind::kLinesSkipped, w});
  }
  if (!one_log) {
    if (const std::string w = DescribeSkips(session.heading_log, step.headings.skipped);
        !w.empty()) {
      step.warnings.push_back({WarningKind::kLinesSkipped, w});
    }
  }

  std::vector<calib::PositionSample> positions;
  try {
    positions = calib::PositionSamples(step.gnss, session.min_fix_quality, result.frame,
                                       &step.used_fixes);
  } catch (const io::InputError& e) {
    throw io::InputError(io::Where(session.gnss_log, 0, e.what()));  // a fix outside the grid
  }
  step.fixes_used = static_cast<int64_t>(positions.size());
  {
    // A survey (or control point) far from where the vehicle drove is a survey mistake: say so
    // now rather than after a search for a wall that cannot be in the scans.
    std::vector<Eigen::Vector2d> track;
    track.reserve(positions.size());
    for (const calib::PositionSample& p : positions) track.push_back(p.p_local_m);
    CheckTrackNearWalls(track, result.walls, result.preset, session);
  }
  if (positions.size() < 2) {
    std::ostringstream found;
    for (const auto& [quality, count] : step.gnss.fixes_by_quality) {
      found << " quality " << quality << ": " << count << ";";
    }
    // Why the lines were not fixes, with the first line of each reason: the user can open the
    // log there (a missing checksum, a latitude of 91°, a misspelt sentence type).
    const std::string reasons = step.gnss.skipped.ListReasons(false, 6);
    throw io::InputError(io::Where(
        session.gnss_log, 0,
        "fewer than 2 GGA fixes of accepted quality (gnss.min_fix_quality " +
            std::to_string(session.min_fix_quality) + "); found" +
            (found.str().empty() ? std::string(" none") : found.str()) +
            (reasons.empty() ? std::string() : " (lines skipped: " + reasons + ")") +
            "; expected NMEA GGA sentences with checksums, e.g. $GNGGA,...*hh"));
  }
  const int64_t rejected = static_cast<int64_t>(step.gnss.fixes.size()) - step.fixes_used;
  if (rejected > 0) {
    step.warnings.push_back(
        {WarningKind::kFixesNotUsed,
         std::to_string(rejected) +
             " GGA fixes below gnss.min_fix_quality (or out of time order) not used"});
  }
  const std::vector<calib::YawSample> yaws = calib::YawSamples(
      step.headings, session.heading_reference, result.frame, step.used_fixes);
  step.headings_used = static_cast<int64_t>(yaws.size());
  if (yaws.size() < 2) {
    throw io::InputError(io::Where(session.heading_log, 0,
                                   "fewer than 2 usable HDT/THS headings; expected a heading log"));
  }
  step.poses = std::make_unique<calib::PoseInterpolator>(positions, yaws, options.alignment);
  // A moving scan carries one interpolated pose, so its σ is the sensors' white noise in full:
  // measured at the stops where they hold enough samples (RunCalibration uses it instead of
  // the configured fallbacks, which inflated the σ of sessions with drives when above the
  // receiver's).
  step.measured_noise = calib::MeasureWhiteNoise(positions, yaws, step.poses->dwells());
  if (options.solver.gnss_bias_tau_s > 0.0 &&
      options.alignment.segment_max_s > options.solver.gnss_bias_tau_s / 60.0) {
    // The solver holds the RTK error constant within a slice; over a long slice it wanders and
    // the σ is no longer honest (docs/method.md, "GNSS error").
    step.warnings.push_back(
        {WarningKind::kSliceTooLong,
        "alignment.segment_max_s = " + Format("%.2f", options.alignment.segment_max_s) +
        " s is long against the RTK error's correlation time (solver.gnss_bias_tau_s = " +
        Format("%.0f", options.solver.gnss_bias_tau_s) +
        " s): the error wanders within a slice and the σ may be too small; use at most " +
        Format("%.2f", options.solver.gnss_bias_tau_s / 240.0) + " s"});
  }
  if (!(step.poses->start_s() < step.poses->end_s())) {
    throw io::InputError(session.gnss_log + " and " + session.heading_log +
                         ": the GNSS and heading logs do not overlap in time");
  }
  step.num_dwells = static_cast<int>(step.poses->dwells().size());
  return step;
}

void UseMeasuredWhiteNoise(const PoseStep& poses, const solvers::SolverOptions& configured,
                           CalibrationResult* result) {
  result->measured_noise = poses.measured_noise;
  result->configured_gnss_white_sigma_m = configured.gnss_white_sigma_m;
  result->configured_heading_sigma_rad = configured.heading_sigma_rad;
  solvers::SolverOptions& solver = result->options.solver;
  solver.gnss_white_sigma_m = configured.gnss_white_sigma_m;
  solver.heading_sigma_rad = configured.heading_sigma_rad;
  if (!configured.use_measured_white_noise) return;
  const calib::MeasuredWhiteNoise& m = poses.measured_noise;
  if (m.gnss_white_sigma_m > 0.0) solver.gnss_white_sigma_m = m.gnss_white_sigma_m;
  if (m.heading_sigma_rad > 0.0) solver.heading_sigma_rad = m.heading_sigma_rad;
}

MovingScans ChooseMovingScans(const CalibrateOptions& options, int num_dwells) {
  MovingScans moving;
  // Moving scans: when asked for, or when the engineer drove continuously (too few dwells to
  // calibrate from stations alone). The solver then estimates the scanner clock offset too.
  moving.use_moving = options.alignment.use_moving_scans ||
                      (options.alignment.moving_scans_if_few_stations &&
                       num_dwells < options.solver.min_stations);
  // Stop-and-go: the drives between the stops too, kept if the clock offset is determined.
  moving.moving_by_default = !moving.use_moving && options.alignment.moving_scans_in_stop_and_go;
  moving.use_moving = moving.use_moving || moving.moving_by_default;
  return moving;
}

PassSetup PreparePasses(const CalibrateRequest& request, const CalibrationResult& result,
                        const calib::PoseInterpolator& poses) {
  PassSetup setup;
  const CalibrateOptions& options = result.options;
  calib::PassContext& pass = setup.pass;
  // A CARMEN log, or a recording's LaserScan topic checked against the preset.
  pass.open_scans = recording::MakeScanOpener(result.session, &result.preset);
  pass.scanner_time_offset_s = result.session.scanner_time_offset_s;
  pass.preset = &result.preset;
  pass.detector = &options.detector;
  pass.walls = &result.walls;
  pass.poses = &poses;
  // A preset that does not fit the scans (beams, step, range) misplaces every beam: refuse
  // before the detection passes, naming both, unless forced.
  const PresetFit fit = CheckPresetAgainstScans(pass.open_scans, result.preset);
  EnforcePresetFit(fit, result.preset, result.session, request.force, &setup.warnings);
  setup.scanner_from_data = fit.taken_from_data;
  pass.threads = options.solver.num_threads;
  const MovingScans moving = ChooseMovingScans(options, result.num_dwells);
  pass.use_moving = moving.use_moving;
  setup.moving_by_default = moving.moving_by_default;
  if (pass.use_moving && !options.alignment.use_moving_scans && !setup.moving_by_default) {
    setup.warnings.push_back({WarningKind::kMovingScansUsed, "only " + std::to_string(result.num_dwells) +
                               " stations (dwells) found: scans taken while moving are used, with "
                               "an estimated scanner clock offset (stop-and-go is more accurate)"});
  }
  return setup;
}

FirstPassStep FirstPass(const CalibrateRequest& request, const ProgressFn& progress,
                        const CalibrationResult& result, const RunInputs& inputs) {
  const io::SessionSpec& session = result.session;
  const CalibrateOptions& options = result.options;
  calib::PassRequest pass;
  if (session.mount_guess) {
    pass.mount = calib::Mount{session.mount_guess->x_m, session.mount_guess->y_m,
                              session.mount_guess->yaw_rad};
  }
  pass.gates = calib::Gates{options.detector.wide_angle_gate_rad,
                            options.detector.wide_offset_gate_m, false};
  pass.min_interval_s = (inputs.poses->end_s() - inputs.poses->start_s()) /
                        std::max(1, options.first_pass_max_scans);
  if (progress) {
    pass.progress = [&progress](int64_t done) {
      progress(Progress{Stage::kFirstPass, "first pass", done, 0, true});
    };
  }
  Say(progress, Stage::kFirstPass, "first pass: wall detection on a subsample with wide gates");
  const calib::PassOutcome first = calib::DetectionPass(inputs.pass, pass);
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
                 first.first_stamp_s, first.last_stamp_s, inputs.poses->start_s(),
                 inputs.poses->end_s())));
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
      why << "the wall was not detected in any of " << first.scans_examined
          << " sampled scans (";
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
  solvers::SolverOptions first_solver = options.solver;
  first_solver.max_sigma_xy_m = 1e3;  // finite: the check scales the information by them
  first_solver.max_sigma_yaw_rad = 1e3;
  const solvers::MountEstimate start = solvers::SolveMountBarawid(
      first.observations, result.walls, first_solver, request.force);
  if (!start.usable) {
    return StopAfterFirstPass(start, first);
  }
  const solvers::MountEstimate refined = solvers::SolveMountCeres(
      first.observations, result.walls, first_solver, start.mount, request.force);
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

SecondPassStep SecondPass(const CalibrateRequest& request, const ProgressFn& progress,
                          const CalibrationResult& result, const RunInputs& inputs) {
  SecondPassStep step;
  const io::SessionSpec& session = result.session;
  calib::PassRequest pass;
  pass.mount = result.first_pass.mount;
  pass.gates = TightGates(result);
  pass.gate_time_offset_s =
      result.first_pass.time_offset_estimated ? result.first_pass.time_offset_s : 0.0;
  Say(progress, Stage::kSecondPass, "second pass: wall detection in every scan with tight gates");
  calib::PassOutcome second;
  if (progress) {
    // The total is known from the first pass: every scan is read again.
    const int64_t total = inputs.scans_in_log;
    pass.progress = [&progress, total](int64_t done) {
      progress(Progress{Stage::kSecondPass, "second pass", done, total, true});
    };
  }
  calib::ScanLogTally tally;
  if (request.preview) pass.tally = &tally;  // inspect's scan-log summary
  second = calib::DetectionPass(inputs.pass, pass);
  if (request.preview) step.scan_log = std::move(tally);
  if (progress) {
    // The pass reports every 2000 scans: the last count is said here.
    progress(Progress{Stage::kSecondPass, "second pass", second.scans_read,
                      std::max(inputs.scans_in_log, second.scans_read), true});
  }
  step.observations = std::move(second.observations);
  // The vector grew by doubling: up to half of it is spare capacity, held through the solve.
  step.observations.shrink_to_fit();
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
                                 result.preset.name + " has " +
                                 std::to_string(result.preset.num_beams) +
                                 ": check scanner.model"});
  }
  return step;
}

Warning DrivesNotUsedWarning(int64_t scans) {
  return {WarningKind::kDrivesNotUsed,
          std::to_string(scans) +
              " scans taken while driving were not used: the timing their poses need (scanner "
              "clock offset, heading delay) was not determined (σ above "
              "alignment.moving_max_time_offset_sigma_s)"};
}

SolveStep Solve(const CalibrateRequest& request, const ProgressFn& progress,
                const CalibrationResult& result, const RunInputs& inputs,
                std::vector<calib::WallObservation> observations) {
  SolveStep step;
  std::vector<calib::WallObservation>& obs = step.observations;
  obs = std::move(observations);
  Say(progress, Stage::kSolving,
      std::string("solving (") + solvers::MethodName(request.method) + ") on " +
          std::to_string(obs.size()) + " observations");
  const auto on_round = [&progress](double shift_s) {
    Say(progress, Stage::kClockOffsetRound,
        "clock offset " + Format("%.4f", shift_s) +
            " s so far: poses (and headings by the heading delay) interpolated at the shifted "
            "scan times, solving again");
  };
  // Drops the observations of moving scans; returns how many scans that was.
  const auto drop_moving = [&obs]() {
    const auto moving = std::stable_partition(
        obs.begin(), obs.end(), [](const calib::WallObservation& o) { return o.pose.stationary; });
    std::vector<int> scans;
    scans.reserve(static_cast<size_t>(obs.end() - moving));
    for (auto it = moving; it != obs.end(); ++it) scans.push_back(it->scan_index);
    obs.erase(moving, obs.end());
    return CountDistinct(&scans);
  };
  const solvers::SolverOptions& solver = result.options.solver;
  const auto solve = [&]() {
    return solvers::SolveWithPolicy(request.method, &obs, result.walls, solver,
                                    result.first_pass.mount, request.force, *inputs.poses,
                                    on_round, inputs.observation_weight);
  };
  // Moving scans by default only where their clock offset is estimated: not for barawid.
  int64_t moving_dropped = 0;
  if (inputs.moving_by_default && request.method != solvers::Method::kCeres) {
    moving_dropped = drop_moving();
  }
  solvers::PolicyOutcome outcome = solve();
  int64_t unshift_dropped = 0;  // observations without a pose at their own stamp
  const double max_offset_sigma_s = result.options.alignment.moving_max_time_offset_sigma_s;
  if (inputs.moving_by_default && moving_dropped == 0 &&
      !(outcome.estimate.time_offset_estimated &&
        solvers::DrivesTimingSigma(obs, result.walls, outcome.estimate.mount,
                                   outcome.estimate.time_covariance) <= max_offset_sigma_s)) {
    // The timing the drives' poses need (the clock offset when driving towards a wall, the
    // clock offset plus the heading delay when turning in front of it) is not determined: their
    // scans would misplace the wall by speed × offset. Standing scans alone, back at the poses
    // of their own stamps (the clock rounds moved every observation by the same shift).
    if (!obs.empty() && (obs.front().pose.clock_shift_s != 0.0 ||
                         obs.front().pose.heading_shift_s != 0.0)) {
      unshift_dropped = calib::ShiftObservations(
          *inputs.poses, -obs.front().pose.clock_shift_s, -obs.front().pose.heading_shift_s, &obs);
    }
    moving_dropped = drop_moving();
    if (moving_dropped > 0) {
      step.drives_dropped = moving_dropped;
      // A preview's count is of its thinned set: the warning waits for the whole set.
      if (!request.preview) step.warnings.push_back(DrivesNotUsedWarning(moving_dropped));
      outcome = solve();
    }
  }
  if (moving_dropped > 0) step.scans_skipped[calib::ScanSkip::kVehicleMoving] += moving_dropped;
  if (outcome.dropped_at_shifted_time + unshift_dropped > 0) {
    step.scans_skipped[calib::ScanSkip::kNoPoseAtShiftedTime] +=
        outcome.dropped_at_shifted_time + unshift_dropped;
  }
  step.estimate = std::move(outcome.estimate);
  const solvers::MountEstimate& estimate = step.estimate;
  step.forced = estimate.usable && estimate.forced;
  for (const std::string& w : estimate.warnings) {
    step.warnings.push_back({WarningKind::kForcedObservability, w});
  }
  if (estimate.time_offset_estimated) {
    step.time_offset_s = estimate.time_offset_s;
    step.time_offset_sigma_s = estimate.time_offset_sigma_s;
    step.drives_timing_sigma_s =
        solvers::DrivesTimingSigma(obs, result.walls, estimate.mount, estimate.time_covariance);
  }
  const double clock_prior_s = solver.time_offset_sigma_s;
  const double heading_prior_s =
      estimate.heading_delay_estimated ? estimate.heading_delay_prior_sigma_s : 0.0;
  const auto determined = [&](int index) {
    return solvers::DelayDetermined(estimate.time_covariance, clock_prior_s, heading_prior_s, index);
  };
  step.scanner_offset =
      ClassifyDelay(estimate.time_offset_estimated, estimate.time_offset_s,
                    estimate.time_offset_sigma_s, clock_prior_s, determined(0));
  step.heading_delay =
      ClassifyDelay(estimate.heading_delay_estimated, estimate.heading_delay_s,
                    estimate.heading_delay_sigma_s, heading_prior_s, determined(1));
  return step;
}

AnalysisStep Analyse(const CalibrateRequest& request, const ProgressFn& progress,
                     const CalibrationResult& result) {
  AnalysisStep step;
  const solvers::MountEstimate& estimate = result.estimate;
  if (!estimate.usable) return step;
  Say(progress, Stage::kResidualAnalysis, "residual analysis");
  step.residual_analysis =
      analysis::AnalyseResiduals(result.observations, result.walls, estimate, result.preset);
  for (const std::string& flag : step.residual_analysis.flags) {
    step.warnings.push_back({WarningKind::kResiduals, "residuals: " + flag});
  }
  const solvers::SolverOptions& solver = result.options.solver;
  if (request.method == solvers::Method::kCeres && solver.bootstrap_samples >= 0 &&
      !request.preview) {
    Say(progress, Stage::kRepeatability,
        "repeatability: split halves and " + std::to_string(solver.bootstrap_samples) +
            " bootstrap resamples of the stations");
    step.repeatability = analysis::AssessRepeatability(
        result.observations, result.walls, solver, estimate.mount, solver.bootstrap_samples,
        2007, estimate.time_offset_estimated ? &estimate.time_block_s : nullptr,
        estimate.solution_state.get());
  }
  return step;
}

Coverage CountCoverage(const CalibrationResult& result) {
  Coverage coverage;
  std::vector<int> used_scans, used_segments, moving_scans;
  std::vector<double> grid_headings, wall_angles;
  const size_t n = result.observations.size();
  used_scans.reserve(n);
  used_segments.reserve(n);
  grid_headings.reserve(n);
  wall_angles.reserve(n);
  for (const calib::WallObservation& o : result.observations) {
    used_scans.push_back(o.scan_index);
    if (!o.pose.stationary) moving_scans.push_back(o.scan_index);
    used_segments.push_back(calib::GnssSegment(o));
    grid_headings.push_back(HeadingFromYaw(o.pose.yaw_rad));
    const calib::WallGeometry& wall = result.walls[o.wall_index];
    // φ of Barawid 2007, Eq. 8: the wall normal (towards the wall) in the vehicle frame.
    const double side =
        (wall.offset_m - wall.normal_local.dot(o.pose.antenna_local_m)) >= 0 ? 1 : -1;
    wall_angles.push_back(WrapAngle(
        std::atan2(side * wall.normal_local.y(), side * wall.normal_local.x()) - o.pose.yaw_rad));
  }
  coverage.scans_used = CountDistinct(&used_scans);
  coverage.scans_used_moving = CountDistinct(&moving_scans);
  coverage.num_segments_used = static_cast<int>(CountDistinct(&used_segments));
  const CircularExtent headings = CircularExtentOf(grid_headings);
  const CircularExtent angles = CircularExtentOf(wall_angles);
  if (!headings.empty) {
    coverage.heading_min_deg = WrapTwoPi(headings.min_rad) * kRadToDeg;
    coverage.heading_max_deg = WrapTwoPi(headings.max_rad) * kRadToDeg;
  }
  if (!angles.empty) {
    coverage.wall_angle_min_deg = WrapAngle(angles.min_rad) * kRadToDeg;
    coverage.wall_angle_max_deg = WrapAngle(angles.max_rad) * kRadToDeg;
  }
  return coverage;
}

}  // namespace wallcal::pipeline
