// SPDX-License-Identifier: Apache-2.0
#pragma once
// The observation finder: one pass over the scans that turns each scan into wall observations.
// For every scan it takes the vehicle pose at the scan's time, predicts where each surveyed wall
// should appear for a mount estimate (the gates), and runs the wall detector inside them. Every
// scan not used is counted by a typed reason.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "calib/observation.h"
#include "calib/range_model.h"
#include "calib/time_alignment.h"
#include "calib/wall_detector.h"
#include "calib/wall_detector_options.h"
#include "io/scan_source.h"
#include "io/types.h"

namespace wallcal::calib {

// Why a scan gave no observation (or a line gave no scan).
enum class ScanSkip {
  kNoPoseBeforeLogs,   // before the GNSS / heading logs begin
  kNoPoseAfterLogs,    // after they end
  kNoPoseGnssGap,      // in a gap of the GNSS log
  kNoPoseHeadingGap,   // in a gap of the heading log
  kVehicleMoving,      // moving, and moving scans are not used
  kScannerBehindWall,  // the predicted wall is behind the scanner
  kWallNotDetected,    // the detector found no line in the gates
  kMalformedLine,      // the scan's line in the log could not be read
  kNoPoseAtShiftedTime,  // no pose at the clock-offset-corrected time
  // The wall was not detected and no part of its surveyed extent lies within the scanner's
  // field of view (its beams' bearings) where the pass's mount puts it.
  kWallOutsideField,
};
// For people: "no pose: before the GNSS/heading logs", "vehicle moving", ...
const char* ScanSkipName(ScanSkip reason);
ScanSkip ScanSkipFor(PoseStatus status);  // status != kOk

// The gates around the predicted wall line: half-widths in angle (rad) and offset (m), and
// whether the surveyed wall's extent limits the inliers.
struct Gates {
  double angle_rad = 0.0;
  double offset_m = 0.0;
  bool use_segment = false;
  // Fewest inliers a line needs inside these gates (> 0: instead of detector.min_inliers). A
  // tight gate around a surveyed wall leaves room for little but the wall, so a short stretch
  // of it seen at the edge of the field of view can be taken (calib::DetectorOptions).
  int min_inliers = 0;
};

// What every pass over a session shares.
struct PassContext {
  std::function<std::unique_ptr<io::ScanSource>()> open_scans;  // a fresh stream per pass
  double scanner_time_offset_s = 0.0;  // added to every scan stamp (session.yaml)
  const io::ScannerPreset* preset = nullptr;
  const calib::DetectorOptions* detector = nullptr;
  const std::vector<WallGeometry>* walls = nullptr;
  const PoseInterpolator* poses = nullptr;
  bool use_moving = false;  // scans taken while moving are used
  // Threads that detect the walls (>= 1). Scans are read in file order on the calling thread
  // and detected in batches split over the threads; the outcome is the same, in the same
  // order, whatever the count.
  int threads = 1;
};

// Every scan a pass read, for the scan log's summary (inspect's, which then reads no scan a
// second time): stamps with the session's clock offset, in file order, their lines, the scans
// by beam count and the readings of every scan by fate (calib/range_model.h).
struct ScanLogTally {
  std::vector<double> stamps_s;
  std::vector<int> lines;
  std::map<size_t, int64_t> beams;  // beam count -> scans
  RangeCounts readings;
  double first_start_rad = 0.0, first_step_rad = 0.0, first_max_range_m = 0.0;  // first scan's
};

struct PassRequest {
  Mount mount;  // the estimate the gates are centred on
  Gates gates;
  double min_interval_s = 0.0;  // > 0: only scans at least this far apart are examined
  // The scanner clock offset of an earlier estimate (s): gates are predicted at the scan's true
  // time; observations keep the pose at the stamp (the solver applies the offset itself).
  double gate_time_offset_s = 0.0;
  std::function<void(int64_t scans_done)> progress;  // every 2000 scans; may be empty
  ScanLogTally* tally = nullptr;  // filled with every scan read when given (not when skimming)
};

struct PassOutcome {
  std::vector<WallObservation> observations;
  std::map<ScanSkip, int64_t> skipped;  // per examined scan, why it gave no observation
  int64_t scans_read = 0;
  int64_t scans_examined = 0;
  io::SkipCounts line_skips;  // what the scan source passed over
  RangeCounts range_counts;
  int64_t beam_count_mismatch = 0;
  int first_mismatch_beams = 0;
  int64_t not_increasing = 0;  // scans stamped at or before the scan before them
  int first_not_increasing_line = 0;
  double first_stamp_s = 0.0, last_stamp_s = 0.0;  // the scans' time span (all scans)
};

// Streams the scans once and detects the walls in each examined scan.
PassOutcome DetectionPass(const PassContext& context, const PassRequest& request);

// The detector's gate for one wall seen from one pose with `mount`, as a pass builds it.
LineGate GateFor(const WallObservation& at, const WallGeometry& wall, const Mount& mount,
                 const Gates& gates);

// Moves every observation to its scan's time + dt_s, with the pose interpolated anew at that
// time (the scanner clock offset the solver estimated; the wall line is the scan's and does not
// change), and its heading a further heading_shift_s later than before (the heading stream's
// delay the solver estimated: pose.heading_shift_s grows by it; pose.clock_shift_s by dt_s).
// Observations whose shifted times have no pose are dropped; returns how many.
int ShiftObservations(const PoseInterpolator& poses, double dt_s, double heading_shift_s,
                      std::vector<WallObservation>* observations);

}  // namespace wallcal::calib
