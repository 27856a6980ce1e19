// SPDX-License-Identifier: Apache-2.0
#pragma once
// Plain records read from (or written to) a logged session. No behaviour here: io/ fills these
// structs from files, calib/ turns them into observations. Units are in every name; angles are
// radians, except geodetic latitude/longitude, which stay in degrees as GeographicLib takes them.

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace wallcal::io {

// The one exception type for bad user input. what() reads "file:line: what is wrong and what
// was expected" (line omitted when the problem is not tied to a line).
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Builds the "file:line: message" text of an InputError. line <= 0 omits the line.
std::string Where(const std::string& file, int line, const std::string& message);

// GGA fix quality (NMEA 0183): its name ("RTK fixed", "RTK float", ...; "unknown" otherwise).
const char* FixQualityName(int quality);
// gnss.min_fix_quality's rule. Qualities ranked from best to worst: RTK fixed (4), RTK float
// (5), DGPS/SBAS (2, 9), PPS (3), autonomous (1); min_fix_quality q accepts every quality
// ranked at least as high as q. 0 (invalid), 6 (dead reckoning), 7 (manual) and 8 (simulator)
// are never accepted.
bool FixQualityAccepted(int quality, int min_fix_quality);

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One scan as logged (CARMEN RAWLASER1 / ROBOTLASER1 / FLASER). Ranges are raw: no range
// correction applied, error codes and no-returns still in place.
struct ScanRecord {
  double stamp_s = 0.0;           // logger_timestamp, s on the session's logging clock
  double start_angle_rad = 0.0;   // bearing of the first beam in the scanner frame (ccw +)
  double angular_step_rad = 0.0;  // bearing increment between beams (ccw +)
  double max_range_m = 0.0;       // the log's maximum_range (FLASER: 0 = unknown)
  std::vector<float> ranges_m;    // raw ranges, one per beam
  int line = 0;                   // 1-based line number in the log
};

// One GGA position (with the matching GST σ when the log has one).
struct GnssFix {
  double stamp_s = 0.0;  // logging clock (prefix), or UTC from the sentence for plain captures
  double lat_deg = 0.0;  // WGS84 geodetic latitude, north +
  double lon_deg = 0.0;  // WGS84 longitude, east +
  double height_m = 0.0;        // ellipsoidal height = GGA altitude + geoid separation
  int quality = 0;              // GGA fix quality (1 GPS, 2 DGPS, 4 RTK fixed, 5 RTK float, ...)
  int satellites = 0;
  double hdop = kNaN;
  double sigma_lat_m = kNaN;  // from GST; NaN when the log has no GST for this epoch
  double sigma_lon_m = kNaN;
  // UTC of the receiver's epoch (s since 1970, from the sentence's time of day and the log's
  // date), kept when the line also had a logger stamp (then stamp_s is the arrival on the
  // logger clock until calib::MapGnssEpochs puts the epoch there); NaN otherwise. The NMEA
  // writer takes the sentence's time from it when finite.
  double utc_epoch_s = kNaN;
  int line = 0;
};

// One HDT/THS heading.
struct HeadingSample {
  double stamp_s = 0.0;
  double heading_rad = 0.0;  // clockwise from north (true or grid: see SessionSpec), [0, 2π)
  int line = 0;
};

// One sample of the vehicle's attitude from an attitude stream: an NMEA $PASHR or $PTNL,AVR
// sentence, or a ROS sensor_msgs/Imu orientation. Vehicle frame x forward, y left, z up. Roll
// and pitch are the Tait-Bryan angles of the heading-pitch-roll (z-y-x) sequence, as INSs and
// $PASHR give them: pitch is the nose's angle above the horizontal, roll the turn about the
// vehicle's own x axis after it. Each is within ±kMaxVehicleTiltRad: readers skip anything else
// (counted, with its line).
// The largest roll or pitch a vehicle stands or drives at on a calibration site (30°). Beyond
// it a sample is no vehicle's attitude: a sensor whose frame is turned on the vehicle (an IMU
// on its side reads a roll near 90°), or a corrupt value.
inline constexpr double kMaxVehicleTiltRad = 30.0 * 3.14159265358979323846 / 180.0;
// The skip reason of such a sample, in every attitude reader's counts.
inline constexpr char kAttitudeOutOfRangeReason[] = "roll or pitch beyond 30 deg";

struct AttitudeSample {
  double stamp_s = 0.0;   // logging clock (as a heading's)
  // About x: positive right side down. NaN when the sample does not measure it: a $PTNL,AVR
  // gives the tilt of one antenna baseline, along the vehicle (pitch) or across it (roll).
  double roll_rad = 0.0;
  double pitch_rad = 0.0;  // about y: positive nose up; NaN as roll_rad
  // The stream's own 1σ of each (PASHR's σ fields, the Imu's orientation covariance); NaN when
  // it gives none (the session's attitude.sigma_deg stands in).
  double roll_sigma_rad = kNaN;
  double pitch_sigma_rad = kNaN;
  int line = 0;  // 1-based line in its text log; message index + 1 in a recording
};

// How a skipped line counts: lines a healthy log has too (comments, blank lines, other NMEA
// sentences, CARMEN PARAM/ODOM lines) are informational; the rest are problems worth a warning.
enum class SkipSeverity { kInformational, kProblem };

// What a reader passed over, by reason, so nothing is silently dropped. The reason text is for
// people; decisions use the severity recorded with it.
struct SkipCounts {
  std::map<std::string, int64_t> by_reason;  // e.g. "bad checksum" -> 3
  std::map<std::string, int> first_line;     // first line skipped for each reason (0: none)
  std::map<std::string, SkipSeverity> severity;
  int64_t Total() const {
    int64_t n = 0;
    for (const auto& kv : by_reason) n += kv.second;
    return n;
  }
  // Lines skipped for a reason of severity kProblem.
  int64_t Problems() const {
    int64_t n = 0;
    for (const auto& kv : by_reason) {
      if (!IsInformational(kv.first)) n += kv.second;
    }
    return n;
  }
  bool IsInformational(const std::string& reason) const {
    const auto it = severity.find(reason);
    return it != severity.end() && it->second == SkipSeverity::kInformational;
  }
  void Add(const std::string& reason, int line = 0, int64_t n = 1,
           SkipSeverity how = SkipSeverity::kProblem) {
    by_reason[reason] += n;
    severity.emplace(reason, how);
    if (line > 0 && first_line.find(reason) == first_line.end()) first_line[reason] = line;
  }
  // "reason: n, first at line L; ..." for the reasons counted (the problems only when
  // `problems_only`), at most `max_reasons` of them and then "; ...": the one way a skip list
  // is written, in calibrate's warnings and inspect's report alike.
  std::string ListReasons(bool problems_only,
                          size_t max_reasons = std::numeric_limits<size_t>::max()) const;
};

struct NmeaLog {
  std::vector<GnssFix> fixes;            // sorted by stamp_s as read; all qualities
  std::vector<HeadingSample> headings;   // sorted by stamp_s as read
  std::vector<AttitudeSample> attitudes;  // $PASHR and $PTNL,AVR, sorted by stamp_s as read
  std::map<int, int64_t> fixes_by_quality;
  // The attitude samples by what gave them: "$PASHR", "$PTNL,AVR" (or "sensor_msgs/Imu" for a
  // recording's Imu topic), for reports.
  std::map<std::string, int64_t> attitudes_by_source;
  SkipCounts skipped;
  int64_t lines_read = 0;
};

// Where a survey point's coordinates come from (docs/survey-files.md).
enum class SurveySource {
  kCoordinates,      // stored coordinates: a CSV row, or GSI words 81/82/83
  kPolarFromSetup,   // a GSI polar observation reduced from a set-up in the file (84/85/86)
  kPolarFromOrigin,  // a GSI polar observation before any set-up: station at the local origin
};

// The frame a survey point's coordinates are in (docs/survey-files.md).
enum class SurveyFrame {
  kLocal,     // the total station's own frame: x_m, y_m, z_m
  kGeodetic,  // a GNSS rover's: lat_deg, lon_deg and the ellipsoidal height in z_m, in the
              // GNSS's datum; x_m, y_m stay 0 until calib::GeodeticSurveyToLocal places them
};

// One surveyed point. A total-station point is in the survey's local right-handed frame
// (ground metres): x east, y north, z up (a file's N/E columns or GSI words are mapped so).
// A rover point (frame kGeodetic) is in latitude, longitude (degrees) and ellipsoidal height.
struct SurveyPoint {
  std::string id;
  std::string code;
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.0;
  int line = 0;          // 1-based line in the survey file (combined: the first observation's)
  int observations = 1;  // how many observations were averaged into this point (>= 1)
  SurveySource source = SurveySource::kCoordinates;
  SurveyFrame frame = SurveyFrame::kLocal;
  double lat_deg = 0.0;  // kGeodetic only, WGS84 / the GNSS's datum
  double lon_deg = 0.0;
  // Horizontal 1σ per axis (m) the file gives for this point (a rover's precision column);
  // 0: not given (the session's or the solver's σ applies).
  double sigma_m = 0.0;
};

// The columns of a survey CSV (session.yaml `survey.columns`): named by a header row, or a
// headerless file with point, northing, easting, elevation[, description] (PNEZD) or point,
// easting, northing, elevation[, description] (PENZD).
enum class SurveyColumns { kHeader, kPNEZD, kPENZD };

// A rover-surveyed wall point's horizontal 1σ per axis (m) when neither the survey file nor
// survey.point_sigma_m gives one: an RTK fix held on a pole for a few seconds.
inline constexpr double kDefaultRoverPointSigmaM = 0.010;
// The 1σ of a tape-measured scanner height (scanner.z_sigma_m), of a scanner tilt taken from an
// inclinometer or the drawings (scanner.tilt_sigma_deg: 0.2°), and of one attitude sample's
// roll and pitch where the stream gives none (attitude.sigma_deg: 0.1°).
inline constexpr double kDefaultScannerZSigmaM = 0.02;
inline constexpr double kDefaultScannerTiltSigmaRad = 0.2 * 3.14159265358979323846 / 180.0;
inline constexpr double kDefaultAttitudeSigmaRad = 0.1 * 3.14159265358979323846 / 180.0;

// A survey point whose WGS84 position RTK-GNSS also measured.
struct ControlPoint {
  std::string id;
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double h_m = 0.0;  // ellipsoidal height
  int line = 0;      // line in session.yaml
};

struct WallSpec {
  std::string id;
  std::string code;  // survey points with this code lie on the wall
};

struct UtmZone {
  int zone = 0;  // 1..60
  bool north = true;
};

enum class HeadingReference { kTrueNorth, kGridNorth };

// A rough mount (tape measure) to centre the wall detector's gates. Optional in the session.
// With a tolerance it is also a gross-error check: an estimate farther from the guess than
// tolerance_m in x or y, or tolerance_yaw_rad in yaw, is refused (pipeline/checks.h).
struct MountGuess {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
  std::optional<double> tolerance_m;        // > 0 when given
  std::optional<double> tolerance_yaw_rad;  // > 0 when given
};

// Antenna position in the vehicle's base_link frame, when the session gives it.
struct AntennaInBase {
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.0;
};

// session.yaml, with every path resolved against the session folder.
// Which time a message from a recording is stamped with (session.yaml `stamp:`): the message's
// header.stamp (the sensor driver's time; default), or the recorder's receive time.
enum class StampSource { kHeader, kReceive };

// Largest horizontal σ (m) of a sensor_msgs/NavSatFix accepted as a fix (gnss.max_sigma_m):
// NavSatFix cannot tell RTK fixed from float, so the covariance decides. 5 cm keeps RTK fixed
// (1-2 cm) and drops float (typically 0.1-1 m).
inline constexpr double kDefaultGnssMaxSigmaM = 0.05;

// One scanner of a session that lists several (session.yaml `scanners:`): the keys of
// `scanner:` plus its id and the frame its transform is published under.
// The scanner's own tilt on the vehicle (session.yaml scanner.pitch_deg, roll_deg,
// tilt_sigma_deg; from an inclinometer or the drawings): pitch positive nose up, roll positive
// right side down (rad). Not given: level, with that σ.
struct ScannerTilt {
  double pitch_rad = 0.0;
  double roll_rad = 0.0;
  double sigma_rad = kDefaultScannerTiltSigmaRad;  // 1σ of each
  bool given = false;  // pitch_deg or roll_deg is in session.yaml
};

struct ScannerSpec {
  std::string id;     // unique in the session
  std::string frame;  // the child frame of its transform; the id unless `frame:` is given
  int line = 0;       // the list item's line in session.yaml
  std::string model;
  std::string log;    // resolved path
  double time_offset_s = 0.0;
  std::string topic;  // the LaserScan topic when log is a recording
  StampSource stamp = StampSource::kHeader;
  std::optional<MountGuess> mount_guess;
  std::optional<double> z_m;
  double z_sigma_m = kDefaultScannerZSigmaM;
  ScannerTilt tilt;
};

struct SessionSpec {
  std::string file;  // path of session.yaml
  std::string dir;   // its folder
  std::string name;
  std::optional<UtmZone> utm_zone;
  // The id of the `scanners:` entry this one-scanner session was made from
  // (io::SessionForScanner); empty for a one-scanner session.yaml.
  std::string scanner_id;

  std::string scanner_model;
  std::string scanner_log;       // resolved path
  double scanner_time_offset_s = 0.0;  // added to every scan time
  // scanner.topic: the sensor_msgs/LaserScan topic when scanner_log is a recording ("" for a
  // text log); likewise gnss_topic and heading_topic. The log is told apart by content
  // (recording::IsRecording), not by this key.
  std::string scanner_topic;
  StampSource scanner_stamp = StampSource::kHeader;
  std::optional<MountGuess> mount_guess;
  // Height of the scanner's origin relative to the GNSS antenna (m, up +: a scanner below the
  // antenna is negative), measured by hand: the 2-D calibration cannot see it. Unset: the
  // emitted transforms carry z = 0 and say so.
  std::optional<double> scanner_z_m;
  double scanner_z_sigma_m = kDefaultScannerZSigmaM;  // scanner.z_sigma_m: the tape's 1σ
  ScannerTilt scanner_tilt;

  std::string gnss_log;
  int min_fix_quality = 4;  // 4 = RTK fixed only; 5 also accepts float
  std::string gnss_topic;   // NavSatFix or nmea_msgs/Sentence
  StampSource gnss_stamp = StampSource::kHeader;
  double gnss_max_sigma_m = kDefaultGnssMaxSigmaM;  // NavSatFix only

  std::string heading_log;
  HeadingReference heading_reference = HeadingReference::kTrueNorth;
  std::string heading_topic;  // QuaternionStamped, Imu or nmea_msgs/Sentence
  StampSource heading_stamp = StampSource::kHeader;

  // attitude: the vehicle's roll and pitch stream (attitude.log: a text log with $PASHR or
  // $PTNL,AVR sentences, which may be the heading log, or a recording with attitude.topic, a
  // sensor_msgs/Imu topic); empty: none (the yard is estimated from the GNSS heights).
  std::string attitude_log;
  std::string attitude_topic;
  StampSource attitude_stamp = StampSource::kHeader;
  double attitude_time_offset_s = 0.0;  // added to every attitude sample's time
  // attitude.sigma_deg: the 1σ of one sample of roll and of pitch where the stream gives none.
  double attitude_sigma_rad = kDefaultAttitudeSigmaRad;

  std::string survey_points;  // resolved path
  SurveyColumns survey_columns = SurveyColumns::kHeader;  // CSV only; a GSI file is recognised
  std::vector<ControlPoint> control;  // empty for a rover survey (no tie)
  std::optional<double> survey_rotation_rad;  // Barawid 2007 Eq. 4-5 rotation, single control point
  // survey.point_sigma_m: a rover point's horizontal 1σ per axis (m) where the survey file
  // gives none; unset: kDefaultRoverPointSigmaM. Applies to rover (geodetic) surveys only.
  std::optional<double> survey_point_sigma_m;

  std::vector<WallSpec> walls;
  std::optional<AntennaInBase> antenna_in_base;

  // `scanners:` (several scanners on the vehicle), in the order listed; empty for a session
  // with one `scanner:` (the scanner_* fields above). io::SessionForScanner gives the
  // one-scanner session of each.
  std::vector<ScannerSpec> scanners;
};

// A scanner preset from configs/scanners/NAME.yaml.
struct ScannerPreset {
  std::string name;
  int num_beams = 0;
  double start_angle_rad = 0.0;   // bearing of beam 0
  double angular_step_rad = 0.0;  // ccw step between beams
  double rate_hz = 0.0;           // scans per second
  double min_range_m = 0.0;       // below: no valid reading
  double max_range_m = 0.0;       // at or above: no return
  double error_codes_below_m = 0.0;  // readings below this are error codes (URG: 0.020 m)
  bool max_range_is_no_return = true;  // SICK reports no-return as its maximum
  double range_resolution_m = 0.001;   // quantisation of the logged range
  // Range correction applied by the tool: corrected = k * raw + b (Ye & Borenstein 2002; Okubo, Ye & Borenstein 2009).
  double range_scale_k = 1.0;
  double range_offset_b_m = 0.0;
  // How far the unit a session uses may be off that correction (1σ): its range scale
  // (dimensionless, a relative error of every range) and its range offset (m). A family preset
  // states the family's spread, a preset `characterise` measured on one unit its fit's σ;
  // 0: the unit's model taken as exact. Only the joint adjustment of several scanners carries
  // them (pipeline/multi_scanner.h).
  double range_scale_sigma = 0.0;
  double range_offset_sigma_m = 0.0;
  // Simulation model z = Int(n * true + c + xi), xi ~ N(0, sigma) (Ye & Borenstein 2002; Okubo, Ye & Borenstein 2009).
  double sim_scale_n = 1.0;
  double sim_offset_c_m = 0.0;
  double range_sigma_m = 0.005;
  double max_incidence_rad = 1.3;  // beyond this incidence the simulator drops returns
  std::string source;              // citation for the numbers
  std::string file;                // the file it was read from (set by ReadScannerPreset)
};

// One input file of a calibration, for the provenance of offsets.yaml.
struct InputFileDigest {
  std::string role;    // "session", "scanner_log", "gnss_log", ...
  std::string path;    // as the run opened it
  std::string sha256;  // 64 lowercase hex digits; empty when the file could not be read
};

// The output document: offsets.yaml. Filled by the application from the solver's result.
struct OffsetsDocument {
  std::string parent_frame = "gnss_antenna";
  std::string child_frame = "laser";
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
  double covariance[9] = {0};  // row-major, order x, y, yaw (m, m, rad)
  bool sigma_known = true;     // false: stddev and covariance are written as null
  std::string method;          // "ceres" or "barawid"
  // quality: ordered key/value lines, numbers already formatted by the writer's caller.
  int64_t scans_total = 0;
  int64_t scans_used = 0;
  double heading_min_deg = 0.0;  // grid headings at which the wall was used
  double heading_max_deg = 0.0;
  double residual_rms_m = 0.0;
  std::vector<std::pair<std::string, std::string>> quality_extra;  // more quality keys
  std::vector<std::string> warnings;
  // More top-level keys (verdict, error budget, change since the previous calibration) with
  // their values already formatted as YAML (flow style), written after `quality:`.
  std::vector<std::pair<std::string, std::string>> sections;
  // Provenance (`source:`): what produced this file, when, and from which inputs.
  std::string session;
  std::string tool_version;
  std::string created_utc;             // ISO 8601, e.g. 2025-05-12T06:32:02Z
  std::vector<std::string> command_line;  // argv as given
  std::vector<InputFileDigest> inputs;
};

// The parts of an earlier offsets.yaml that `calibrate --compare` reads.
struct PreviousOffsets {
  std::string file;
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
  bool sigma_known = false;  // its covariance was written (not null)
  double covariance[9] = {0};
  std::string created_utc;  // empty when the file does not say
};

// An earlier offsets.yaml as `calibrate --compare` of a session with several scanners reads it:
// each scanner's mount by id and each relative transform by (from, to). A one-scanner file
// (`scanner_mount:`) gives one scanner whose id is its child_frame (`laser` when not written),
// matched against the scanners' frames.
struct PreviousScannerOffsets {
  std::string id;
  PreviousOffsets offsets;
};
struct PreviousRelativeOffsets {
  std::string from_id, to_id;
  PreviousOffsets offsets;  // the pose of `to` in the frame of `from`
};
struct PreviousSeveralOffsets {
  std::string file;
  std::string created_utc;  // empty when the file does not say
  bool several = false;     // scanner_mounts: (false: one scanner_mount, matched by frame)
  std::vector<PreviousScannerOffsets> scanners;  // in the file's order
  std::vector<PreviousRelativeOffsets> relative;
};

}  // namespace wallcal::io
