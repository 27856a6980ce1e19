// SPDX-License-Identifier: Apache-2.0
// The poses step of a calibration run (pipeline/internal/steps.h): the GNSS fixes and headings
// as a pose interpolator with its dwells, and the white noise the solve takes.

#include <sstream>
#include <utility>

#include "calib/gnss_epoch_time.h"
#include "calib/pose_samples.h"
#include "common/format.h"
#include "pipeline/checks.h"
#include "pipeline/internal/steps.h"

namespace wallcal::pipeline {

// The stops first: the scatter of a standing vehicle's samples needs no model of its motion.
// Calibrate and the guide take the same, so the guide's σ is calibrate's on the same data.
WhiteNoiseInUse ChooseWhiteNoise(const solvers::SolverOptions& configured,
                                 const calib::MeasuredWhiteNoise& at_stops,
                                 const calib::DriveWhiteNoise& on_drives) {
  WhiteNoiseInUse noise;
  noise.gnss_white_sigma_m = configured.gnss_white_sigma_m;
  noise.heading_sigma_rad = configured.heading_sigma_rad;
  if (!configured.use_measured_white_noise) return noise;
  if (at_stops.gnss_white_sigma_m > 0.0) {
    noise.gnss_white_sigma_m = at_stops.gnss_white_sigma_m;
    noise.gnss_source = NoiseSource::kMeasuredAtStops;
  } else if (on_drives.gnss_white_sigma_m > 0.0) {
    noise.gnss_white_sigma_m = on_drives.gnss_white_sigma_m;
    noise.gnss_source = NoiseSource::kMeasuredOnDrives;
  }
  if (at_stops.heading_sigma_rad > 0.0) {
    noise.heading_sigma_rad = at_stops.heading_sigma_rad;
    noise.heading_source = NoiseSource::kMeasuredAtStops;
  } else if (on_drives.heading_sigma_rad > 0.0) {
    noise.heading_sigma_rad = on_drives.heading_sigma_rad;
    noise.heading_source = NoiseSource::kMeasuredOnDrives;
  }
  return noise;
}

PoseResult PosesFromLogs(const CalibrationResult& so_far, recording::PoseLogs logs,
                         RunState* state) {
  PoseResult step;
  const io::SessionSpec& session = so_far.loaded.session;
  const CalibrateOptions& options = so_far.loaded.options;
  const bool one_log = session.heading_log == session.gnss_log;
  io::NmeaLog& gnss = state->gnss;
  io::NmeaLog& headings = state->headings;
  gnss = std::move(logs.gnss);
  headings = std::move(logs.headings);
  state->attitudes = std::move(logs.attitudes);
  state->used_fixes.clear();
  state->track_local_m.clear();
  for (std::string& w : logs.warnings)
    step.warnings.push_back({WarningKind::kPoseLog, std::move(w)});
  // Each GGA at its epoch on the logger clock, not at its jittered arrival
  // (docs/time-alignment.md).
  step.gnss_epochs = calib::MapGnssEpochs(&gnss.fixes, options.alignment.gnss_epoch_time);
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
  if (const std::string w = DescribeSkips(session.gnss_log, gnss.skipped); !w.empty()) {
    step.warnings.push_back({WarningKind::kLinesSkipped, w});
  }
  if (!one_log) {
    if (const std::string w = DescribeSkips(session.heading_log, headings.skipped); !w.empty()) {
      step.warnings.push_back({WarningKind::kLinesSkipped, w});
    }
  }

  std::vector<calib::PositionSample> positions;
  try {
    positions = calib::PositionSamples(gnss, session.min_fix_quality, so_far.survey.frame,
                                       &state->used_fixes);
  } catch (const io::InputError& e) {
    throw io::InputError(io::Where(session.gnss_log, 0, e.what()));  // a fix outside the grid
  }
  step.fixes_used = static_cast<int64_t>(positions.size());
  {
    // A survey (or control point) far from where the vehicle drove is a survey mistake: say so
    // now rather than after a search for a wall that cannot be in the scans.
    std::vector<Eigen::Vector2d>& track = state->track_local_m;
    track.reserve(positions.size());
    for (const calib::PositionSample& p : positions) track.push_back(p.p_local_m);
    CheckTrackNearWalls(track, so_far.survey.walls, so_far.loaded.preset, session);
  }
  if (positions.size() < 2) {
    std::ostringstream found;
    for (const auto& [quality, count] : gnss.fixes_by_quality) {
      found << " quality " << quality << ": " << count << ";";
    }
    // Why the lines were not fixes, with the first line of each reason: the user can open the
    // log there (a missing checksum, a latitude of 91°, a misspelt sentence type).
    const std::string reasons = gnss.skipped.ListReasons(false, 6);
    throw io::InputError(
        io::Where(session.gnss_log, 0,
                  "fewer than 2 GGA fixes of accepted quality (gnss.min_fix_quality " +
                      std::to_string(session.min_fix_quality) + "); found" +
                      (found.str().empty() ? std::string(" none") : found.str()) +
                      (reasons.empty() ? std::string() : " (lines skipped: " + reasons + ")") +
                      "; expected NMEA GGA sentences with checksums, e.g. $GNGGA,...*hh"));
  }
  const int64_t rejected = static_cast<int64_t>(gnss.fixes.size()) - step.fixes_used;
  if (rejected > 0) {
    step.warnings.push_back(
        {WarningKind::kFixesNotUsed,
         std::to_string(rejected) +
             " GGA fixes below gnss.min_fix_quality (or out of time order) not used"});
  }
  const std::vector<calib::YawSample> yaws = calib::YawSamples(
      headings, session.heading_reference, so_far.survey.frame, state->used_fixes);
  step.headings_used = static_cast<int64_t>(yaws.size());
  if (yaws.size() < 2) {
    throw io::InputError(io::Where(session.heading_log, 0,
                                   "fewer than 2 usable HDT/THS headings; expected a heading log"));
  }
  auto poses = std::make_shared<calib::PoseInterpolator>(positions, yaws, options.alignment);
  // A moving scan carries one interpolated pose, so its σ is the sensors' white noise in full:
  // measured at the stops or on the drives where they hold enough samples, it stands in for the
  // configured fallbacks (which inflate the σ of sessions with drives when above the receiver's).
  step.measured_noise = calib::MeasureWhiteNoise(positions, yaws, poses->dwells());
  step.drive_noise = calib::MeasureDriveWhiteNoise(positions, yaws, poses->dwells());
  step.white_noise = ChooseWhiteNoise(options.solver, step.measured_noise, step.drive_noise);
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
  if (!(poses->start_s() < poses->end_s())) {
    throw io::InputError(session.gnss_log + " and " + session.heading_log +
                         ": the GNSS and heading logs do not overlap in time");
  }
  step.num_dwells = static_cast<int>(poses->dwells().size());
  step.fixes_by_quality = gnss.fixes_by_quality;
  step.gnss_skipped = gnss.skipped;
  step.heading_skipped = headings.skipped;
  step.interpolator = std::move(poses);
  return step;
}

}  // namespace wallcal::pipeline
