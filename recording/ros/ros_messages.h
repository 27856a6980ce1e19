// SPDX-License-Identifier: Apache-2.0
#pragma once
// The ROS message types wallcal reads from recordings, as plain structs, and their decoders for
// the two wire formats: ROS 1 serialization (little-endian, no alignment, uint32 length before
// strings and variable arrays) and ROS 2 CDR (XCDR1 little/big endian as the 4-byte
// encapsulation header says, fields aligned to their size relative to the end of that header).
// Definitions: sensor_msgs/LaserScan, sensor_msgs/NavSatFix, nmea_msgs/Sentence,
// geometry_msgs/QuaternionStamped, sensor_msgs/Imu (ROS 1 Noetic, ROS 2 Humble and later).
//
// Times: builtin time (ROS 1 uint32 secs + uint32 nsecs; ROS 2 int32 sec + uint32 nanosec) as
// seconds (double) since the epoch of the recording's clock.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace wallcal::recording {

enum class WireFormat { kRos1, kCdr };

// The message types wallcal decodes. Names as ROS 1 writes them ("sensor_msgs/LaserScan");
// ROS 2's "sensor_msgs/msg/LaserScan" maps to the same kind.
enum class RosType { kLaserScan, kNavSatFix, kNmeaSentence, kQuaternionStamped, kImu, kOther };

// "sensor_msgs/LaserScan" or "sensor_msgs/msg/LaserScan" -> kLaserScan; anything else kOther.
RosType RosTypeFromName(std::string_view type_name);
// The ROS 1 name of a supported type ("sensor_msgs/LaserScan"); "" for kOther.
const char* RosTypeName(RosType type);
// The ROS 1 md5sum of a supported type's definition (what a bag's connection header carries);
// "" for kOther.
const char* RosTypeMd5(RosType type);

struct RosHeader {
  uint32_t seq = 0;  // ROS 1 only
  double stamp_s = 0.0;
  std::string frame_id;
};

struct LaserScanMsg {
  RosHeader header;
  float angle_min_rad = 0, angle_max_rad = 0, angle_increment_rad = 0;
  float time_increment_s = 0, scan_time_s = 0;
  float range_min_m = 0, range_max_m = 0;
  std::vector<float> ranges_m;
  std::vector<float> intensities;
};

struct NavSatFixMsg {
  RosHeader header;
  int8_t status = 0;  // -1 no fix, 0 fix, 1 SBAS, 2 GBAS
  uint16_t service = 0;
  double latitude_deg = 0, longitude_deg = 0, altitude_m = 0;  // altitude above the ellipsoid
  double position_covariance[9] = {0};                         // ENU, m², row-major
  uint8_t position_covariance_type = 0;  // 0 unknown, 1 approximated, 2 diagonal known, 3 known
};

struct NmeaSentenceMsg {
  RosHeader header;
  std::string sentence;
};

// Orientation of geometry_msgs/QuaternionStamped, or sensor_msgs/Imu (orientation and the rest
// of the Imu message, so that an Imu re-encodes to the same bytes).
struct QuaternionMsg {
  RosHeader header;
  double x = 0, y = 0, z = 0, w = 1;
  double orientation_covariance[9] = {0};  // Imu only; [0] = -1 means "no orientation"
  bool from_imu = false;                   // set by DecodeImu, cleared by DecodeQuaternionStamped
  // Imu only (zero for QuaternionStamped): body rates, rad/s, and accelerations, m/s², in the
  // header's frame, each with its row-major covariance ([0] = -1: not provided).
  double angular_velocity_rad_s[3] = {0};
  double angular_velocity_covariance[9] = {0};
  double linear_acceleration_m_s2[3] = {0};
  double linear_acceleration_covariance[9] = {0};
};

// Why a payload could not be decoded: typed, so callers never look at the text.
enum class DecodeFailure { kNone, kTooShort, kBadLength, kBadEncapsulation, kTrailingBytes };

// kTooShort: the payload ends before a field (or a string's / sequence's declared length) ends;
// kBadLength: a CDR string whose last counted byte is not its NUL; kBadEncapsulation: CDR
// payload not starting 00 01 / 00 00 (XCDR2 and parameter lists are not read); kTrailingBytes:
// bytes left after the last field (CDR allows up to 3 bytes of final padding).
struct DecodeResult {
  DecodeFailure failure = DecodeFailure::kNone;
  // Byte offset in the payload (CDR: counted from the payload's first byte, the encapsulation
  // header included) where the field that could not be read starts.
  size_t offset = 0;
  std::string detail;  // for people: what was being read ("ranges: 681 floats")
  bool ok() const { return failure == DecodeFailure::kNone; }
};

// Decoders fill *out (left partly filled on failure). Never read outside [data, data + size);
// never allocate more than the payload could hold.
DecodeResult DecodeLaserScan(const uint8_t* data, size_t size, WireFormat wire, LaserScanMsg* out);
DecodeResult DecodeNavSatFix(const uint8_t* data, size_t size, WireFormat wire, NavSatFixMsg* out);
DecodeResult DecodeNmeaSentence(const uint8_t* data, size_t size, WireFormat wire,
                                NmeaSentenceMsg* out);
DecodeResult DecodeQuaternionStamped(const uint8_t* data, size_t size, WireFormat wire,
                                     QuaternionMsg* out);
DecodeResult DecodeImu(const uint8_t* data, size_t size, WireFormat wire, QuaternionMsg* out);

// Encoders (the simulator writes recordings; tests round-trip). CDR is written little-endian.
// Stamps are rounded to the nanosecond (ROS 1: clamped to unsigned 32-bit seconds).
std::vector<uint8_t> EncodeLaserScan(const LaserScanMsg& msg, WireFormat wire);
std::vector<uint8_t> EncodeNavSatFix(const NavSatFixMsg& msg, WireFormat wire);
std::vector<uint8_t> EncodeNmeaSentence(const NmeaSentenceMsg& msg, WireFormat wire);
std::vector<uint8_t> EncodeQuaternionStamped(const QuaternionMsg& msg, WireFormat wire);
std::vector<uint8_t> EncodeImu(const QuaternionMsg& msg, WireFormat wire);

// The message definition text a recording stores with a topic (ROS 1 connection header
// `message_definition`, MCAP schema `ros2msg`, rosbag2 `message_definitions`), with its
// dependencies after "=====...\nMSG: pkg/Type" separators as the ROS tools write them. ROS 1
// and ROS 2 differ (std_msgs/Header has seq only in ROS 1). "" for kOther.
const char* RosTypeDefinition(RosType type, WireFormat wire = WireFormat::kRos1);

}  // namespace wallcal::recording
