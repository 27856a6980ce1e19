#pragma once
// The calibrate and simulate programs as library calls, so tests can run them in-process.
// Data flows one way: io/ reads the session -> calib/ makes wall observations -> solvers/
// estimates the mount -> io/ writes offsets.yaml (only when the estimate is usable).

#include <cstdint>
#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "calib/observation.h"
#include "calib/time_alignment.h"
#include "io/options.h"
#include "io/types.h"
#include "solvers/mount_solver.h"

namespace wallcal::app {

// Where scanner presets and default configs are looked for, in order: $WALLCAL_CONFIG_DIR,
// <executable>/../configs, the source tree's configs/ (compiled in).
std::vector<std::string> ConfigDirs();
std::vector<std::string> PresetDirs();

struct CalibrateRequest {
  std::string session_path;  // session.yaml or its folder
  std::string config_path;   // calibrate options YAML; empty: built-in defaults
  std::string method = "ceres";  // "ceres" or "barawid"
  bool force = false;  // write an estimate the observability checks refuse, with a warning
};

// Progress of a long run: a stage name and, within a stage, how far it got. total == 0 when
// the total is not known (the first pass over the scan log).
struct Progress {
  std::string stage;  // "reading survey", "first pass", "second pass", "solving", ...
  int64_t done = 0;
  int64_t total = 0;
};
using ProgressFn = std::function<void(const Progress&)>;

// Residuals examined after the solve (seed 003's residual analysis): robust spread, outliers,
// and trends against what a systematic error would show up in.
struct ResidualTrend {
  std::string against;   // "range", "incidence", "bearing", "heading", "station", "time"
  std::string unit;      // unit of the slope, e.g. "m/m", "m/deg", "m/station"
  double slope = 0.0;    // least-squares slope of the distance residual against that quantity
  double significance = 0.0;  // |slope| / σ(slope)
  bool flagged = false;
  std::string message;   // what a flagged trend suggests (e.g. "range scale error: check k")
};
struct ResidualAnalysis {
  bool done = false;
  double robust_sigma_m = 0.0;  // 1.4826 × median absolute deviation of the distance residuals
  double outlier_share = 0.0;   // share of observations beyond 2 robust σ (seed 003: 2σ rule)
  std::vector<ResidualTrend> trends;
  std::vector<std::string> flags;  // human-readable summaries of the flagged trends
  bool range_model_estimated = false;  // k, b re-estimated jointly when ranges span enough
  double range_scale_k = 1.0, range_offset_b_m = 0.0;
  double sigma_range_scale_k = 0.0, sigma_range_offset_b_m = 0.0;
};

// How much the mount moves when the session is split or resampled.
struct RepeatabilitySplit {
  std::string name;          // "first half", "second half", "odd stations", ...
  solvers::Mount mount;
  bool usable = false;
};
struct Repeatability {
  bool done = false;
  std::vector<RepeatabilitySplit> splits;
  int bootstrap_samples = 0;
  double bootstrap_sigma_x_m = 0.0, bootstrap_sigma_y_m = 0.0, bootstrap_sigma_yaw_rad = 0.0;
  double max_split_shift_x_m = 0.0, max_split_shift_y_m = 0.0, max_split_shift_yaw_rad = 0.0;
};

// Everything calibrate learned, for the summary and offsets.yaml.
struct CalibrationResult {
  io::SessionSpec session;
  io::ScannerPreset preset;
  solvers::MountEstimate first_pass;  // wide-gate pass on a subsample (Barawid start + Ceres)
  solvers::MountEstimate estimate;    // the final estimate by the requested method
  std::vector<calib::WallGeometry> walls;
  std::vector<calib::WallObservation> observations;  // second pass
  calib::LocalFrame frame;
  double control_rms_m = 0.0;
  int num_control = 0;
  int num_dwells = 0;
  int num_segments_used = 0;
  // Scan accounting: every scan line of the log is in exactly one bucket.
  int64_t scans_total = 0;  // valid scan records read + malformed scan lines skipped
  int64_t scans_used = 0;   // scans with at least one wall observation in the final solve
  std::map<std::string, int64_t> scans_skipped;  // reason -> count
  std::map<int, int64_t> fixes_by_quality;
  int64_t fixes_used = 0;
  int64_t headings_used = 0;
  io::SkipCounts gnss_skipped, heading_skipped, scan_lines_skipped;
  double heading_min_deg = 0.0, heading_max_deg = 0.0;  // grid headings of used scans
  double wall_angle_min_deg = 0.0, wall_angle_max_deg = 0.0;  // vehicle-to-wall angle φ
  ResidualAnalysis residual_analysis;
  Repeatability repeatability;
  double time_offset_s = 0.0;        // estimated scanner-to-GNSS clock offset (moving data)
  double time_offset_sigma_s = 0.0;  // 0 when not estimated
  bool forced = false;               // written despite a failed observability check
  std::vector<std::string> warnings;
  double seconds = 0.0;  // wall-clock run time, for the summary
};

// The GNSS fixes calibrate uses, as local positions: qualities gnss.min_fix_quality accepts,
// strictly increasing in time, σ from GST (0 without). `used` (may be null) receives the fix of
// each sample, in the same order.
std::vector<calib::PositionSample> PositionSamples(const io::NmeaLog& gnss, int min_fix_quality,
                                                   const calib::LocalFrame& frame,
                                                   std::vector<const io::GnssFix*>* used);

// The headings as vehicle yaws in the local frame (strictly increasing in time). True headings
// are turned into grid headings with the meridian convergence at the vehicle: at the used fix
// nearest in time (`used` must not be empty then). Grid headings are taken as they are.
std::vector<calib::YawSample> YawSamples(const io::NmeaLog& headings,
                                         io::HeadingReference reference,
                                         const calib::LocalFrame& frame,
                                         const std::vector<const io::GnssFix*>& used);

// Runs the whole calibration. Writes nothing. Throws io::InputError for bad input; an
// estimate the data cannot support comes back with estimate.usable == false and a message.
// `progress` (may be empty) is called at each stage and every few thousand scans.
CalibrationResult RunCalibration(const CalibrateRequest& request,
                                 const ProgressFn& progress = nullptr);

// offsets.yaml for a usable result.
io::OffsetsDocument MakeOffsetsDocument(const CalibrationResult& result);

// The human summary printed on stdout.
std::string FormatSummary(const CalibrationResult& result);

// Default output path: offsets.yaml beside session.yaml.
std::string DefaultOutputPath(const io::SessionSpec& session);

// simulate: writes a session folder (session.yaml, scans.clf, gnss.nmea, heading.nmea,
// survey.csv) and truth.yaml into `dir` (created if missing). Every file is written to a
// temporary name and renamed, so an interrupted run leaves no half-written file behind.
struct SimulateSummary {
  int64_t scans_written = 0, scans_lost = 0, fixes = 0, headings = 0, survey_points = 0;
  double duration_s = 0.0;
};
SimulateSummary WriteSimulatedSession(const io::SimulationConfig& config, uint64_t seed,
                                      const std::string& dir);

}  // namespace wallcal::app
