// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the inspect files share (not part of the public preflight API): text formatting of the
// report, the scan-log summary and the per-stream statistics helpers.

#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "calib/detection_pass.h"
#include "calib/range_model.h"
#include "io/text/nmea_reader.h"
#include "io/types.h"
#include "pipeline/calibrate_options.h"
#include "preflight/inspect.h"
#include "recording/recording_streams.h"

namespace wallcal::preflight::internal {

// ---- Text (report_text.cc) -----------------------------------------------------------------
std::string Fmt(const char* format, double value);
std::string FileName(const std::string& path);
// Stamps on the UNIX clock (after 1973) are printed as UTC; smaller ones (a logger that counts
// from its own start, like the Radish logs) as seconds.
std::string FormatStamp(double stamp_s);

// Circular extent of angles (rad) about their circular mean: min and max as headings in
// [0, 360) degrees and the width in degrees (0 for fewer than one angle).
struct AngleExtent {
  double min_deg = 0.0, max_deg = 0.0, width_deg = 0.0;
  bool any = false;
};
AngleExtent Extent(const std::vector<double>& angles_rad);
// 36 bins of 10 degrees of heading (clockwise from north), one character each.
std::string Histogram(const std::vector<double>& headings_rad);
int OccupiedBins(const std::vector<double>& headings_rad);
// The axis over Histogram(): labels at 0, 90, 180, 270, 360 degrees.
std::string HistogramAxis();
std::string DescribeSkips(const io::SkipCounts& skips);
int64_t WorrisomeSkips(const io::SkipCounts& skips);
std::string FormatStream(const StreamStats& s);

struct Interval {
  double start_s = io::kNaN, end_s = io::kNaN;
  bool Valid() const { return std::isfinite(start_s) && std::isfinite(end_s) && end_s >= start_s; }
};
Interval Intersect(const Interval& a, const Interval& b);
std::string FormatOverlap(const Interval& i);
// A CSV cell: the number, or nothing when it is not finite.
void CsvNumber(std::ostream& out, const char* format, double value);

// ---- Paths (log_kind.cc) -------------------------------------------------------------------
// Throws io::InputError naming the path when it does not exist, is a folder or cannot be read.
void RequireReadableFile(const std::string& path);

// ---- Streams (stream_stats.cc) -------------------------------------------------------------
StreamStats FixStats(const std::string& path, const io::NmeaLog& log);
StreamStats HeadingStats(const std::string& path, const io::NmeaLog& log);
std::string FormatQualities(const io::NmeaLog& log);
// Time covered by consecutive RTK-fixed epochs (steps no longer than max_step_s).
double TimeRtkFixed(const std::vector<io::GnssFix>& fixes, double max_step_s);

// ---- Scan logs (log_inspection.cc) ---------------------------------------------------------
struct ScanLogSummary {
  StreamStats stats;
  std::vector<double> stamps_s;  // with the session's time offset
  std::map<size_t, int64_t> beams;  // beam count -> scans
  calib::RangeCounts readings;
  bool have_readings = false;
  double first_start_rad = 0.0, first_step_rad = 0.0, first_max_range_m = 0.0;
  io::SkipCounts skipped;
  int64_t lines_read = 0;
};
// Valid readings of a scan without a preset: finite, positive and below the log's maximum.
int LogValid(const io::ScanRecord& scan, float* min_m, float* max_m);
ScanLogSummary ReadScanLog(const std::string& path, double time_offset_s,
                           const io::ScannerPreset* preset, double min_range_m, double mixed_jump_m,
                           const recording::ScanOpener* opener = nullptr);
// The same summary from a detection pass's tally of the log (calib/detection_pass.h) and what
// its scan source passed over: the preview's second pass read every scan already.
ScanLogSummary SummaryFromTally(const std::string& path, calib::ScanLogTally tally,
                                const io::SkipCounts& skipped);

// ---- A session's logs (session_logs.cc) ----------------------------------------------------
struct SessionLogs {
  std::optional<ScanLogSummary> scans;
  std::optional<io::NmeaLog> gnss;
  std::optional<io::NmeaLog> heading_log;
  std::optional<StreamStats> fix_stats, heading_stats;
  int64_t accepted_fixes = 0;
};
// The "logs" part of the session report (scans, GNSS, headings, their overlap), written to
// `out`; problems become blockers and warnings in `result`.
// shared_scan_log, when given, returns the scan log's summary if another reader has it (the
// preview's second pass); the log is read here when it returns none.
SessionLogs InspectSessionLogs(
    const io::SessionSpec& spec, const pipeline::CalibrateOptions& options,
    const io::ScannerPreset* preset,
    const std::function<std::optional<ScanLogSummary>()>& shared_scan_log,
    SessionInspection* result, std::ostream& out);

// ---- The attitude stream (attitude_inspection.cc) -------------------------------------------
// What the reports say about an attitude stream, computed once from it.
struct AttitudeSummary {
  StreamStats stats;   // stamps and lines of the samples
  std::string source;  // "$PASHR 1200", "topic /imu/data: sensor_msgs/Imu 11865"
  int64_t roll_samples = 0, pitch_samples = 0;  // samples that measure each (an AVR: one)
  double roll_min_rad = io::kNaN, roll_max_rad = io::kNaN;
  double pitch_min_rad = io::kNaN, pitch_max_rad = io::kNaN;
  double roll_sigma_median_rad = io::kNaN, pitch_sigma_median_rad = io::kNaN;  // the stream's
  int64_t without_sigma = 0;            // samples with no σ of their own
  double default_sigma_rad = io::kNaN;  // attitude.sigma_deg, on a session
  io::SkipCounts skipped;
};
// `topic`: the recording topic the log came from ("" for a text log).
AttitudeSummary SummariseAttitude(const std::string& path, const std::string& topic,
                                  const io::NmeaLog& log);
// The stream's statistics, then FormatAttitudeValues, then (with_skips) its skipped lines.
std::string FormatAttitude(const AttitudeSummary& summary, bool with_skips);
// The lines on roll, pitch and σ (none without a sample).
std::string FormatAttitudeValues(const AttitudeSummary& summary);
// The attitude block of the session report (after the headings); an unreadable stream or one
// without a sample blocks, as calibrate stops on it.
void InspectSessionAttitude(const io::SessionSpec& spec, const SessionLogs& logs,
                            SessionInspection* result, std::ostream& out);

}  // namespace wallcal::preflight::internal

namespace wallcal::preflight {
// The CSV of inspect --dump from the streams `spec` names (text logs or recording topics);
// scans are judged valid by `preset` when not null, else by the log alone.
void WriteDumpCsv(const io::SessionSpec& spec, DumpKind kind, const io::ScannerPreset* preset,
                  std::ostream& out);
}  // namespace wallcal::preflight
