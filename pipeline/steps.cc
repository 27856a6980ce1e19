// The steps of a calibration run (pipeline/steps.h).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <thread>

#include "calib/geodesy.h"
#include "calib/gnss_epoch_time.h"
#include "calib/pose_samples.h"
#include "common/angles.h"
#include "common/circular.h"
#include "common/format.h"
#include "io/text/carmen_reader.h"
#include "io/text/nmea_reader.h"
#include "io/recording/recording_streams.h"
#include "io/config/session_reader.h"
#include "io/survey/survey_reader.h"
#include "io/config/offsets_reader.h"
#include "pipeline/checks.h"
#include "pipeline/config_dirs.h"
#include "pipeline/stream_delays.h"
#include "pipeline/steps.h"
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
  std::ostringstream out;
  out << FileName(file) << ": " << skips.Problems() << " lines skipped (";
  bool first = true;
  for (const auto& [reason, count] : skips.by_reason) {
    if (skips.IsInformational(reason)) continue;
    out << (first ? "" : "; ") << reason << ": " << count;
    first = false;
    const auto line = skips.first_line.find(reason);
    if (line != skips.first_line.end() && line->second > 0) out << ", first at line " << line->second;
  }
  out << ")";
  return out.str();
}

// Stops the run after the first pass: the estimate says why.
void StopAfterFirstPass(const solvers::MountEstimate& estimate, const calib::PassOutcome& pass,
                        CalibrationResult* result) {
  result->first_pass = estimate;
  result->estimate = estimate;
  result->scans_total = pass.scans_read + pass.line_skips.Problems();
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

void LoadSessionAndOptions(const CalibrateRequest& request, CalibrationResult* result,
                           RunInputs* inputs) {
  result->session = io::ReadSession(request.session_path);
  if (!request.config_path.empty()) result->options = pipeline::ReadCalibrateOptions(request.config_path);
  result->options.Validate();
  result->options.solver.num_threads =
      request.threads > 0 ? request.threads
                          : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  // A measured preset beside the session (characterise writes <session>/scanners/NAME.yaml)
  // is found first, then the shipped ones (config_dirs.h).
  result->preset = LoadSessionPreset(result->session.scanner_model, result->session.dir);
  // The previous calibration is read now: a bad --compare file fails before the work.
  if (!request.compare_path.empty()) inputs->previous = io::ReadPreviousOffsets(request.compare_path);
}

void TieSurveyAndFitWalls(CalibrationResult* result, RunInputs* inputs, bool swap_survey_axes) {
  const io::SessionSpec& session = result->session;
  const solvers::SolverOptions& solver = result->options.solver;
  // Points measured more than once (both faces, two set-ups) are averaged (io/survey_reader.h).
  const io::SurveyCombination combined = io::CombineSurveyObservations(
      io::ReadSurvey(session.survey_points, session.survey_columns));
  inputs->survey = combined.points;
  if (swap_survey_axes) {
    for (io::SurveyPoint& p : inputs->survey) std::swap(p.x_m, p.y_m);
  }
  for (const std::string& w : combined.warnings) result->warnings.push_back(w);
  const io::ControlPoint& first_control = session.control.front();
  try {
    result->frame =
        calib::MakeLocalFrame(first_control.lat_deg, first_control.lon_deg, session.utm_zone);
  } catch (const io::InputError& e) {
    // The frame comes from session.yaml's first control point and utm_zone: name the line.
    throw io::InputError(io::Where(session.file, first_control.line,
                                   std::string("survey.control[0] / utm_zone: ") + e.what()));
  }
  // Before the tie: a mirrored survey would fail it with a message about one control point.
  CheckSurveyNotMirrored(inputs->survey, session, result->frame);
  inputs->tie =
      calib::TieSurvey(inputs->survey, session.survey_points, session, result->frame, solver.survey());
  result->control_rms_m = inputs->tie.control_rms_m;
  result->num_control = inputs->tie.num_control;
  result->walls =
      calib::FitWalls(inputs->survey, session.survey_points, session, inputs->tie, solver.survey());
  if (inputs->tie.num_control >= 2 &&
      inputs->tie.control_rms_m >
          3.0 * std::hypot(solver.control_sigma_m, solver.total_station_sigma_m)) {
    result->warnings.push_back("control points fit the survey with RMS " +
                               Format("%.3f", inputs->tie.control_rms_m) +
                               " m, more than 3x the expected RTK + total-station error");
  }
}

void ReadPoses(CalibrationResult* result, RunInputs* inputs) {
  const io::SessionSpec& session = result->session;
  const pipeline::CalibrateOptions& options = result->options;
  const bool one_log = session.heading_log == session.gnss_log;
  // Text logs or recording topics (one pass when GNSS and heading share a recording).
  io::PoseLogs logs = io::ReadPoseLogs(session);
  inputs->gnss = std::move(logs.gnss);
  inputs->headings = std::move(logs.headings);
  for (std::string& w : logs.warnings) result->warnings.push_back(std::move(w));
  // Each GGA at its epoch on the logger clock, not at its jittered arrival (docs/time-alignment.md).
  result->gnss_epochs =
      calib::MapGnssEpochs(&inputs->gnss.fixes, options.alignment.gnss_epoch_time);
  if (result->gnss_epochs.status == calib::EpochMappingStatus::kInconsistent ||
      result->gnss_epochs.status == calib::EpochMappingStatus::kTooFew) {
    result->warnings.push_back(
        "GNSS epoch time " + std::string(calib::EpochMappingStatusName(result->gnss_epochs.status)) +
        ": logger stamp − UTC over " + std::to_string(result->gnss_epochs.fixes) +
        " fixes has scatter " + Format("%.1f", 1000.0 * result->gnss_epochs.jitter_s) +
        " ms, drift " + Format("%.0f", 1e6 * result->gnss_epochs.drift) + " ppm, " +
        std::to_string(result->gnss_epochs.outliers) +
        " outliers; the fixes keep their arrival stamps");
  }
  result->fixes_by_quality = inputs->gnss.fixes_by_quality;
  result->gnss_skipped = inputs->gnss.skipped;
  result->heading_skipped = inputs->headings.skipped;
  if (const std::string w = DescribeSkips(session.gnss_log, inputs->gnss.skipped); !w.empty()) {
    result->warnings.push_back(w);
  }
  if (!one_log) {
    if (const std::string w = DescribeSkips(session.heading_log, inputs->headings.skipped);
        !w.empty()) {
      result->warnings.push_back(w);
    }
  }

  std::vector<calib::PositionSample> positions;
  try {
    positions = calib::PositionSamples(inputs->gnss, session.min_fix_quality, result->frame,
                                       &inputs->used_fixes);
  } catch (const io::InputError& e) {
    throw io::InputError(io::Where(session.gnss_log, 0, e.what()));  // a fix outside the grid
  }
  result->fixes_used = static_cast<int64_t>(positions.size());
  {
    // A survey (or control point) far from where the vehicle drove is a survey mistake: say so
    // now rather than after a search for a wall that cannot be in the scans.
    std::vector<Eigen::Vector2d> track;
    track.reserve(positions.size());
    for (const calib::PositionSample& p : positions) track.push_back(p.p_local_m);
    CheckTrackNearWalls(track, result->walls, result->preset, session);
  }
  if (positions.size() < 2) {
    std::ostringstream found;
    for (const auto& [quality, count] : inputs->gnss.fixes_by_quality) {
      found << " quality " << quality << ": " << count << ";";
    }
    // Why the lines were not fixes, with the first line of each reason: the user can open the
    // log there (a missing checksum, a latitude of 91°, a misspelt sentence type).
    std::ostringstream reasons;
    int shown = 0;
    for (const auto& [reason, count] : inputs->gnss.skipped.by_reason) {
      if (shown++ == 6) {
        reasons << "; ...";
        break;
      }
      reasons << (shown > 1 ? "; " : "") << reason << ": " << count;
      const auto line = inputs->gnss.skipped.first_line.find(reason);
      if (line != inputs->gnss.skipped.first_line.end() && line->second > 0) {
        reasons << ", first at line " << line->second;
      }
    }
    throw io::InputError(io::Where(
        session.gnss_log, 0,
        "fewer than 2 GGA fixes of accepted quality (gnss.min_fix_quality " +
            std::to_string(session.min_fix_quality) + "); found" +
            (found.str().empty() ? std::string(" none") : found.str()) +
            (shown > 0 ? " (lines skipped: " + reasons.str() + ")" : std::string()) +
            "; expected NMEA GGA sentences with checksums, e.g. $GNGGA,...*hh"));
  }
  const int64_t rejected = static_cast<int64_t>(inputs->gnss.fixes.size()) - result->fixes_used;
  if (rejected > 0) {
    result->warnings.push_back(std::to_string(rejected) +
                               " GGA fixes below gnss.min_fix_quality (or out of time order) not used");
  }
  const std::vector<calib::YawSample> yaws = calib::YawSamples(
      inputs->headings, session.heading_reference, result->frame, inputs->used_fixes);
  result->headings_used = static_cast<int64_t>(yaws.size());
  if (yaws.size() < 2) {
    throw io::InputError(io::Where(session.heading_log, 0,
                                   "fewer than 2 usable HDT/THS headings; expected a heading log"));
  }
  inputs->poses = std::make_unique<calib::PoseInterpolator>(positions, yaws, options.alignment);
  if (options.solver.gnss_bias_tau_s > 0.0 &&
      options.alignment.segment_max_s > options.solver.gnss_bias_tau_s / 60.0) {
    // The solver holds the RTK error constant within a slice; over a long slice it wanders and
    // the σ is no longer honest (docs/method.md, "GNSS error").
    result->warnings.push_back(
        "alignment.segment_max_s = " + Format("%.2f", options.alignment.segment_max_s) +
        " s is long against the RTK error's correlation time (solver.gnss_bias_tau_s = " +
        Format("%.0f", options.solver.gnss_bias_tau_s) +
        " s): the error wanders within a slice and the σ may be too small; use at most " +
        Format("%.2f", options.solver.gnss_bias_tau_s / 240.0) + " s");
  }
  if (!(inputs->poses->start_s() < inputs->poses->end_s())) {
    throw io::InputError(session.gnss_log + " and " + session.heading_log +
                         ": the GNSS and heading logs do not overlap in time");
  }
  result->num_dwells = static_cast<int>(inputs->poses->dwells().size());
}

void PreparePasses(const CalibrateRequest& request, CalibrationResult* result, RunInputs* inputs) {
  const pipeline::CalibrateOptions& options = result->options;
  calib::PassContext& pass = inputs->pass;
  // A CARMEN log, or a recording's LaserScan topic checked against the preset.
  pass.open_scans = io::MakeScanOpener(result->session, &result->preset);
  pass.scanner_time_offset_s = result->session.scanner_time_offset_s;
  pass.preset = &result->preset;
  pass.detector = &options.detector;
  pass.walls = &result->walls;
  pass.poses = inputs->poses.get();
  // A preset that does not fit the scans (beams, step, range) misplaces every beam: refuse
  // before the detection passes, naming both, unless forced.
  const PresetFit fit = CheckPresetAgainstScans(pass.open_scans, result->preset);
  EnforcePresetFit(fit, result->preset, result->session, request.force, &result->warnings);
  result->scanner_from_data = fit.taken_from_data;
  pass.threads = options.solver.num_threads;
  // Moving scans: when asked for, or when the engineer drove continuously (too few dwells to
  // calibrate from stations alone). The solver then estimates the scanner clock offset too.
  pass.use_moving = options.alignment.use_moving_scans ||
                    (options.alignment.moving_scans_if_few_stations &&
                     result->num_dwells < options.solver.min_stations);
  // Stop-and-go: the drives between the stops too, kept if the clock offset is determined.
  inputs->moving_by_default = !pass.use_moving && options.alignment.moving_scans_in_stop_and_go;
  pass.use_moving = pass.use_moving || inputs->moving_by_default;
  if (pass.use_moving && !options.alignment.use_moving_scans && !inputs->moving_by_default) {
    result->warnings.push_back("only " + std::to_string(result->num_dwells) +
                               " stations (dwells) found: scans taken while moving are used, with "
                               "an estimated scanner clock offset (stop-and-go is more accurate)");
  }
}

bool FirstPass(const CalibrateRequest& request, const ProgressFn& progress,
               CalibrationResult* result, RunInputs* inputs) {
  const io::SessionSpec& session = result->session;
  const pipeline::CalibrateOptions& options = result->options;
  calib::PassRequest pass;
  if (session.mount_guess) {
    pass.mount = calib::Mount{session.mount_guess->x_m, session.mount_guess->y_m,
                              session.mount_guess->yaw_rad};
  }
  pass.gates = calib::Gates{options.detector.wide_angle_gate_rad,
                            options.detector.wide_offset_gate_m, false};
  pass.min_interval_s = (inputs->poses->end_s() - inputs->poses->start_s()) /
                        std::max(1, options.first_pass_max_scans);
  if (progress) {
    pass.progress = [&progress](int64_t done) {
      progress(Progress{Stage::kFirstPass, "first pass", done, 0, true});
    };
  }
  Say(progress, Stage::kFirstPass, "first pass: wall detection on a subsample with wide gates");
  const calib::PassOutcome first = calib::DetectionPass(inputs->pass, pass);
  if (first.scans_read == 0) {
    std::string why = "no scan records";
    if (const std::string w = DescribeSkips(session.scanner_log, first.line_skips); !w.empty()) {
      why += "; " + w;
    }
    throw io::InputError(io::Where(session.scanner_log, 0,
                                   why + "; expected CARMEN RAWLASER1/ROBOTLASER1/FLASER lines"));
  }
  inputs->scans_in_log = first.scans_read;
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
                 first.first_stamp_s, first.last_stamp_s, inputs->poses->start_s(),
                 inputs->poses->end_s())));
    }
    std::ostringstream why;
    why << "the wall was not detected in any of " << first.scans_examined << " sampled scans (";
    bool first_reason = true;
    for (const auto& [reason, count] : first.skipped) {
      why << (first_reason ? "" : "; ") << calib::ScanSkipName(reason) << ": " << count;
      first_reason = false;
    }
    why << "); check the walls' survey codes, the scanner model, the time overlap of the logs, "
           "or give scanner.mount_guess";
    solvers::MountEstimate none;
    none.failure = solvers::EstimateFailure::kWallNotDetected;
    none.message = why.str();
    StopAfterFirstPass(none, first, result);
    return false;
  }
  // The first pass only starts the second: the σ limits (a refusal of the final estimate, with
  // every scan counted) do not apply to it.
  solvers::SolverOptions first_solver = options.solver;
  first_solver.max_sigma_xy_m = 1e3;  // finite: the check scales the information by them
  first_solver.max_sigma_yaw_rad = 1e3;
  const solvers::MountEstimate start = solvers::SolveMountBarawid(
      first.observations, result->walls, first_solver, request.force);
  if (!start.usable) {
    StopAfterFirstPass(start, first, result);
    return false;
  }
  const solvers::MountEstimate refined = solvers::SolveMountCeres(
      first.observations, result->walls, first_solver, start.mount, request.force);
  if (!refined.usable) {
    StopAfterFirstPass(refined, first, result);
    return false;
  }
  result->first_pass = refined;
  Say(progress, Stage::kFirstPass,
      "first pass: " + std::to_string(first.observations.size()) + " observations, mount x " +
          Format("%.3f", refined.mount.x_m) + " m, y " + Format("%.3f", refined.mount.y_m) +
          " m, yaw " + Format("%.2f", refined.mount.yaw_rad * kRadToDeg) + " deg");
  return true;
}

