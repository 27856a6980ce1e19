// SPDX-License-Identifier: Apache-2.0
#pragma once
// What each step of a calibration run gives, one small struct per step, in the order the steps
// run (pipeline/session.h runs them; pipeline/calibration.h's CalibrationResult holds one of
// each). A step reads the results of the steps before it and writes only its own; each carries
// the warnings it raised (typed, pipeline/run_warnings.h).

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/error_budget.h"
#include "analysis/repeatability.h"
#include "analysis/residual_analysis.h"
#include "calib/attitude_model.h"
#include "calib/detection_pass.h"
#include "calib/drive_white_noise.h"
#include "calib/gnss_epoch_time.h"
#include "calib/observation.h"
#include "calib/survey_tie.h"
#include "calib/time_alignment.h"
#include "calib/white_noise.h"
#include "io/types.h"
#include "pipeline/calibrate_options.h"
#include "pipeline/run_warnings.h"
#include "pipeline/verdict.h"
#include "solvers/mount_solver.h"

namespace wallcal::pipeline {

// Load: session.yaml, the options and the scanner preset.
struct LoadResult {
  io::SessionSpec session;
  // As configured and validated (solver.num_threads set from the request). Never rewritten:
  // the white noise the solve uses is PoseResult::white_noise.
  CalibrateOptions options;
  io::ScannerPreset preset;
};

// Survey: the survey tied to UTM and the walls as lines in the local frame.
struct SurveyResult {
  calib::LocalFrame frame;
  std::vector<calib::WallGeometry> walls;
  std::vector<io::SurveyPoint> points;  // the survey, repeated points averaged
  calib::SurveyTie tie;                 // its control points' fit (rms, count)
  Warnings warnings;
};

// The GNSS and heading white noise the solve takes (m per axis, rad) and where each came from.
enum class NoiseSource { kConfigured, kMeasuredAtStops, kMeasuredOnDrives };
// "configured", "measured at the stops", "measured on the drives"
const char* NoiseSourceName(NoiseSource source);
struct WhiteNoiseInUse {
  double gnss_white_sigma_m = 0.0;
  NoiseSource gnss_source = NoiseSource::kConfigured;
  double heading_sigma_rad = 0.0;
  NoiseSource heading_source = NoiseSource::kConfigured;
};
// With configured.use_measured_white_noise, each figure the stops' measure where they hold
// enough samples, else the drives' where they do, else the configured one; without it, the
// configured ones.
WhiteNoiseInUse ChooseWhiteNoise(const solvers::SolverOptions& configured,
                                 const calib::MeasuredWhiteNoise& at_stops,
                                 const calib::DriveWhiteNoise& on_drives);

// Poses: the GNSS fixes and headings as a pose interpolator, its dwells and the white noise.
struct PoseResult {
  // The poses the observations are interpolated from. Shared: a joint adjustment of several
  // scanners re-interpolates each scanner's poses at its own estimated scan time.
  std::shared_ptr<const calib::PoseInterpolator> interpolator;
  calib::GnssEpochMapping gnss_epochs;  // the GGA epochs mapped onto the logger clock
  std::map<int, int64_t> fixes_by_quality;
  io::SkipCounts gnss_skipped, heading_skipped;
  int64_t fixes_used = 0;
  int64_t headings_used = 0;
  int num_dwells = 0;
  calib::MeasuredWhiteNoise measured_noise;  // at the dwells (calib/white_noise.h)
  calib::DriveWhiteNoise drive_noise;        // on the drives (calib/drive_white_noise.h)
  // With solver.use_measured_white_noise, each figure the dwells' measure where there is one,
  // else the drives' where there is one, else the configured one (LoadResult::options.solver).
  WhiteNoiseInUse white_noise;
  Warnings warnings;
};

// Site: the 3-D geometry the level model leaves out (calib/site_geometry.h): where each scan's
// vehicle attitude comes from, the yard fitted to the antenna's RTK heights, the scanner's
// height and tilt, the walls' leans. On a level site with an untilted scanner and upright walls
// nothing is corrected (`corrected` false) and the run is the level model's.
struct SiteResult {
  // The attitude stream when the logs hold one, else the yard when its grade is told from
  // level (calib::YardPlane::ToldFromLevel), else level.
  calib::AttitudeModel attitude;
  calib::YardPlane yard;  // from the GNSS heights at every fix used (fitted or not)
  // The scanner's height relative to the antenna (0 when not given) and its tilt.
  calib::ScannerPlacement placement;
  bool z_given = false;
  double z_sigma_m = 0.0;
  bool tilt_given = false;
  double tilt_sigma_rad = 0.0;
  // The antenna's ellipsoidal heights (stamp s, height m) in time order, for walls that lean.
  std::vector<std::pair<double, double>> antenna_heights_m;
  // The stream: its samples, rate (Hz) and range (rad), and its grade check against the yard.
  int64_t attitude_samples = 0;
  double attitude_rate_hz = 0.0;
  double roll_min_rad = 0.0, roll_max_rad = 0.0, pitch_min_rad = 0.0, pitch_max_rad = 0.0;
  // The stream's roll or pitch at the stations disagrees with the yard the GNSS heights show
  // (a sign reversed, a sensor turned): which, and by how much (rad, RMS at the stations).
  bool roll_disagrees = false, pitch_disagrees = false;
  double roll_mismatch_rad = 0.0, pitch_mismatch_rad = 0.0;
  // The scanner's height is given, there is no stream, and the stations do not spread over an
  // area (all at one distance from the wall): the yard's grade cannot be measured, the site is
  // taken as level.
  bool yard_unmeasured = false;
  bool corrected = false;  // the level corrections apply
  Warnings warnings;
};

// Detection: the two passes of the wall detector over the scans (wide gates on a subsample for
// a start, then every scan with tight gates around it) and their accounting. The detections
// themselves go to the solve (SolveResult::observations).
struct DetectionResult {
  // The scanner geometry taken from the scans where it differs from the preset's within the
  // family's limits ("681 beams (preset 682)"); empty when the scans have the preset's.
  std::string scanner_from_data;
  // Scans taken while driving are in the passes only by alignment.moving_scans_in_stop_and_go:
  // the solve keeps them only when their timing comes out determined.
  bool moving_by_default = false;
  // The first pass's start estimate (Barawid's closed form refined by the adjustment); when
  // `stopped`, the estimate that says why the run ends there.
  solvers::MountEstimate first_pass;
  bool stopped = false;
  int64_t scans_in_log = 0;  // scan records the first pass read
  // Every scan line of the log is in exactly one bucket: skipped for a reason here or in the
  // solve (CalibrationResult::ScansSkipped), or used.
  int64_t scans_total = 0;  // valid scan records + malformed scan lines
  std::map<calib::ScanSkip, int64_t> scans_skipped;
  io::SkipCounts scan_lines_skipped;
  // A preview's tally of every scan the second pass read (inspect's scan-log summary).
  std::optional<calib::ScanLogTally> scan_log;
  Warnings warnings;
};

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

// The site's inputs the level model leaves out, as terms of the mount's σ.
enum class SiteTermKind { kVehicleAttitude, kLeverArmHeight, kScannerTilt, kWallLean };
// "vehicle attitude", "lever arm height", "scanner tilt", "wall lean".
const char* SiteTermName(SiteTermKind kind);
// vehicle_attitude, lever_arm_height, scanner_tilt, wall_lean.
const char* SiteTermKey(SiteTermKind kind);
// The scanner's height relative to the antenna taken for the bias a graded yard could cause
// when scanner.z_m is not given (m): a front scanner on a tractor 2.5 m below a cab-roof antenna.
inline constexpr double kAssumedLeverArmM = -2.5;

// Solve: the estimate by the requested method on the second pass's detections.
struct SolveResult {
  // The observations the estimate rests on, at the poses the solve gave them (the clock rounds
  // move them); a preview's are every detection (its solve used every k-th, weighted by k),
  // without the drives when the solve left them out.
  std::vector<calib::WallObservation> observations;
  // The final estimate: checked against scanner.mount_guess's tolerance (refused outside it
  // unless forced); the closed form's with its covariance NaN. When the passes stopped, the
  // first pass's refusal.
  solvers::MountEstimate estimate;
  // false: the method gives no σ (barawid): offsets.yaml, the summary and the JSON say so.
  bool sigma_known = true;
  bool forced = false;  // usable only because of --force
  // A preview: how many observations its solve used (0 when not a preview), and how many
  // detections each stood for (its weight: 1 unless the solve was on a thinned set).
  int64_t preview_observations_solved = 0;
  double preview_weight = 1.0;
  // Skipped by the solve, beyond the passes' (DetectionResult::scans_skipped): drives whose
  // timing was not determined, scans without a pose at their shifted time.
  std::map<calib::ScanSkip, int64_t> scans_skipped;
  int64_t drives_dropped = 0;  // scans taken while driving the solve left out
  // The scanner clock offset (true scan time = stamp + offset, on the GNSS-epoch clock) and the
  // heading stream's delay after the GNSS epochs, as the run reports them.
  StreamDelay scanner_offset;
  StreamDelay heading_delay;
  // How well the timing the drives' poses need is known (s; solvers::DrivesTimingSigma): the
  // clock offset when driving towards a wall, offset + heading delay when turning in front of
  // it. 0 when no moving scan is used.
  double drives_timing_sigma_s = 0.0;
  // The site's systematic terms (calib/site_geometry.h) the solve propagated into
  // estimate.covariance: each input's σ through a re-solve at the input moved by it.
  struct SiteTerm {
    SiteTermKind kind = SiteTermKind::kVehicleAttitude;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  };
  std::vector<SiteTerm> site_terms;
  // On a graded yard with scanner.z_m not given: how far a scanner kAssumedLeverArmM below the
  // antenna would move the mount (x, y m; yaw rad); empty when z_m is given or the site level.
  std::optional<Eigen::Vector3d> unknown_height_bias;
  Warnings warnings;
};

// Scans used, GNSS slices, heading and vehicle-to-wall angle extents of the solve's
// observations.
struct Coverage {
  int64_t scans_used = 0;
  int64_t scans_used_moving = 0;
  int num_segments_used = 0;
  double heading_min_deg = 0.0, heading_max_deg = 0.0;        // grid headings
  double wall_angle_min_deg = 0.0, wall_angle_max_deg = 0.0;  // vehicle-to-wall angle φ
};

// Finish: what is learned about the estimate after the solve.
struct FinishResult {
  analysis::ResidualAnalysis residual_analysis;  // a usable estimate's (not a thinned set's)
  analysis::Repeatability repeatability;         // ceres, not a preview
  analysis::ErrorBudget budget;                  // what the σ is made of (ceres, not a preview)
  // A σ refusal whose variance one source dominates: the refusal said with advice about that
  // source (CalibrationResult::Why gives it in place of the estimate's message).
  std::optional<std::string> refusal_advice;
  Coverage coverage;
  Warnings warnings;
};

// Where a run came from, for offsets.yaml.
struct Provenance {
  std::string created_utc;  // ISO 8601 UTC, seconds
  std::string tool_version;
  std::vector<std::string> command_line;
  std::vector<io::InputFileDigest> inputs;
};

// Decide: the verdict, the change since the --compare file and the provenance.
struct DecideResult {
  std::optional<Change> change;  // when --compare was given and the estimate is usable
  Decision decision;             // ACCEPT / REVIEW / REJECT with the reasons
  Provenance provenance;
};

}  // namespace wallcal::pipeline
