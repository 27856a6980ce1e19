// SPDX-License-Identifier: Apache-2.0
#include "recording/recording_streams.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <map>
#include <set>

#include "common/angles.h"
#include "io/scanner_geometry.h"
#include "io/text/carmen_reader.h"
#include "io/text/nmea_reader.h"
#include "recording/attitude_stream.h"
#include "recording/internal/stream_decoding.h"
#include "recording/recording_tail.h"

namespace wallcal::recording {

int LineOf(int64_t index) { return static_cast<int>(std::min<int64_t>(index + 1, INT_MAX)); }

std::string Describe(const RecordedMessage& m) {
  return "topic " + m.topic->name + " message " + std::to_string(m.index + 1);
}

void Require(const DecodeResult& result, const Recording& recording, const RecordedMessage& m,
             RosType type) {
  if (result.ok()) return;
  const char* why = result.failure == DecodeFailure::kTooShort    ? "message shorter than its type"
                    : result.failure == DecodeFailure::kBadLength ? "string without its NUL"
                    : result.failure == DecodeFailure::kBadEncapsulation
                        ? "unknown CDR encapsulation"
                        : "bytes after the last field";
  throw io::InputError(io::Where(recording.path(), 0,
                                 Describe(m) + " (byte " + std::to_string(result.offset) + " of " +
                                     std::to_string(m.size) + "): " + why + " (" + result.detail +
                                     "); expected a whole " + RosTypeName(type)));
}

double StampOf(const RosHeader& header, const RecordedMessage& m, io::StampSource stamp) {
  return stamp == io::StampSource::kReceive ? m.receive_s : header.stamp_s;
}

TailTopics::TailTopics(const RecordingTail& tail) : format_(tail.format()) {
  path_ = tail.path();
  for (const auto& [name, topic] : tail.topics()) topics_.push_back(topic);
}

namespace {

std::string TypeList(const std::vector<RosType>& types) {
  std::string text;
  for (size_t i = 0; i < types.size(); ++i) {
    text += (i == 0 ? "" : i + 1 == types.size() ? " or " : ", ");
    text += RosTypeName(types[i]);
  }
  return text;
}

// The streams of a session that one recording holds (null: not in it).
struct RecordedStreams {
  const TopicStream* gnss = nullptr;
  const TopicStream* heading = nullptr;
  const TopicStream* attitude = nullptr;
};

// Reads the streams `which` names from one recording, in one pass over their topics.
void ReadRecordedPoses(const std::string& path, const RecordedStreams& which, double max_sigma_m,
                       PoseLogs* out) {
  std::unique_ptr<Recording> recording = OpenRecording(path);
  PoseDecoder decoder(path, which.gnss, which.heading, max_sigma_m, which.attitude);
  decoder.CheckTopics(*recording);
  recording->ForEach(decoder.topics(),
                     [&](const RecordedMessage& m) { decoder.Take(m, *recording); });
  decoder.AddTo(out);
  for (const std::string& w : recording->warnings()) out->warnings.push_back(w);
}

// A session's attitude stream that gave no sample: the attitude log or topic named, with the
// skips that emptied it.
void RequireAttitudeSamples(const io::SessionSpec& spec, const io::NmeaLog& attitudes,
                            bool recorded) {
  if (!attitudes.attitudes.empty()) return;
  const std::string skips = attitudes.skipped.ListReasons(false, 6);
  const std::string read = std::to_string(attitudes.lines_read) +
                           (skips.empty() ? std::string() : "; skipped: " + skips);
  throw io::InputError(io::Where(
      spec.attitude_log, 0,
      recorded
          ? "attitude.topic " + spec.attitude_topic + ": no attitude sample (messages: " + read +
                "); expected sensor_msgs/Imu messages with the vehicle's orientation (x forward, y "
                "left, z up: roll and pitch within ±30°), or nmea_msgs/Sentence with $PASHR "
                "or $PTNL,AVR"
          : "attitude.log: no attitude sample (lines read: " + read +
                "); expected $PASHR or $PTNL,AVR sentences with roll and pitch, e.g. "
                "$PASHR,hhmmss.ss,heading,T,roll,pitch,...*hh"));
}

// Scans of a recording, decoded once and replayed for every pass.
class ReplayedScans : public io::ScanSource {
 public:
  ReplayedScans(std::shared_ptr<const std::vector<io::ScanRecord>> scans, std::string path)
      : scans_(std::move(scans)), path_(std::move(path)) {}
  bool Next(io::ScanRecord* scan) override {
    if (next_ >= scans_->size()) return false;
    *scan = (*scans_)[next_++];
    return true;
  }
  const io::SkipCounts& skipped() const override { return skipped_; }
  int64_t scans_read() const override { return static_cast<int64_t>(next_); }
  const std::string& path() const override { return path_; }