void SecondPass(const CalibrateRequest& request, const ProgressFn& progress,
                CalibrationResult* result, RunInputs* inputs) {
  const io::SessionSpec& session = result->session;
  calib::PassRequest pass;
  pass.mount = result->first_pass.mount;
  pass.gates = TightGates(*result);
  pass.gate_time_offset_s =
      result->first_pass.time_offset_estimated ? result->first_pass.time_offset_s : 0.0;
  Say(progress, Stage::kSecondPass, "second pass: wall detection in every scan with tight gates");
  calib::PassOutcome second;
  if (progress) {
    // The total is known from the first pass: every scan is read again.
    const int64_t total = inputs->scans_in_log;
    pass.progress = [&progress, total](int64_t done) {
      progress(Progress{Stage::kSecondPass, "second pass", done, total, true});
    };
  }
  calib::ScanLogTally tally;
  if (request.preview) pass.tally = &tally;  // inspect's scan-log summary
  second = calib::DetectionPass(inputs->pass, pass);
  if (request.preview) result->scan_log = std::move(tally);
  if (progress) {
    // The pass reports every 2000 scans: the last count is said here.
    progress(Progress{Stage::kSecondPass, "second pass", second.scans_read,
                      std::max(inputs->scans_in_log, second.scans_read), true});
  }
  result->observations = std::move(second.observations);
  // The vector grew by doubling: up to half of it is spare capacity, held through the solve.
  result->observations.shrink_to_fit();
  result->scans_skipped = second.skipped;
  result->scan_lines_skipped = second.line_skips;
  result->scans_total = second.scans_read + second.line_skips.Problems();
  if (const std::string w = DescribeSkips(session.scanner_log, second.line_skips); !w.empty()) {
    result->warnings.push_back(w);
    result->scans_skipped[calib::ScanSkip::kMalformedLine] += second.line_skips.Problems();
  }
  if (second.not_increasing > 0) {
    result->warnings.push_back(FileName(session.scanner_log) + ": " +
                               std::to_string(second.not_increasing) +
                               " scans not later than the scan before them (first at line " +
                               std::to_string(second.first_not_increasing_line) +
                               "); each was used at its own time");
  }
  if (second.beam_count_mismatch > 0) {
    result->warnings.push_back(std::to_string(second.beam_count_mismatch) + " scans have " +
                               std::to_string(second.first_mismatch_beams) + " beams, preset " +
                               result->preset.name + " has " +
                               std::to_string(result->preset.num_beams) + ": check scanner.model");
  }
}

