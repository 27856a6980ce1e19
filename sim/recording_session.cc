// SPDX-License-Identifier: Apache-2.0
#include "sim/recording_session.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <vector>

#include "common/angles.h"
#include "io/config/session_reader.h"
#include "io/output_file.h"
#include "io/text/carmen_reader.h"
#include "io/text/nmea_reader.h"
#include "io/types.h"
#include "io/writers/writers.h"
#include "recording/attitude_stream.h"
#include "recording/recording.h"
#include "recording/ros/ros_messages.h"
#include "recording/writers/mcap_writer.h"
#include "recording/writers/rosbag1_writer.h"
#include "recording/writers/rosbag2_sqlite_writer.h"
#include "sim/simulated_session.h"

namespace wallcal::sim {
namespace {

namespace fs = std::filesystem;

// "sensor_msgs/LaserScan" -> "sensor_msgs/msg/LaserScan" (the ROS 2 name).
std::string Ros2Name(recording::RosType type) {
  const std::string name = recording::RosTypeName(type);
  const size_t slash = name.find('/');
  return name.substr(0, slash) + "/msg" + name.substr(slash);
}

// One recording being written, whatever the container: topics, then messages.
class Sink {
 public:
  virtual ~Sink() = default;
  virtual int Add(const std::string& topic, recording::RosType type) = 0;
  virtual recording::WireFormat wire() const = 0;
  virtual void Write(int id, double stamp_s, const std::vector<uint8_t>& payload) = 0;
  virtual void Close() = 0;
};

class Ros1Sink : public Sink {
 public:
  Ros1Sink(const std::string& path, recording::ChunkCompression c) : writer_(path, c) {}
  int Add(const std::string& topic, recording::RosType type) override {
    return writer_.AddConnection(topic, type);
  }
  recording::WireFormat wire() const override { return recording::WireFormat::kRos1; }
  void Write(int id, double stamp_s, const std::vector<uint8_t>& payload) override {
    writer_.Write(id, stamp_s, payload);
  }
  void Close() override { writer_.Close(); }

 private:
  recording::Ros1BagWriter writer_;
};

class McapSink : public Sink {
 public:
  McapSink(const std::string& path, recording::ChunkCompression c) : writer_(path, c) {}
  int Add(const std::string& topic, recording::RosType type) override {
    return writer_.AddChannel(topic, Ros2Name(type),
                              recording::RosTypeDefinition(type, recording::WireFormat::kCdr));
  }
  recording::WireFormat wire() const override { return recording::WireFormat::kCdr; }
  void Write(int id, double stamp_s, const std::vector<uint8_t>& payload) override {
    writer_.Write(static_cast<uint16_t>(id), stamp_s, stamp_s, payload);
  }
  void Close() override { writer_.Close(); }

 private:
  recording::McapWriter writer_;
};

class Db3Sink : public Sink {
 public:
  explicit Db3Sink(const std::string& path) : writer_(path, recording::Rosbag2Layout::kIron) {}
  int Add(const std::string& topic, recording::RosType type) override {
    return static_cast<int>(writer_.AddTopic(
        topic, Ros2Name(type), recording::RosTypeDefinition(type, recording::WireFormat::kCdr)));
  }
  recording::WireFormat wire() const override { return recording::WireFormat::kCdr; }
  void Write(int id, double stamp_s, const std::vector<uint8_t>& payload) override {
    writer_.Write(id, stamp_s, payload);
  }
  void Close() override { writer_.Close(); }