 private:
  std::shared_ptr<const std::vector<io::ScanRecord>> scans_;
  std::string path_;
  io::SkipCounts skipped_;
  size_t next_ = 0;
};

// Why a LaserScan message comes from another scanner than the preset's; "" when its geometry
// is the preset's or within the family's limits (io/scanner_geometry.h).
std::string PresetMismatch(const LaserScanMsg& msg, const io::ScannerPreset& preset) {
  const io::GeometryCheck check = io::CheckScanGeometry(
      static_cast<int64_t>(msg.ranges_m.size()), msg.angle_increment_rad, msg.range_max_m, preset);
  return check.fit == io::GeometryFit::kOtherScanner ? check.what : std::string();
}

// One LaserScan message as a scan, checked against `preset` when not null.
io::ScanRecord DecodeScan(const RecordedMessage& m, const Recording& recording, RosType type,
                          const io::SessionSpec& spec, const io::ScannerPreset* preset,
                          LaserScanMsg* msg) {
  Require(DecodeLaserScan(m.data, m.size, m.wire, msg), recording, m, type);
  if (preset != nullptr) {
    if (const std::string why = PresetMismatch(*msg, *preset); !why.empty()) {
      throw io::InputError(
          io::Where(spec.scanner_log, 0,
                    Describe(m) + ": " + why +
                        "; expected the scanner.model preset to match the scanner "
                        "(pick another preset or write one)"));
    }
  }
  return ScanFromLaserScan(*msg, StampOf(msg->header, m, spec.scanner_stamp), LineOf(m.index));
}

std::vector<io::ScanRecord> ReadRecordedScans(const io::SessionSpec& spec,
                                              const io::ScannerPreset* preset) {
  std::unique_ptr<Recording> recording = OpenRecording(spec.scanner_log);
  const RosType type =
      CheckTopic(*recording, spec.scanner_topic, AcceptedScanTypes(), "scanner.topic");
  std::vector<io::ScanRecord> scans;
  LaserScanMsg msg;
  recording->ForEach({spec.scanner_topic}, [&](const RecordedMessage& m) {
    scans.push_back(DecodeScan(m, *recording, type, spec, preset, &msg));
  });
  return scans;
}

}  // namespace

void RequireNoTopic(const std::string& topic, const std::string& log, const std::string& key) {
  if (topic.empty()) return;
  throw io::InputError(
      io::Where(log, 0,
                key + " '" + topic +
                    "' given, but this is a text log, not a recording; expected a ROS 1 "
                    "bag, an MCAP file or a rosbag2 .db3 / folder"));
}

std::vector<RosType> AcceptedScanTypes() { return {RosType::kLaserScan}; }
std::vector<RosType> AcceptedGnssTypes() { return {RosType::kNavSatFix, RosType::kNmeaSentence}; }
std::vector<RosType> AcceptedHeadingTypes() {
  return {RosType::kQuaternionStamped, RosType::kImu, RosType::kNmeaSentence};
}

RosType CheckTopic(const Recording& recording, const std::string& topic,
                   const std::vector<RosType>& accepted, const std::string& key) {
  const TopicInfo* found = nullptr;
  for (const TopicInfo& info : recording.topics()) {
    if (info.name == topic) found = &info;
  }
  if (found == nullptr) {
    std::string present;
    for (const TopicInfo& info : recording.topics()) {
      present += (present.empty() ? "" : ", ") + info.name + " (" + info.type + ")";
    }
    throw io::InputError(
        io::Where(recording.path(), 0,
                  (topic.empty() ? key + " is missing" : key + ": no topic '" + topic + "'") +
                      "; expected a topic of type " + TypeList(accepted) + "; the recording has " +
                      (present.empty() ? std::string("no topics") : present)));
  }
  const RosType type = RosTypeFromName(found->type);
  const bool type_ok = std::find(accepted.begin(), accepted.end(), type) != accepted.end();
  if (!type_ok) {
    throw io::InputError(io::Where(recording.path(), 0,
                                   key + ": topic " + topic + " has type " + found->type +
                                       "; expected " + TypeList(accepted)));
  }
  if (!found->md5sum.empty() && found->md5sum != "*" && found->md5sum != RosTypeMd5(type)) {
    throw io::InputError(io::Where(recording.path(), 0,
                                   key + ": topic " + topic + " has type " + found->type +
                                       " with md5sum " + found->md5sum + "; expected " +
                                       RosTypeMd5(type) + " (another definition of the type)"));
  }
  return type;
}

io::ScanRecord ScanFromLaserScan(const LaserScanMsg& msg, double stamp_s, int line) {
  io::ScanRecord scan;
  scan.stamp_s = stamp_s;
  scan.start_angle_rad = msg.angle_min_rad;
  scan.angular_step_rad = msg.angle_increment_rad;
  scan.max_range_m = msg.range_max_m;
  scan.line = line;
  scan.ranges_m = msg.ranges_m;
  for (float& r : scan.ranges_m) {
    if (!std::isfinite(r) || r < msg.range_min_m || r > msg.range_max_m) r = msg.range_max_m;
  }
  return scan;
}

io::GnssFix FixFromNavSatFix(const NavSatFixMsg& msg, double stamp_s, double max_sigma_m,
                             int line) {
  io::GnssFix fix;
  fix.stamp_s = stamp_s;
  fix.lat_deg = msg.latitude_deg;
  fix.lon_deg = msg.longitude_deg;
  fix.height_m = msg.altitude_m;
  fix.line = line;
  const bool position_ok = std::isfinite(msg.latitude_deg) && std::isfinite(msg.longitude_deg) &&
                           std::abs(msg.latitude_deg) <= 90.0 &&
                           std::abs(msg.longitude_deg) <= 180.0 && std::isfinite(msg.altitude_m);
  if (msg.status < 0 || !position_ok) {
    fix.quality = 0;
    return fix;
  }
  if (msg.position_covariance_type == 0) {
    fix.quality = 4;  // nothing to judge by: accepted, with the caller's warning
    return fix;
  }
  const double var_east = msg.position_covariance[0], var_north = msg.position_covariance[4];
  fix.sigma_lon_m = var_east >= 0 ? std::sqrt(var_east) : io::kNaN;
  fix.sigma_lat_m = var_north >= 0 ? std::sqrt(var_north) : io::kNaN;
  const double sigma_m = std::sqrt(std::max(var_east, var_north));
  fix.quality = std::isfinite(sigma_m) && sigma_m <= max_sigma_m ? 4 : 1;
  return fix;
}

double HeadingFromEnuQuaternion(double x, double y, double z, double w) {
  const double yaw = std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
  return WrapTwoPi(HeadingFromYaw(yaw));  // the grid heading of an ENU yaw
}

PoseLogs ReadPoseLogs(const io::SessionSpec& spec, bool read_gnss, bool read_heading,
                      bool read_attitude) {
  PoseLogs out;
  read_attitude = read_attitude && !spec.attitude_log.empty();
  const bool gnss_recorded = read_gnss && IsRecording(spec.gnss_log);
  const bool heading_recorded = read_heading && IsRecording(spec.heading_log);
  const bool attitude_recorded = read_attitude && IsRecording(spec.attitude_log);
  if (read_gnss && !gnss_recorded) {
    RequireNoTopic(spec.gnss_topic, spec.gnss_log, "gnss.topic");
    out.gnss = io::ReadNmea(spec.gnss_log);
  }
  if (read_heading && !heading_recorded) {
    RequireNoTopic(spec.heading_topic, spec.heading_log, "heading.topic");
    out.headings = (read_gnss && !gnss_recorded && spec.heading_log == spec.gnss_log)
                       ? out.gnss
                       : io::ReadNmea(spec.heading_log);
  }
  if (read_attitude && !attitude_recorded) {
    RequireNoTopic(spec.attitude_topic, spec.attitude_log, "attitude.topic");
    const double offset_s = spec.attitude_time_offset_s;
    if (read_heading && !heading_recorded && spec.attitude_log == spec.heading_log) {
      out.attitudes = AttitudeStreamOf(out.headings, offset_s);  // one log read once
    } else if (read_gnss && !gnss_recorded && spec.attitude_log == spec.gnss_log) {
      out.attitudes = AttitudeStreamOf(out.gnss, offset_s);
    } else {
      out.attitudes = AttitudeStreamOf(io::ReadNmea(spec.attitude_log), offset_s);
    }
  }
  // The recorded streams, each recording read once for all the streams it holds.
  const TopicStream gnss{spec.gnss_topic, spec.gnss_stamp, RosType::kOther, 0.0};
  const TopicStream heading{spec.heading_topic, spec.heading_stamp, RosType::kOther, 0.0};
  const TopicStream attitude{spec.attitude_topic, spec.attitude_stamp, RosType::kOther,
                             spec.attitude_time_offset_s};
  std::map<std::string, RecordedStreams> recordings;
  if (gnss_recorded) recordings[spec.gnss_log].gnss = &gnss;
  if (heading_recorded) recordings[spec.heading_log].heading = &heading;
  if (attitude_recorded) recordings[spec.attitude_log].attitude = &attitude;
  for (const auto& [path, which] : recordings) {
    ReadRecordedPoses(path, which, spec.gnss_max_sigma_m, &out);
  }
  if (read_attitude) RequireAttitudeSamples(spec, out.attitudes, attitude_recorded);
  return out;
}

ScanOpener MakeScanOpener(const io::SessionSpec& spec, const io::ScannerPreset* preset) {
  if (!IsRecording(spec.scanner_log)) {
    RequireNoTopic(spec.scanner_topic, spec.scanner_log, "scanner.topic");
    const std::string log = spec.scanner_log;
    return [log]() -> std::unique_ptr<io::ScanSource> {
      return std::make_unique<io::CarmenReader>(log);
    };
  }
  auto cache = std::make_shared<std::shared_ptr<const std::vector<io::ScanRecord>>>();
  return [spec, preset, cache]() -> std::unique_ptr<io::ScanSource> {
    if (!*cache) {
      *cache = std::make_shared<const std::vector<io::ScanRecord>>(ReadRecordedScans(spec, preset));
    }
    return std::make_unique<ReplayedScans>(*cache, spec.scanner_log);
  };
}

ScanTail::ScanTail(const io::SessionSpec& spec, const io::ScannerPreset* preset)
    : spec_(spec), preset_(preset), tail_(OpenRecordingTail(spec.scanner_log)) {
  if (!tail_) {
    throw io::InputError(io::Where(
        spec.scanner_log, 0,
        "not read on as it grows; expected a ROS 1 bag, an MCAP file, a .db3 file or a rosbag2 "
        "folder"));
  }
}

ScanTail::~ScanTail() = default;

bool ScanTail::Supports(const std::string& path) {
  return OpenRecordingTail(path) != nullptr;
}

TailRead ScanTail::ReadOn(std::vector<io::ScanRecord>* scans) {
  const std::map<std::string, TopicInfo>& topics = tail_->topics();
  RosType type = RosType::kOther;
  std::unique_ptr<TailTopics> seen;  // the topics met, once the first message comes
  LaserScanMsg msg;
  const TailRead read = tail_->ReadOn({spec_.scanner_topic}, [&](const RecordedMessage& m) {
    if (!seen) {
      seen = std::make_unique<TailTopics>(*tail_);
      type = CheckTopic(*seen, spec_.scanner_topic, AcceptedScanTypes(), "scanner.topic");
    }
    scans->push_back(DecodeScan(m, *seen, type, spec_, preset_, &msg));
  });
  if (read.messages == 0 && topics.count(spec_.scanner_topic) > 0) {
    // A topic of the wrong type is named now, not when its first message comes.
    CheckTopic(TailTopics(*tail_), spec_.scanner_topic, AcceptedScanTypes(), "scanner.topic");
  }
  return read;
}

}  // namespace wallcal::recording