std::string DrivesNotUsedWarning(int64_t scans) {
  return std::to_string(scans) +
         " scans taken while driving were not used: the timing their poses need (scanner clock "
         "offset, heading delay) was not determined (σ above "
         "alignment.moving_max_time_offset_sigma_s)";
}

void Solve(const CalibrateRequest& request, const ProgressFn& progress,
           CalibrationResult* result, RunInputs* inputs) {
  Say(progress, Stage::kSolving,
      std::string("solving (") + solvers::MethodName(request.method) + ") on " +
          std::to_string(result->observations.size()) + " observations");
  const auto on_round = [&progress](double shift_s) {
    Say(progress, Stage::kClockOffsetRound,
        "clock offset " + Format("%.4f", shift_s) +
            " s so far: poses (and headings by the heading delay) interpolated at the shifted "
            "scan times, solving again");
  };
  // Drops the observations of moving scans; returns how many scans that was.
  const auto drop_moving = [result]() {
    auto& obs = result->observations;
    const auto moving = std::stable_partition(
        obs.begin(), obs.end(), [](const calib::WallObservation& o) { return o.pose.stationary; });
    std::set<int> scans;
    for (auto it = moving; it != obs.end(); ++it) scans.insert(it->scan_index);
    obs.erase(moving, obs.end());
    return static_cast<int64_t>(scans.size());
  };
  // Moving scans by default only where their clock offset is estimated: not for barawid.
  int64_t moving_dropped = 0;
  if (inputs->moving_by_default && request.method != solvers::Method::kCeres) {
    moving_dropped = drop_moving();
  }
  solvers::PolicyOutcome outcome = solvers::SolveWithPolicy(
      request.method, &result->observations, result->walls, result->options.solver,
      result->first_pass.mount, request.force, *inputs->poses, on_round,
      inputs->observation_weight);
  const double max_offset_sigma_s = result->options.alignment.moving_max_time_offset_sigma_s;
  if (inputs->moving_by_default && moving_dropped == 0 &&
      !(outcome.estimate.time_offset_estimated &&
        solvers::DrivesTimingSigma(result->observations, result->walls, outcome.estimate.mount,
                                   outcome.estimate.time_covariance) <= max_offset_sigma_s)) {
    // The timing the drives' poses need (the clock offset when driving towards a wall, the
    // clock offset plus the heading delay when turning in front of it) is not determined: their
    // scans would misplace the wall by speed × offset. Standing scans alone, from the poses at their stamps.
    // Back to the poses at the scans' own stamps first (the policy moved them by the offset).
    if (outcome.estimate.time_offset_s != 0.0) {
      for (calib::WallObservation& o : result->observations) {
        calib::VehiclePose pose;
        if (inputs->poses->At(o.pose.stamp_s - outcome.estimate.time_offset_s, &pose) ==
            calib::PoseStatus::kOk) {
          o.pose = pose;
        }
      }
    }
    moving_dropped = drop_moving();
    if (moving_dropped > 0) {
      inputs->drives_dropped = moving_dropped;
      // A preview's count is of its thinned set: the warning waits for the whole set.
      if (!request.preview) result->warnings.push_back(DrivesNotUsedWarning(moving_dropped));
      outcome = solvers::SolveWithPolicy(request.method, &result->observations, result->walls,
                                         result->options.solver, result->first_pass.mount,
                                         request.force, *inputs->poses, on_round,
                                         inputs->observation_weight);
    }
  }
  if (moving_dropped > 0) result->scans_skipped[calib::ScanSkip::kVehicleMoving] += moving_dropped;
  result->estimate = outcome.estimate;
  if (outcome.dropped_at_shifted_time > 0) {
    result->scans_skipped[calib::ScanSkip::kNoPoseAtShiftedTime] += outcome.dropped_at_shifted_time;
  }
  const solvers::MountEstimate& estimate = result->estimate;
  result->forced = estimate.usable && estimate.forced;
  for (const std::string& w : estimate.warnings) result->warnings.push_back(w);
  if (estimate.time_offset_estimated) {
    result->time_offset_s = estimate.time_offset_s;
    result->time_offset_sigma_s = estimate.time_offset_sigma_s;
    result->drives_timing_sigma_s = solvers::DrivesTimingSigma(
        result->observations, result->walls, estimate.mount, estimate.time_covariance);
  }
  const double clock_prior_s = result->options.solver.time_offset_sigma_s;
  const double heading_prior_s =
      estimate.heading_delay_estimated ? estimate.heading_delay_prior_sigma_s : 0.0;
  const auto determined = [&](int index) {
    return solvers::DelayDetermined(estimate.time_covariance, clock_prior_s, heading_prior_s, index);
  };
  result->scanner_offset =
      ClassifyDelay(estimate.time_offset_estimated, estimate.time_offset_s,
                    estimate.time_offset_sigma_s, clock_prior_s, determined(0));
  result->heading_delay =
      ClassifyDelay(estimate.heading_delay_estimated, estimate.heading_delay_s,
                    estimate.heading_delay_sigma_s, heading_prior_s, determined(1));
}

