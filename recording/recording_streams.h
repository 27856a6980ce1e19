// SPDX-License-Identifier: Apache-2.0
#pragma once
// A session's streams (scans, GNSS, heading, attitude) whatever holds them: the text logs of old
// (CARMEN, NMEA), or topics of a robot recording (ROS 1 bag, MCAP, rosbag2), told apart by content
// (recording::IsRecording). Recorded messages become the plain records of io/types.h, so everything
// downstream (time model, clock offset, detection) is the same for both.
//
// Messages -> records (line = the message's 1-based index on its topic, so errors name it):
// - sensor_msgs/LaserScan -> io::ScanRecord: bearings angle_min + i·angle_increment (a negative
//   increment, an upside-down scanner, is kept as is); max_range_m = range_max; a range that is
//   NaN, ±inf or outside [range_min, range_max] is written as range_max, which the range model
//   (calib/range_model.cc) counts as "no return", as it does a CARMEN reading at the maximum.
// - sensor_msgs/NavSatFix -> io::GnssFix: height_m = altitude; sigma_lat_m / sigma_lon_m from the
//   ENU position_covariance (north, east variances). NavSatFix cannot tell RTK fixed from float,
//   so a fix is accepted by its horizontal σ = sqrt(max(var_east, var_north)) <=
//   gnss.max_sigma_m and status >= 0. To keep the counts and gnss.min_fix_quality of the NMEA
//   path meaningful, accepted fixes carry quality 4 (RTK fixed) and refused ones quality 1
//   (never accepted); status -1 (no fix) is skipped as "NavSatFix without a fix". A topic with
//   no covariance (type 0) accepts every fix with status >= 0, with a warning that float fixes
//   cannot be told apart.
// - nmea_msgs/Sentence: each sentence goes through the NMEA text reader (io::ParseNmea) as a
//   logger-stamped line "<stamp> <sentence>", so every sentence it takes (GGA+GST, HDT, THS)
//   works and gnss.min_fix_quality applies.
// - geometry_msgs/QuaternionStamped, sensor_msgs/Imu -> io::HeadingSample: ENU yaw (REP 103: 0 =
//   east, counter-clockwise) -> heading clockwise from north = π/2 − yaw, in [0, 2π);
//   heading.reference says which north. An Imu with orientation_covariance[0] = -1 (no
//   orientation) is skipped.
// - sensor_msgs/Imu (attitude.topic) -> io::AttitudeSample: recording/attitude_stream.h.
// Stamps: header.stamp, or the receive time with `stamp: receive`.
//
// Errors (io::InputError, exit 2): a topic not in the recording (the topics present are listed), a
// topic of another type (found and accepted types named; ROS 1 also checks the md5sum), a
// message that does not decode (file, topic, message index, byte offset), a scanner preset
// that does not match the LaserScan messages (beam count, increment, range_max: both named).

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "io/scan_source.h"
#include "io/types.h"
#include "recording/recording.h"
#include "recording/recording_tail.h"
#include "recording/ros/ros_messages.h"