 private:
  recording::Rosbag2SqliteWriter writer_;
};

std::unique_ptr<Sink> MakeSink(const std::string& dir, SessionFormat format, std::string* name) {
  switch (format) {
    case SessionFormat::kRos1:
    case SessionFormat::kRos1Bz2:
    case SessionFormat::kRos1Lz4: {
      *name = "session.bag";
      const recording::ChunkCompression c =
          format == SessionFormat::kRos1Bz2   ? recording::ChunkCompression::kBz2
          : format == SessionFormat::kRos1Lz4 ? recording::ChunkCompression::kLz4
                                              : recording::ChunkCompression::kNone;
      return std::make_unique<Ros1Sink>((fs::path(dir) / *name).string(), c);
    }
    case SessionFormat::kMcap:
    case SessionFormat::kMcapLz4:
      *name = "session.mcap";
      return std::make_unique<McapSink>((fs::path(dir) / *name).string(),
                                        format == SessionFormat::kMcap
                                            ? recording::ChunkCompression::kZstd
                                            : recording::ChunkCompression::kLz4);
    case SessionFormat::kDb3:
      *name = "session.db3";
      return std::make_unique<Db3Sink>((fs::path(dir) / *name).string());
    case SessionFormat::kText:
      break;
  }
  return nullptr;
}

// An attitude sample as the next sensor_msgs/Imu of /imu/data into *msg (its header seq
// counted on): the orientation from its roll and pitch and the ENU yaw of heading_rad (0 when
// NaN), orientation_covariance diagonal (σ_roll², σ_pitch², 0), a σ not given written as 0 (the
// Imu's "unknown"); no rates or accelerations ([0] = -1: not provided). False for a sample
// without roll or pitch (an AVR gives one of them), which an Imu cannot carry.
bool AttitudeImu(const io::AttitudeSample& sample, double heading_rad,
                 recording::QuaternionMsg* msg) {
  if (!std::isfinite(sample.roll_rad) || !std::isfinite(sample.pitch_rad)) return false;
  const double yaw_rad = std::isfinite(heading_rad) ? YawFromHeading(heading_rad) : 0.0;
  const recording::UnitQuaternion q =
      recording::EnuQuaternionFromAttitude(sample.roll_rad, sample.pitch_rad, yaw_rad);
  msg->header.stamp_s = sample.stamp_s;
  ++msg->header.seq;
  msg->x = q.x;
  msg->y = q.y;
  msg->z = q.z;
  msg->w = q.w;
  auto variance = [](double sigma_rad) {
    return std::isfinite(sigma_rad) ? sigma_rad * sigma_rad : 0.0;
  };
  for (double& c : msg->orientation_covariance) c = 0.0;
  msg->orientation_covariance[0] = variance(sample.roll_sigma_rad);
  msg->orientation_covariance[4] = variance(sample.pitch_sigma_rad);
  for (double& c : msg->angular_velocity_covariance) c = 0.0;
  for (double& c : msg->linear_acceleration_covariance) c = 0.0;
  msg->angular_velocity_covariance[0] = -1.0;
  msg->linear_acceleration_covariance[0] = -1.0;
  return true;
}

// σ written into a NavSatFix when the GGA had no GST: by quality, so that float and autonomous
// fixes stay above gnss.max_sigma_m and fixed ones below it.
double FallbackSigma(int quality) { return quality == 4 ? 0.02 : quality == 5 ? 0.3 : 3.0; }

// The session as read back, each stream's log the recording and its topic set (several
// scanners: scan_topics maps each scanner's old log to its topic), written again through
// io::FormatSessionYaml.
void RewriteSessionYaml(const std::string& dir, const std::string& recording,
                        const std::map<std::string, std::string>& scan_topics) {
  io::SessionSpec session = io::ReadSession(dir);
  const std::string recording_path = (fs::path(dir) / recording).string();
  if (session.scanners.empty()) {
    session.scanner_log = recording_path;
    session.scanner_topic = "/scan";
  }
  for (io::ScannerSpec& scanner : session.scanners) {
    scanner.topic = scan_topics.at(scanner.log);
    scanner.log = recording_path;
  }
  session.gnss_log = recording_path;
  session.gnss_topic = "/fix";
  session.gnss_max_sigma_m = io::kDefaultGnssMaxSigmaM;
  session.heading_log = recording_path;
  session.heading_topic = "/heading";
  if (!session.attitude_log.empty()) {
    session.attitude_log = recording_path;
    session.attitude_topic = "/imu/data";
  }
  io::WriteFileAtomically(session.file, io::FormatSessionYaml(session));
}

}  // namespace

std::optional<SessionFormat> ParseSessionFormat(const std::string& name) {
  if (name == "text") return SessionFormat::kText;
  if (name == "ros1") return SessionFormat::kRos1;
  if (name == "ros1-bz2") return SessionFormat::kRos1Bz2;
  if (name == "ros1-lz4") return SessionFormat::kRos1Lz4;
  if (name == "mcap") return SessionFormat::kMcap;
  if (name == "mcap-lz4") return SessionFormat::kMcapLz4;
  if (name == "db3") return SessionFormat::kDb3;
  return std::nullopt;
}

const char* SessionFormatNames() { return "text, ros1, ros1-bz2, ros1-lz4, mcap, mcap-lz4, db3"; }

void ConvertSessionToRecording(const std::string& dir, SessionFormat format) {
  if (format == SessionFormat::kText) return;
  const std::string scans_path = (fs::path(dir) / "scans.clf").string();
  const std::string gnss_path = (fs::path(dir) / "gnss.nmea").string();
  const std::string heading_path = (fs::path(dir) / "heading.nmea").string();
  std::string name;
  std::unique_ptr<Sink> sink = MakeSink(dir, format, &name);
  const recording::WireFormat wire = sink->wire();
  // The scan streams: /scan from scans.clf, or /<id>/scan from each scanner's scans_<id>.clf.
  struct ScanStream {
    std::string log, topic, frame;
  };
  std::vector<ScanStream> streams;
  const io::SessionSpec session = io::ReadSession(dir);
  std::map<std::string, std::string> scan_topics;
  if (session.scanners.empty()) {
    streams.push_back({scans_path, "/scan", "laser"});
  } else {
    for (const io::ScannerSpec& scanner : session.scanners) {
      streams.push_back({scanner.log, "/" + scanner.id + "/scan", scanner.frame});
      scan_topics[scanner.log] = streams.back().topic;
    }
  }
  std::vector<int> scan_ids;
  for (const ScanStream& stream : streams) {
    scan_ids.push_back(sink->Add(stream.topic, recording::RosType::kLaserScan));
  }
  const int fix_id = sink->Add("/fix", recording::RosType::kNavSatFix);
  const int heading_id = sink->Add("/heading", recording::RosType::kQuaternionStamped);
  // The attitude stream, when the session has one: its samples as sensor_msgs/Imu on
  // /imu/data (AttitudeImu).
  const std::vector<io::AttitudeSample> attitudes =
      session.attitude_log.empty() ? std::vector<io::AttitudeSample>()
                                   : recording::ReadAttitudeLog(session).attitudes;
  const int attitude_id = attitudes.empty() ? -1 : sink->Add("/imu/data", recording::RosType::kImu);
  // The messages in time order, as a recorder writes them: a recording cut short (still being
  // written) then holds every stream up to its cut, not the scans alone.
  const io::NmeaLog gnss = io::ReadNmea(gnss_path);
  const io::NmeaLog headings = io::ReadNmea(heading_path);
  size_t next_fix = 0, next_heading = 0, next_attitude = 0;
  recording::NavSatFixMsg fix_msg;
  fix_msg.header.frame_id = "gps";
  fix_msg.service = 1;
  fix_msg.position_covariance_type = 2;  // diagonal known
  recording::QuaternionMsg heading_msg;
  heading_msg.header.frame_id = "base_link";
  recording::QuaternionMsg imu_msg;
  imu_msg.header.frame_id = "imu_link";
  imu_msg.from_imu = true;
  // Writes the fixes, headings and attitude samples stamped before `until_s`.
  auto write_until = [&](double until_s) {
    while (true) {
      const bool fix_left = next_fix < gnss.fixes.size();
      const bool heading_left = next_heading < headings.headings.size();
      const bool attitude_left = next_attitude < attitudes.size();
      const double fix_s = fix_left ? gnss.fixes[next_fix].stamp_s : until_s;
      const double heading_s = heading_left ? headings.headings[next_heading].stamp_s : until_s;
      const double attitude_s = attitude_left ? attitudes[next_attitude].stamp_s : until_s;
      if (attitude_left && attitude_s < until_s && attitude_s < fix_s && attitude_s < heading_s) {
        const io::AttitudeSample& sample = attitudes[next_attitude++];
        if (!AttitudeImu(sample, HeadingAt(headings.headings, sample.stamp_s), &imu_msg)) continue;
        sink->Write(attitude_id, sample.stamp_s, recording::EncodeImu(imu_msg, wire));
      } else if (fix_left && fix_s < until_s && fix_s <= heading_s) {
        const io::GnssFix& fix = gnss.fixes[next_fix++];
        fix_msg.header.stamp_s = fix.stamp_s;
        ++fix_msg.header.seq;
        fix_msg.status = fix.quality >= 1 ? 2 : -1;
        fix_msg.latitude_deg = fix.lat_deg;
        fix_msg.longitude_deg = fix.lon_deg;
        fix_msg.altitude_m = fix.height_m;
        const double fallback = FallbackSigma(fix.quality);
        const double s_lat = std::isfinite(fix.sigma_lat_m) ? fix.sigma_lat_m : fallback;
        const double s_lon = std::isfinite(fix.sigma_lon_m) ? fix.sigma_lon_m : fallback;
        for (double& c : fix_msg.position_covariance) c = 0.0;
        fix_msg.position_covariance[0] = s_lon * s_lon;
        fix_msg.position_covariance[4] = s_lat * s_lat;
        fix_msg.position_covariance[8] = 4.0 * std::max(s_lat * s_lat, s_lon * s_lon);
        sink->Write(fix_id, fix.stamp_s, recording::EncodeNavSatFix(fix_msg, wire));
      } else if (heading_left && heading_s < until_s) {
        const io::HeadingSample& h = headings.headings[next_heading++];
        heading_msg.header.stamp_s = h.stamp_s;
        ++heading_msg.header.seq;
        const double yaw = YawFromHeading(h.heading_rad);  // ENU yaw (REP 103)
        heading_msg.x = heading_msg.y = 0.0;
        heading_msg.z = std::sin(yaw / 2.0);
        heading_msg.w = std::cos(yaw / 2.0);
        sink->Write(heading_id, h.stamp_s, recording::EncodeQuaternionStamped(heading_msg, wire));
      } else {
        return;
      }
    }
  };
  // Every scan stream's next scan, the earliest written first (with the fixes and headings
  // before it), so that several scanners' scans interleave as a recorder writes them.
  std::vector<std::unique_ptr<io::CarmenReader>> readers;
  std::vector<io::ScanRecord> pending(streams.size());
  std::vector<bool> left(streams.size(), false);
  for (size_t k = 0; k < streams.size(); ++k) {
    readers.push_back(std::make_unique<io::CarmenReader>(streams[k].log));
    left[k] = readers[k]->Next(&pending[k]);
  }
  recording::LaserScanMsg msg;
  std::vector<uint32_t> seq(streams.size(), 0);
  while (true) {
    size_t k = streams.size();
    for (size_t j = 0; j < streams.size(); ++j) {
      if (left[j] && (k == streams.size() || pending[j].stamp_s < pending[k].stamp_s)) k = j;
    }
    if (k == streams.size()) break;
    const io::ScanRecord& scan = pending[k];
    write_until(scan.stamp_s);
    msg.header.frame_id = streams[k].frame;
    msg.header.stamp_s = scan.stamp_s;
    msg.header.seq = ++seq[k];
    msg.angle_min_rad = static_cast<float>(scan.start_angle_rad);
    msg.angle_increment_rad = static_cast<float>(scan.angular_step_rad);
    msg.angle_max_rad = static_cast<float>(
        scan.start_angle_rad +
        scan.angular_step_rad *
            static_cast<double>(scan.ranges_m.size() > 0 ? scan.ranges_m.size() - 1 : 0));
    msg.range_min_m = 0.0f;
    msg.range_max_m = static_cast<float>(scan.max_range_m);
    msg.ranges_m = scan.ranges_m;
    sink->Write(scan_ids[k], scan.stamp_s, recording::EncodeLaserScan(msg, wire));
    left[k] = readers[k]->Next(&pending[k]);
  }
  write_until(std::numeric_limits<double>::infinity());
  sink->Close();
  RewriteSessionYaml(dir, name, scan_topics);
  std::error_code ignored;
  for (const ScanStream& stream : streams) fs::remove(stream.log, ignored);
  for (const std::string& p : {gnss_path, heading_path, session.attitude_log}) {
    if (!p.empty()) fs::remove(p, ignored);
  }
}

SimulateSummary WriteSimulatedSession(const sim::SimulationConfig& config, uint64_t seed,
                                      const std::string& dir, SessionFormat format) {
  const SimulateSummary summary = WriteSimulatedSession(config, seed, dir);
  ConvertSessionToRecording(dir, format);
  return summary;
}

}  // namespace wallcal::sim