void Analyse(const CalibrateRequest& request, const ProgressFn& progress,
             CalibrationResult* result) {
  const solvers::MountEstimate& estimate = result->estimate;
  if (!estimate.usable) return;
  Say(progress, Stage::kResidualAnalysis, "residual analysis");
  result->residual_analysis = analysis::AnalyseResiduals(result->observations, result->walls,
                                                         estimate, result->preset);
  for (const std::string& flag : result->residual_analysis.flags) {
    result->warnings.push_back("residuals: " + flag);
  }
  const solvers::SolverOptions& solver = result->options.solver;
  if (request.method == solvers::Method::kCeres && solver.bootstrap_samples >= 0 &&
      !request.preview) {
    Say(progress, Stage::kRepeatability,
        "repeatability: split halves and " + std::to_string(solver.bootstrap_samples) +
            " bootstrap resamples of the stations");
    result->repeatability = analysis::AssessRepeatability(
        result->observations, result->walls, solver, estimate.mount, solver.bootstrap_samples,
        2007, estimate.time_offset_estimated ? &estimate.time_block_s : nullptr,
        estimate.solution_state.get());
  }
}

void CountCoverage(CalibrationResult* result) {
  std::set<int> used_scans, used_segments, moving_scans;
  std::vector<double> grid_headings, wall_angles;
  for (const calib::WallObservation& o : result->observations) {
    used_scans.insert(o.scan_index);
    if (!o.pose.stationary) moving_scans.insert(o.scan_index);
    used_segments.insert(calib::GnssSegment(o));
    grid_headings.push_back(kPi / 2.0 - o.pose.yaw_rad);
    const calib::WallGeometry& wall = result->walls[o.wall_index];
    // φ of Barawid 2007, Eq. 8: the wall normal (towards the wall) in the vehicle frame.
    const double side =
        (wall.offset_m - wall.normal_local.dot(o.pose.antenna_local_m)) >= 0 ? 1 : -1;
    wall_angles.push_back(WrapAngle(
        std::atan2(side * wall.normal_local.y(), side * wall.normal_local.x()) - o.pose.yaw_rad));
  }
  result->scans_used = static_cast<int64_t>(used_scans.size());
  result->scans_used_moving = static_cast<int64_t>(moving_scans.size());
  result->num_segments_used = static_cast<int>(used_segments.size());
  const CircularExtent headings = CircularExtentOf(grid_headings);
  const CircularExtent angles = CircularExtentOf(wall_angles);
  if (!headings.empty) {
    result->heading_min_deg = WrapTwoPi(headings.min_rad) * kRadToDeg;
    result->heading_max_deg = WrapTwoPi(headings.max_rad) * kRadToDeg;
  }
  if (!angles.empty) {
    result->wall_angle_min_deg = WrapAngle(angles.min_rad) * kRadToDeg;
    result->wall_angle_max_deg = WrapAngle(angles.max_rad) * kRadToDeg;
  }
}

}  // namespace wallcal::pipeline