namespace wallcal::recording {

// The types a session stream takes from a recording.
std::vector<RosType> AcceptedScanTypes();     // LaserScan
std::vector<RosType> AcceptedGnssTypes();     // NavSatFix, nmea_msgs/Sentence
std::vector<RosType> AcceptedHeadingTypes();  // QuaternionStamped, Imu, nmea_msgs/Sentence

// Checks that `topic` is in the recording and carries one of `accepted` (by name; in a ROS 1
// bag also by md5sum). `key` names the session key in messages ("gnss.topic"). Returns the
// type. Throws io::InputError naming the file, the topic, the type found and the types accepted,
// or listing the topics present when it is missing (an empty `topic` too).
RosType CheckTopic(const Recording& recording, const std::string& topic,
                   const std::vector<RosType>& accepted, const std::string& key);

// The GNSS, heading and attitude streams of a session. From text logs: io::ReadNmea, each file
// once (the attitude sentences of the heading or GNSS log come from that log's one read). From
// a recording: its topics in one pass (one ForEach). `warnings`: what the recording reader
// worked around, NavSatFix without covariance.
struct PoseLogs {
  io::NmeaLog gnss;      // fixes (and fixes_by_quality)
  io::NmeaLog headings;  // headings
  // The attitude stream (recording/attitude_stream.h): attitudes with attitude.time_offset_s
  // added; skipped and lines_read are its log's (the whole heading log's when it is that log),
  // or its topic's. Empty when the session names no attitude stream.
  io::NmeaLog attitudes;
  std::vector<std::string> warnings;
};
// `gnss` / `heading` / `attitude` false: that stream is not read (left empty). Throws
// io::InputError as the readers do, and when the session names an attitude stream that gives
// no sample (a text log without a $PASHR or $PTNL,AVR sentence that could be read, a topic
// without a usable message; its skips named).
PoseLogs ReadPoseLogs(const io::SessionSpec& spec, bool gnss = true, bool heading = true,
                      bool attitude = true);

// For a log that is not a recording: throws io::InputError when its session key `key`
// ("gnss.topic") names a topic all the same; nothing when `topic` is empty.
void RequireNoTopic(const std::string& topic, const std::string& log, const std::string& key);

// Opens the session's scans as fresh streams, one per call (a detection pass each). A text log:
// a io::CarmenReader each time. A recording: the LaserScan topic is decoded once, on the first
// call, and checked against `preset` (when not null: it must outlive the opener); later calls
// replay it from memory. The returned function throws io::InputError as the readers do.
using ScanOpener = std::function<std::unique_ptr<io::ScanSource>()>;
ScanOpener MakeScanOpener(const io::SessionSpec& spec, const io::ScannerPreset* preset);

// One LaserScan message as a io::ScanRecord (see above); `line` = index + 1.
io::ScanRecord ScanFromLaserScan(const LaserScanMsg& msg, double stamp_s, int line);
// One NavSatFix as a io::GnssFix (quality 4 or 1 as above; status -1 gives quality 0).
io::GnssFix FixFromNavSatFix(const NavSatFixMsg& msg, double stamp_s, double max_sigma_m, int line);
// Heading clockwise from north, [0, 2π), of an ENU orientation quaternion.
double HeadingFromEnuQuaternion(double x, double y, double z, double w);

// The LaserScan topic of a ROS 1 bag, an MCAP file, a .db3 file or a rosbag2 folder still being
// written, decoded as it grows (recording/recording_tail.h): each read decodes only the scans of
// the whole records added since the last one. Scans come in receive-time order within a chunk,
// file order across chunks and storage files; ScanRecord::line = the message's index on the
// topic + 1, as MakeScanOpener gives.
class ScanTail {
 public:
  // `preset`, when not null, is checked against every scan and must outlive this. Throws
  // io::InputError when spec.scanner_log is not such a file (Supports).
  ScanTail(const io::SessionSpec& spec, const io::ScannerPreset* preset);
  ~ScanTail();
  ScanTail(const ScanTail&) = delete;
  ScanTail& operator=(const ScanTail&) = delete;

  // True for a ROS 1 bag, an MCAP file, a .db3 file or a rosbag2 folder (not a text log).
  static bool Supports(const std::string& path);

  // Appends the scans the recording gained to *scans. TailRead::restarted: the file shrank and
  // was read from its start (the caller drops what it kept). Throws io::InputError as
  // MakeScanOpener's sources do (a topic of another type, a message that does not decode, a
  // preset that does not match) and for a damaged record (RecordingTail).
  TailRead ReadOn(std::vector<io::ScanRecord>* scans);

 private:
  io::SessionSpec spec_;
  const io::ScannerPreset* preset_;
  std::unique_ptr<RecordingTail> tail_;
};

// The GNSS and heading topics of a session's recordings (ROS 1 bag, MCAP, .db3, rosbag2 folder)
// read on as they grow (recording/recording_tail.h): each read decodes only the messages of the
// whole records gained since the last one, with the decoders' state carried over (the last
// stamps of the "time not increasing" check, the NMEA reader's state for nmea_msgs/Sentence
// topics), so that the logs returned are those ReadPoseLogs returns for the recordings as they
// are now, but for its warnings: only the decoders' own (a NavSatFix topic without covariance)
// are given, not the container readers' (no index, no summary, no metadata.yaml), which a
// recording still being written always earns. Messages come in the order of ScanTail's.
class PoseTail {
 public:
  // `gnss` / `heading`: that stream is in a recording (IsRecording of its log) and is read, as
  // for ReadPoseLogs; one RecordingTail for both when they share the recording. Reads nothing
  // yet. Throws io::InputError for a log that is not a recording.
  PoseTail(const io::SessionSpec& spec, bool gnss, bool heading);
  ~PoseTail();
  PoseTail(const PoseTail&) = delete;
  PoseTail& operator=(const PoseTail&) = delete;

  // Reads what the recordings gained and returns the streams read so far (a recording read
  // anew, TailRead::restarted, has its stream decoded anew). Throws io::InputError as
  // ReadPoseLogs does (a topic missing or of another type, a message that does not decode:
  // its recording is then read from its start next time) and for a damaged record.
  PoseLogs ReadOn();
  // What the last ReadOn read of the GNSS recording and of the heading recording (the same
  // when they share one; all zero for a stream not read).
  const TailRead& gnss_read() const;
  const TailRead& heading_read() const;

 private:
  struct Source;
  std::vector<std::unique_ptr<Source>> sources_;  // the GNSS recording's first
  size_t heading_source_ = SIZE_MAX;              // the heading recording's place in sources_
};

}  // namespace wallcal::recording
