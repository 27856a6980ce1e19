// SPDX-License-Identifier: Apache-2.0
#include "recording/ros/ros_messages.h"

#include <string>

#include "recording/ros/internal/wire_cursor.h"

namespace wallcal::recording {
namespace {

// One row per supported type. The md5sums are ROS 1's (genmsg: md5 of the definition with
// comments dropped, constants first, nested types replaced by their own md5); each was checked
// against a real bag where one exists (LaserScan, NavSatFix, Imu) and recomputed from the
// definitions (all five).
struct TypeRow {
  RosType type;
  const char* ros1_name;
  const char* ros2_name;
  const char* md5;
  const char* ros1_definition;
  const char* ros2_definition;
};

#define WALLCAL_SEPARATOR \
  "\n================================================================================\n"

#define WALLCAL_ROS1_HEADER \
  WALLCAL_SEPARATOR         \
  "MSG: std_msgs/Header\n"  \
  "uint32 seq\n"            \
  "time stamp\n"            \
  "string frame_id\n"

#define WALLCAL_ROS2_HEADER             \
  WALLCAL_SEPARATOR                     \
  "MSG: std_msgs/Header\n"              \
  "builtin_interfaces/Time stamp\n"     \
  "string frame_id\n" WALLCAL_SEPARATOR \
  "MSG: builtin_interfaces/Time\n"      \
  "int32 sec\n"                         \
  "uint32 nanosec\n"

#define WALLCAL_LASER_SCAN_BODY \
  "float32 angle_min\n"         \
  "float32 angle_max\n"         \
  "float32 angle_increment\n"   \
  "float32 time_increment\n"    \
  "float32 scan_time\n"         \
  "float32 range_min\n"         \
  "float32 range_max\n"         \
  "float32[] ranges\n"          \
  "float32[] intensities\n"

#define WALLCAL_NAV_SAT_FIX_BODY               \
  "NavSatStatus status\n"                      \
  "float64 latitude\n"                         \
  "float64 longitude\n"                        \
  "float64 altitude\n"                         \
  "float64[9] position_covariance\n"           \
  "uint8 COVARIANCE_TYPE_UNKNOWN = 0\n"        \
  "uint8 COVARIANCE_TYPE_APPROXIMATED = 1\n"   \
  "uint8 COVARIANCE_TYPE_DIAGONAL_KNOWN = 2\n" \
  "uint8 COVARIANCE_TYPE_KNOWN = 3\n"          \
  "uint8 position_covariance_type\n"

#define WALLCAL_NAV_SAT_STATUS      \
  WALLCAL_SEPARATOR                 \
  "MSG: sensor_msgs/NavSatStatus\n" \
  "int8 STATUS_NO_FIX = -1\n"       \
  "int8 STATUS_FIX = 0\n"           \
  "int8 STATUS_SBAS_FIX = 1\n"      \
  "int8 STATUS_GBAS_FIX = 2\n"      \
  "int8 status\n"                   \
  "uint16 SERVICE_GPS = 1\n"        \
  "uint16 SERVICE_GLONASS = 2\n"    \
  "uint16 SERVICE_COMPASS = 4\n"    \
  "uint16 SERVICE_GALILEO = 8\n"    \
  "uint16 service\n"

#define WALLCAL_QUATERNION          \
  WALLCAL_SEPARATOR                 \
  "MSG: geometry_msgs/Quaternion\n" \
  "float64 x\n"                     \
  "float64 y\n"                     \
  "float64 z\n"                     \
  "float64 w\n"

#define WALLCAL_VECTOR3          \
  WALLCAL_SEPARATOR              \
  "MSG: geometry_msgs/Vector3\n" \
  "float64 x\n"                  \
  "float64 y\n"                  \
  "float64 z\n"

#define WALLCAL_IMU_BODY                        \
  "geometry_msgs/Quaternion orientation\n"      \
  "float64[9] orientation_covariance\n"         \
  "geometry_msgs/Vector3 angular_velocity\n"    \
  "float64[9] angular_velocity_covariance\n"    \
  "geometry_msgs/Vector3 linear_acceleration\n" \
  "float64[9] linear_acceleration_covariance\n"

const TypeRow kTypes[] = {
    {RosType::kLaserScan, "sensor_msgs/LaserScan", "sensor_msgs/msg/LaserScan",
     "90c7ef2dc6895d81024acba2ac42f369",
     "Header header\n" WALLCAL_LASER_SCAN_BODY WALLCAL_ROS1_HEADER,
     "std_msgs/Header header\n" WALLCAL_LASER_SCAN_BODY WALLCAL_ROS2_HEADER},
    {RosType::kNavSatFix, "sensor_msgs/NavSatFix", "sensor_msgs/msg/NavSatFix",
     "2d3a8cd499b9b4a0249fb98fd05cfa48",
     "Header header\n" WALLCAL_NAV_SAT_FIX_BODY WALLCAL_ROS1_HEADER WALLCAL_NAV_SAT_STATUS,
     "std_msgs/Header header\n" WALLCAL_NAV_SAT_FIX_BODY WALLCAL_ROS2_HEADER
         WALLCAL_NAV_SAT_STATUS},
    // Not 9c0f7ed9...: genmsg over "Header header\nstring sentence" gives 9f221efc..., the value
    // nmea_msgs' generated code and recorded bags carry.
    {RosType::kNmeaSentence, "nmea_msgs/Sentence", "nmea_msgs/msg/Sentence",
     "9f221efc5f4b3bac7ce4af102b32308b", "Header header\nstring sentence\n" WALLCAL_ROS1_HEADER,
     "std_msgs/Header header\nstring sentence\n" WALLCAL_ROS2_HEADER},
    {RosType::kQuaternionStamped, "geometry_msgs/QuaternionStamped",
     "geometry_msgs/msg/QuaternionStamped", "e57f1e547e0e1fd13504588ffc8334e2",
     "Header header\nQuaternion quaternion\n" WALLCAL_ROS1_HEADER WALLCAL_QUATERNION,
     "std_msgs/Header header\nQuaternion quaternion\n" WALLCAL_ROS2_HEADER WALLCAL_QUATERNION},
    {RosType::kImu, "sensor_msgs/Imu", "sensor_msgs/msg/Imu", "6a62c6daae103f4ff57a132d6f95cec2",
     "Header header\n" WALLCAL_IMU_BODY WALLCAL_ROS1_HEADER WALLCAL_QUATERNION WALLCAL_VECTOR3,
     "std_msgs/Header header\n" WALLCAL_IMU_BODY WALLCAL_ROS2_HEADER WALLCAL_QUATERNION
         WALLCAL_VECTOR3},
};

#undef WALLCAL_SEPARATOR
#undef WALLCAL_ROS1_HEADER
#undef WALLCAL_ROS2_HEADER
#undef WALLCAL_LASER_SCAN_BODY
#undef WALLCAL_NAV_SAT_FIX_BODY
#undef WALLCAL_NAV_SAT_STATUS
#undef WALLCAL_QUATERNION
#undef WALLCAL_VECTOR3
#undef WALLCAL_IMU_BODY

const TypeRow* Row(RosType type) {
  for (const TypeRow& row : kTypes) {
    if (row.type == type) return &row;
  }
  return nullptr;
}

// Field walkers: the one place each message's field order is written. C is wire::Reader (M
// mutable) or wire::Writer (M const).
template <class C, class H>
void WalkHeader(C& c, H& header) {
  if (c.wire() == WireFormat::kRos1) c.Prim(header.seq, "header.seq");
  c.Time(header.stamp_s, "header.stamp");
  c.String(header.frame_id, "header.frame_id");
}

template <class C, class M>
void WalkLaserScan(C& c, M& m) {
  WalkHeader(c, m.header);
  c.Prim(m.angle_min_rad, "angle_min");
  c.Prim(m.angle_max_rad, "angle_max");
  c.Prim(m.angle_increment_rad, "angle_increment");
  c.Prim(m.time_increment_s, "time_increment");
  c.Prim(m.scan_time_s, "scan_time");
  c.Prim(m.range_min_m, "range_min");
  c.Prim(m.range_max_m, "range_max");
  c.Seq(m.ranges_m, "ranges");
  c.Seq(m.intensities, "intensities");
}

template <class C, class M>
void WalkNavSatFix(C& c, M& m) {
  WalkHeader(c, m.header);
  c.Prim(m.status, "status.status");
  c.Prim(m.service, "status.service");
  c.Prim(m.latitude_deg, "latitude");
  c.Prim(m.longitude_deg, "longitude");
  c.Prim(m.altitude_m, "altitude");
  c.Array(m.position_covariance, "position_covariance");
  c.Prim(m.position_covariance_type, "position_covariance_type");
}

template <class C, class M>
void WalkNmeaSentence(C& c, M& m) {
  WalkHeader(c, m.header);
  c.String(m.sentence, "sentence");
}

template <class C, class M>
void WalkQuaternion(C& c, M& m, const char* x, const char* y, const char* z, const char* w) {
  c.Prim(m.x, x);
  c.Prim(m.y, y);
  c.Prim(m.z, z);
  c.Prim(m.w, w);
}

template <class C, class M>
void WalkQuaternionStamped(C& c, M& m) {
  WalkHeader(c, m.header);
  WalkQuaternion(c, m, "quaternion.x", "quaternion.y", "quaternion.z", "quaternion.w");
}

template <class C, class M>
void WalkImu(C& c, M& m) {
  WalkHeader(c, m.header);
  WalkQuaternion(c, m, "orientation.x", "orientation.y", "orientation.z", "orientation.w");
  c.Array(m.orientation_covariance, "orientation_covariance");
  c.Array(m.angular_velocity_rad_s, "angular_velocity");
  c.Array(m.angular_velocity_covariance, "angular_velocity_covariance");
  c.Array(m.linear_acceleration_m_s2, "linear_acceleration");
  c.Array(m.linear_acceleration_covariance, "linear_acceleration_covariance");
}

}  // namespace

RosType RosTypeFromName(std::string_view type_name) {
  for (const TypeRow& row : kTypes) {
    if (type_name == row.ros1_name || type_name == row.ros2_name) return row.type;
  }
  return RosType::kOther;
}

const char* RosTypeName(RosType type) {
  const TypeRow* row = Row(type);
  return row != nullptr ? row->ros1_name : "";
}

const char* RosTypeMd5(RosType type) {
  const TypeRow* row = Row(type);
  return row != nullptr ? row->md5 : "";
}

const char* RosTypeDefinition(RosType type, WireFormat wire) {
  const TypeRow* row = Row(type);
  if (row == nullptr) return "";
  return wire == WireFormat::kRos1 ? row->ros1_definition : row->ros2_definition;
}

DecodeResult DecodeLaserScan(const uint8_t* data, size_t size, WireFormat wire, LaserScanMsg* out) {
  wire::Reader reader(data, size, wire);
  *out = LaserScanMsg();
  WalkLaserScan(reader, *out);
  return reader.Finish();
}

DecodeResult DecodeNavSatFix(const uint8_t* data, size_t size, WireFormat wire, NavSatFixMsg* out) {
  wire::Reader reader(data, size, wire);
  *out = NavSatFixMsg();
  WalkNavSatFix(reader, *out);
  return reader.Finish();
}

DecodeResult DecodeNmeaSentence(const uint8_t* data, size_t size, WireFormat wire,
                                NmeaSentenceMsg* out) {
  wire::Reader reader(data, size, wire);
  *out = NmeaSentenceMsg();
  WalkNmeaSentence(reader, *out);
  return reader.Finish();
}

DecodeResult DecodeQuaternionStamped(const uint8_t* data, size_t size, WireFormat wire,
                                     QuaternionMsg* out) {
  wire::Reader reader(data, size, wire);
  *out = QuaternionMsg();
  WalkQuaternionStamped(reader, *out);
  return reader.Finish();
}

DecodeResult DecodeImu(const uint8_t* data, size_t size, WireFormat wire, QuaternionMsg* out) {
  wire::Reader reader(data, size, wire);
  *out = QuaternionMsg();
  out->from_imu = true;
  WalkImu(reader, *out);
  return reader.Finish();
}

std::vector<uint8_t> EncodeLaserScan(const LaserScanMsg& msg, WireFormat wire) {
  wire::Writer writer(wire);
  WalkLaserScan(writer, msg);
  return writer.Take();
}

std::vector<uint8_t> EncodeNavSatFix(const NavSatFixMsg& msg, WireFormat wire) {
  wire::Writer writer(wire);
  WalkNavSatFix(writer, msg);
  return writer.Take();
}

std::vector<uint8_t> EncodeNmeaSentence(const NmeaSentenceMsg& msg, WireFormat wire) {
  wire::Writer writer(wire);
  WalkNmeaSentence(writer, msg);
  return writer.Take();
}

std::vector<uint8_t> EncodeQuaternionStamped(const QuaternionMsg& msg, WireFormat wire) {
  wire::Writer writer(wire);
  WalkQuaternionStamped(writer, msg);
  return writer.Take();
}

std::vector<uint8_t> EncodeImu(const QuaternionMsg& msg, WireFormat wire) {
  wire::Writer writer(wire);
  WalkImu(writer, msg);
  return writer.Take();
}

}  // namespace wallcal::recording
