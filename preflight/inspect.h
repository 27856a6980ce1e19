// SPDX-License-Identifier: Apache-2.0
#pragma once
// inspect: the pre-flight check of a session (or of one log file) and the CSV dumps of the
// decoded records. Read-only: nothing is written but the report / dump stream.
//
// On a session it reads every input it can on its own (so that one broken file does not hide
// the state of the others), then, when nothing blocks it, runs the calibration pipeline
// (RunCalibration) for the wall detections, and ends with a verdict: enough data for a
// calibration, or the list of what is missing. What each part means: docs/inspect.md.

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "io/types.h"

namespace wallcal::preflight {

enum class LogKind { kNmea, kCarmen };

// Recognises a log by content (not by name): the first lines that are not blank and not `#`
// comments. A line holding an NMEA sentence ("$GPGGA,..." possibly after a logger time or
// after binary bytes) -> kNmea; a line starting with a CARMEN keyword (RAWLASER1, ROBOTLASER1,
// FLASER, PARAM, ODOM, ...) -> kCarmen. A gzip-compressed file is a CARMEN log when its content
// has such a line (the NMEA reader does not read gzip).
// Throws io::InputError naming the file (and the first line looked at) when the file cannot be
// opened, is empty, or is neither.
LogKind SniffLogKind(const std::string& path);

// Time statistics of one stream of time-stamped records (scans, GGA fixes or headings).
struct StreamStats {
  std::string name;  // "scans", "GNSS fixes", "headings"
  std::string file;
  int64_t records = 0;
  double start_s = io::kNaN, end_s = io::kNaN;  // first and last stamp (file order)
  double median_period_s = io::kNaN;            // median of the positive stamp steps
  // A gap: a step longer than gap_periods median periods (the pose interpolator's
  // alignment.max_gap_periods: across such a gap a scan gets no pose).
  double gap_periods = 3.0;
  int64_t gaps = 0;
  double longest_gap_s = 0.0;
  double longest_gap_start_s = io::kNaN;  // stamp of the record before the longest gap
  int longest_gap_line = 0;               // line of the record after it
  int64_t not_increasing = 0;  // steps back in time or repeated stamps
  int first_not_increasing_line = 0;
};

// Statistics of stamps in file order; `lines` (same size, or empty) are their 1-based lines.
StreamStats ComputeStreamStats(const std::string& name, const std::string& file,
                               const std::vector<double>& stamps_s, const std::vector<int>& lines,
                               double gap_periods = 3.0);

// The result of inspecting a session: the printable report and its verdict.
struct SessionInspection {
  std::string report;                 // the whole text, verdict included
  bool enough = false;                // "enough data for a calibration"
  std::vector<std::string> blockers;  // what prevents a calibration (empty when enough)
  std::vector<std::string> warnings;  // what weakens it
};

// Inspects a session (session.yaml or its folder). `config_path`: calibrate options (empty:
// defaults). Problems with the logs, the survey or the geometry become blockers in the result;
// only an unreadable session.yaml or options file throws io::InputError.
SessionInspection InspectSession(const std::string& session_path,
                                 const std::string& config_path = std::string());

// The report on one log file (kind sniffed): per stream time span, rate, gaps, record counts
// and the lines skipped by reason with the first line. Throws io::InputError when the file
// cannot be opened or is neither NMEA nor CARMEN.
std::string InspectLogFile(const std::string& path);

// The report on one survey file (CSV or Leica GSI, io/survey_reader.h): its format, the number
// of observations and points, the codes with their counts and the extents in x, y, z. Throws
// io::InputError as io::ReadSurvey does.
std::string InspectSurveyFile(const std::string& path);

enum class DumpKind { kGnss, kHeading, kScans, kAttitude };

// Writes the decoded records of one log as CSV with a header (columns: docs/inspect.md):
//   gnss:     time_s,lat_deg,lon_deg,height_m,quality,satellites,hdop,sigma_lat_m,sigma_lon_m,line
//   heading:  time_s,heading_deg,line
//   scans:    time_s,beams,valid,min_range_m,max_range_m,line
//   attitude: time_s,roll_deg,pitch_deg,roll_sigma_deg,pitch_sigma_deg,line
// `path` is a session (the log of that kind is dumped; scan times include the session's
// scanner.time_offset_s, attitude times its attitude.time_offset_s, `valid` follows its
// scanner preset; a session without attitude: has no attitude to dump) or one log file of the
// matching kind. Unknown values (no GST, no valid reading, an axis or σ the attitude sentence
// does not give) are empty cells. On a session with
// `scanners:`, `scanner_id` names the scanner whose scans are dumped (needed for kScans; the
// GNSS and heading logs are the session's). Throws io::InputError when the file is missing,
// unreadable or of the other kind, or the scanner is not named or not in the session.
void Dump(const std::string& path, DumpKind kind, std::ostream& out,
          const std::string& scanner_id = "");

// ---- Robot recordings (ROS 1 bag, MCAP, rosbag2; recognised by recording::IsRecording) ----------

// Every topic with its type, message count, rate, span and gaps (receive times), and for the
// supported types the statistics of text logs (beams and readings, NavSatFix status and σ,
// heading histogram, NMEA sentence counts). Throws io::InputError on a damaged recording.
std::string InspectRecording(const std::string& path);

// A ready-to-edit session.yaml naming the recording and the topics chosen by type (LaserScan;
// NavSatFix before GGA sentences; QuaternionStamped, Imu, then HDT/THS sentences; an attitude:
// block when an Imu topic carries an orientation), with a comment naming the others when
// several fit, the scanner preset matching the scans, and for each scanner a commented z_m line
// to fill in.
std::string SuggestSession(const std::string& path);

// --dump on a recording: the CSV of Dump from `topic` (empty: the one topic of a fitting type;
// several -> io::InputError listing them). Stamps are header stamps.
void DumpRecording(const std::string& path, DumpKind kind, const std::string& topic,
                   std::ostream& out);

// A folder or a .yaml/.yml file: a session rather than one log or recording.
bool IsSessionPath(const std::string& path);

}  // namespace wallcal::preflight
