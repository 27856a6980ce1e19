// SPDX-License-Identifier: Apache-2.0
// The ROS message codecs: type table, hand-worked byte layouts on both wires, round trips, and
// what a damaged payload reports (kind and offset).

#include "recording/ros/ros_messages.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "test/support/expect_text.h"

namespace wallcal::recording {
namespace {

// Little-endian (or big-endian) byte builder for hand-worked payloads.
class Bytes {
 public:
  explicit Bytes(bool big_endian = false) : big_(big_endian) {}
  Bytes& Raw(std::initializer_list<int> bytes) {
    for (int b : bytes) out.push_back(static_cast<uint8_t>(b));
    return *this;
  }
  template <class T>
  Bytes& Put(T value) {
    uint8_t b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));  // the test host is little-endian (x86-64, aarch64)
    for (size_t i = 0; i < sizeof(T); ++i) out.push_back(big_ ? b[sizeof(T) - 1 - i] : b[i]);
    return *this;
  }
  Bytes& Text(const std::string& s) {
    out.insert(out.end(), s.begin(), s.end());
    return *this;
  }
  std::vector<uint8_t> out;

 private:
  bool big_;
};

LaserScanMsg SampleScan() {
  LaserScanMsg m;
  m.header = {7, 1700000000.25, "laser"};  // the stamp is exact in binary: round trips to the bit
  m.angle_min_rad = -2.0f;
  m.angle_max_rad = 2.0f;
  m.angle_increment_rad = 0.5f;
  m.time_increment_s = 1e-4f;
  m.scan_time_s = 0.1f;
  m.range_min_m = 0.02f;
  m.range_max_m = 30.0f;
  m.ranges_m = {1.5f, 2.5f, 3.25f, 0.0f, 29.0f, 4.0f, 5.0f, 6.0f, 7.0f};
  m.intensities = {10, 20, 30};
  return m;
}

NavSatFixMsg SampleFix() {
  NavSatFixMsg m;
  m.header = {3, 1432235498.5, "gps"};
  m.status = 2;
  m.service = 1;
  m.latitude_deg = 42.375812;
  m.longitude_deg = -71.147394;
  m.altitude_m = 7.3;
  for (int i = 0; i < 9; ++i) m.position_covariance[i] = 0.1 * (i + 1);
  m.position_covariance_type = 1;
  return m;
}

QuaternionMsg SampleImu() {
  QuaternionMsg m;
  m.header = {11, 1432235497.75, "imu_link"};
  m.x = 0.44;
  m.y = -0.54;
  m.z = -0.55;
  m.w = 0.45;
  m.from_imu = true;
  for (int i = 0; i < 9; ++i) {
    m.orientation_covariance[i] = i;
    m.angular_velocity_covariance[i] = 10 + i;
    m.linear_acceleration_covariance[i] = 20 + i;
  }
  m.angular_velocity_rad_s[0] = 0.1;
  m.angular_velocity_rad_s[2] = -0.3;
  m.linear_acceleration_m_s2[2] = 9.81;
  return m;
}

TEST(RosTypesTest, NamesMd5sumsAndDefinitions) {
  EXPECT_EQ(RosTypeFromName("sensor_msgs/LaserScan"), RosType::kLaserScan);
  EXPECT_EQ(RosTypeFromName("sensor_msgs/msg/LaserScan"), RosType::kLaserScan);
  EXPECT_EQ(RosTypeFromName("sensor_msgs/msg/NavSatFix"), RosType::kNavSatFix);
  EXPECT_EQ(RosTypeFromName("nmea_msgs/msg/Sentence"), RosType::kNmeaSentence);
  EXPECT_EQ(RosTypeFromName("geometry_msgs/QuaternionStamped"), RosType::kQuaternionStamped);
  EXPECT_EQ(RosTypeFromName("sensor_msgs/Imu"), RosType::kImu);
  EXPECT_EQ(RosTypeFromName("sensor_msgs/LaserScanX"), RosType::kOther);
  EXPECT_EQ(RosTypeFromName("nav_msgs/Odometry"), RosType::kOther);
  // md5sums as recorded bags carry them (LaserScan, NavSatFix, Imu seen in the real bags;
  // all five recomputed from the definitions the genmsg way).
  EXPECT_STREQ(RosTypeMd5(RosType::kLaserScan), "90c7ef2dc6895d81024acba2ac42f369");
  EXPECT_STREQ(RosTypeMd5(RosType::kNavSatFix), "2d3a8cd499b9b4a0249fb98fd05cfa48");
  EXPECT_STREQ(RosTypeMd5(RosType::kNmeaSentence), "9f221efc5f4b3bac7ce4af102b32308b");
  EXPECT_STREQ(RosTypeMd5(RosType::kQuaternionStamped), "e57f1e547e0e1fd13504588ffc8334e2");
  EXPECT_STREQ(RosTypeMd5(RosType::kImu), "6a62c6daae103f4ff57a132d6f95cec2");
  EXPECT_STREQ(RosTypeMd5(RosType::kOther), "");
  EXPECT_STREQ(RosTypeName(RosType::kImu), "sensor_msgs/Imu");
  const std::string ros1 = RosTypeDefinition(RosType::kLaserScan, WireFormat::kRos1);
  const std::string ros2 = RosTypeDefinition(RosType::kLaserScan, WireFormat::kCdr);
  testing_support::ExpectContains(
      ros1, {"float32[] ranges\n", "MSG: std_msgs/Header\nuint32 seq\ntime stamp"});
  EXPECT_EQ(ros2.find("uint32 seq"), std::string::npos);
  EXPECT_NE(ros2.find("MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec"),
            std::string::npos);
  EXPECT_NE(
      std::string(RosTypeDefinition(RosType::kNavSatFix)).find("MSG: sensor_msgs/NavSatStatus"),
      std::string::npos);
  EXPECT_STREQ(RosTypeDefinition(RosType::kOther), "");
}

// Header seq 7, stamp 1 s + 2 ns, frame "ab"; angles etc. 1..7; ranges {0.5, 0.25}; no
// intensities.
LaserScanMsg TinyScan() {
  LaserScanMsg m;
  m.header = {7, 1.000000002, "ab"};
  m.angle_min_rad = 1;
  m.angle_max_rad = 2;
  m.angle_increment_rad = 3;
  m.time_increment_s = 4;
  m.scan_time_s = 5;
  m.range_min_m = 6;
  m.range_max_m = 7;
  m.ranges_m = {0.5f, 0.25f};
  return m;
}

TEST(LaserScanCodecTest, Ros1LayoutByHand) {
  Bytes b;
  b.Put<uint32_t>(7).Put<uint32_t>(1).Put<uint32_t>(2).Put<uint32_t>(2).Text("ab");  // 0..18
  for (float f = 1; f <= 7; ++f) b.Put<float>(f);                                    // 18..46
  b.Put<uint32_t>(2).Put<float>(0.5f).Put<float>(0.25f);                             // 46..58
  b.Put<uint32_t>(0);                                                                // 58..62
  EXPECT_EQ(EncodeLaserScan(TinyScan(), WireFormat::kRos1), b.out);
  LaserScanMsg decoded;
  ASSERT_TRUE(DecodeLaserScan(b.out.data(), b.out.size(), WireFormat::kRos1, &decoded).ok());
  EXPECT_EQ(decoded.header.seq, 7u);
  EXPECT_NEAR(decoded.header.stamp_s, 1.000000002, 1e-12);
  EXPECT_EQ(decoded.header.frame_id, "ab");
  EXPECT_EQ(decoded.range_max_m, 7.0f);
  EXPECT_EQ(decoded.ranges_m, (std::vector<float>{0.5f, 0.25f}));
  EXPECT_TRUE(decoded.intensities.empty());
}

TEST(LaserScanCodecTest, CdrLayoutByHandWithPadding) {
  // Offsets after the 4-byte encapsulation: sec 0, nanosec 4, string count 8 (3 = "ab" + NUL),
  // bytes 12..15, one pad byte to align the float at 16, floats 16..44, count 44, ranges 48..56,
  // count 56..60. No seq in ROS 2's Header.
  Bytes b;
  b.Raw({0x00, 0x01, 0x00, 0x00});
  b.Put<int32_t>(1).Put<uint32_t>(2).Put<uint32_t>(3).Text("ab").Raw({0x00}).Raw({0x00});
  for (float f = 1; f <= 7; ++f) b.Put<float>(f);
  b.Put<uint32_t>(2).Put<float>(0.5f).Put<float>(0.25f).Put<uint32_t>(0);
  ASSERT_EQ(b.out.size(), 64u);
  EXPECT_EQ(EncodeLaserScan(TinyScan(), WireFormat::kCdr), b.out);
  LaserScanMsg decoded;
  ASSERT_TRUE(DecodeLaserScan(b.out.data(), b.out.size(), WireFormat::kCdr, &decoded).ok());
  EXPECT_EQ(decoded.header.seq, 0u);
  EXPECT_EQ(decoded.header.frame_id, "ab");
  EXPECT_EQ(decoded.angle_min_rad, 1.0f);
  EXPECT_EQ(decoded.ranges_m, (std::vector<float>{0.5f, 0.25f}));
}

TEST(NavSatFixCodecTest, CdrAlignsServiceTo2AndLatitudeTo8) {
  NavSatFixMsg m = SampleFix();  // frame "gps": count 4 at rel 8, bytes rel 12..16
  const std::vector<uint8_t> bytes = EncodeNavSatFix(m, WireFormat::kCdr);
  // rel 16 status (int8), pad 1, rel 18 service (uint16), pad 4, rel 24 latitude.
  EXPECT_EQ(bytes[4 + 16], 2);
  EXPECT_EQ(bytes[4 + 17], 0);
  EXPECT_EQ(bytes[4 + 18], 1);
  double latitude;
  std::memcpy(&latitude, &bytes[4 + 24], 8);
  EXPECT_EQ(latitude, m.latitude_deg);
  EXPECT_EQ(bytes.size(), 4u + 24 + 3 * 8 + 9 * 8 + 1);
  // ROS 1: no padding at all: seq+stamp 12, frame 4+3, status 1, service 2, 12 doubles, 1.
  EXPECT_EQ(EncodeNavSatFix(m, WireFormat::kRos1).size(), 12u + 7 + 1 + 2 + 12 * 8 + 1);
}

TEST(QuaternionCodecTest, BigEndianCdrByHand) {
  Bytes b(/*big_endian=*/true);
  b.Raw({0x00, 0x00, 0x00, 0x00});
  b.Put<int32_t>(-5).Put<uint32_t>(500000000).Put<uint32_t>(2).Text("q").Raw({0});
  b.Raw({0, 0});  // frame id at rel 12..14; the doubles align to 8: rel 16
  b.Put<double>(0.5).Put<double>(-0.5).Put<double>(0.25).Put<double>(0.75);
  QuaternionMsg q;
  const DecodeResult r = DecodeQuaternionStamped(b.out.data(), b.out.size(), WireFormat::kCdr, &q);
  ASSERT_TRUE(r.ok()) << r.detail;
  EXPECT_DOUBLE_EQ(q.header.stamp_s, -4.5);
  EXPECT_EQ(q.header.frame_id, "q");
  EXPECT_EQ(q.x, 0.5);
  EXPECT_EQ(q.y, -0.5);
  EXPECT_EQ(q.z, 0.25);
  EXPECT_EQ(q.w, 0.75);
  EXPECT_FALSE(q.from_imu);
}

template <class M, class Enc, class Dec>
M RoundTrip(const M& in, WireFormat wire, Enc encode, Dec decode) {
  const std::vector<uint8_t> bytes = encode(in, wire);
  M out;
  const DecodeResult r = decode(bytes.data(), bytes.size(), wire, &out);
  EXPECT_TRUE(r.ok()) << r.detail << " at " << r.offset;
  EXPECT_EQ(encode(out, wire), bytes);  // decoding loses nothing the encoder wrote
  return out;
}

class RoundTripTest : public ::testing::TestWithParam<WireFormat> {};

TEST_P(RoundTripTest, EveryTypeComesBackEqual) {
  const WireFormat wire = GetParam();
  const uint32_t seq = wire == WireFormat::kRos1 ? 1 : 0;  // CDR has no seq
  const LaserScanMsg scan = RoundTrip(SampleScan(), wire, EncodeLaserScan, DecodeLaserScan);
  EXPECT_EQ(scan.header.seq, seq * 7);
  EXPECT_EQ(scan.header.stamp_s, SampleScan().header.stamp_s);
  EXPECT_EQ(scan.header.frame_id, "laser");
  EXPECT_EQ(scan.ranges_m, SampleScan().ranges_m);
  EXPECT_EQ(scan.intensities, SampleScan().intensities);
  EXPECT_EQ(scan.time_increment_s, 1e-4f);

  const NavSatFixMsg fix = RoundTrip(SampleFix(), wire, EncodeNavSatFix, DecodeNavSatFix);
  EXPECT_EQ(fix.header.seq, seq * 3);
  EXPECT_EQ(fix.status, 2);
  EXPECT_EQ(fix.service, 1);
  EXPECT_EQ(fix.latitude_deg, 42.375812);
  EXPECT_EQ(fix.longitude_deg, -71.147394);
  EXPECT_EQ(fix.altitude_m, 7.3);
  EXPECT_EQ(fix.position_covariance[8], 0.9);
  EXPECT_EQ(fix.position_covariance_type, 1);

  NmeaSentenceMsg nmea;
  nmea.header.stamp_s = 12.5;
  nmea.header.frame_id = "gps";
  nmea.sentence = "$GPGGA,123519,4807.038,N,01131.000,E,4,08,0.9,545.4,M,46.9,M,,*4F";
  const NmeaSentenceMsg nmea_back = RoundTrip(nmea, wire, EncodeNmeaSentence, DecodeNmeaSentence);
  EXPECT_EQ(nmea_back.sentence, nmea.sentence);
  EXPECT_EQ(nmea_back.header.stamp_s, 12.5);

  QuaternionMsg q;
  q.header.stamp_s = 100.75;
  q.header.frame_id = "base_link";
  q.x = 0.1;
  q.y = 0.2;
  q.z = 0.3;
  q.w = 0.927;
  const QuaternionMsg q_back = RoundTrip(q, wire, EncodeQuaternionStamped, DecodeQuaternionStamped);
  EXPECT_EQ(q_back.z, 0.3);
  EXPECT_EQ(q_back.w, 0.927);
  EXPECT_FALSE(q_back.from_imu);

  const QuaternionMsg imu = RoundTrip(SampleImu(), wire, EncodeImu, DecodeImu);
  EXPECT_TRUE(imu.from_imu);
  EXPECT_EQ(imu.x, 0.44);
  EXPECT_EQ(imu.orientation_covariance[4], 4.0);
  EXPECT_EQ(imu.angular_velocity_rad_s[2], -0.3);
  EXPECT_EQ(imu.linear_acceleration_m_s2[2], 9.81);
  EXPECT_EQ(imu.linear_acceleration_covariance[8], 28.0);
  EXPECT_EQ(imu.header.frame_id, "imu_link");
}

INSTANTIATE_TEST_SUITE_P(BothWires, RoundTripTest,
                         ::testing::Values(WireFormat::kRos1, WireFormat::kCdr),
                         [](const auto& param_info) {
                           return param_info.param == WireFormat::kRos1 ? std::string("Ros1")
                                                                        : std::string("Cdr");
                         });

TEST(DecodeFailureTest, TruncatedLaserScanStopsWhereTheFieldStarts) {
  // A cut of TinyScan's bytes: where the decode stops and the field it names ("": any).
  struct Cut {
    WireFormat wire;
    size_t size;
    size_t offset;
    const char* field;
  };
  const Cut cuts[] = {
      {WireFormat::kRos1, 54, 50, "ranges"},    // in the ranges (at 50, after their count at 46)
      {WireFormat::kRos1, 17, 16, ""},          // in the frame id's bytes (they start at 16)
      {WireFormat::kCdr, 19, 19, ""},           // in the padding before angle_min (at 19)
      {WireFormat::kCdr, 22, 20, "angle_min"},  // in angle_min (at 20)
      {WireFormat::kCdr, 2, 0, ""},             // in the encapsulation header
  };
  for (const Cut& cut : cuts) {
    SCOPED_TRACE(cut.size);
    const std::vector<uint8_t> bytes = EncodeLaserScan(TinyScan(), cut.wire);
    LaserScanMsg m;
    const DecodeResult r = DecodeLaserScan(bytes.data(), cut.size, cut.wire, &m);
    EXPECT_EQ(r.failure, DecodeFailure::kTooShort);
    EXPECT_EQ(r.offset, cut.offset);
    EXPECT_NE(r.detail.find(cut.field), std::string::npos) << r.detail;
  }
}

TEST(DecodeFailureTest, EveryPrefixOfEveryTypeFailsWithinItsLength) {
  for (WireFormat wire : {WireFormat::kRos1, WireFormat::kCdr}) {
    const std::vector<std::vector<uint8_t>> payloads = {
        EncodeLaserScan(SampleScan(), wire), EncodeNavSatFix(SampleFix(), wire),
        EncodeNmeaSentence(NmeaSentenceMsg(), wire), EncodeImu(SampleImu(), wire),
        EncodeQuaternionStamped(QuaternionMsg(), wire)};
    for (size_t type = 0; type < payloads.size(); ++type) {
      const std::vector<uint8_t>& full = payloads[type];
      for (size_t n = 0; n < full.size(); ++n) {
        // The prefix in its own allocation, so that a read past it is an ASan error.
        const std::vector<uint8_t> cut(full.begin(), full.begin() + static_cast<long>(n));
        DecodeResult r;
        LaserScanMsg scan;
        NavSatFixMsg fix;
        NmeaSentenceMsg nmea;
        QuaternionMsg q;
        switch (type) {
          case 0:
            r = DecodeLaserScan(cut.data(), n, wire, &scan);
            break;
          case 1:
            r = DecodeNavSatFix(cut.data(), n, wire, &fix);
            break;
          case 2:
            r = DecodeNmeaSentence(cut.data(), n, wire, &nmea);
            break;
          case 3:
            r = DecodeImu(cut.data(), n, wire, &q);
            break;
          default:
            r = DecodeQuaternionStamped(cut.data(), n, wire, &q);
            break;
        }
        // CDR keeps up to 3 bytes of final padding: a LaserScan cut in its last count is
        // still too short, so every cut fails.
        EXPECT_EQ(r.failure, DecodeFailure::kTooShort) << "type " << type << " cut " << n;
        EXPECT_LE(r.offset, n);
      }
    }
  }
}

TEST(DecodeFailureTest, HostileCountFailsWithoutAllocating) {
  std::vector<uint8_t> ros1 = EncodeLaserScan(TinyScan(), WireFormat::kRos1);
  ros1[46] = ros1[47] = ros1[48] = ros1[49] = 0xff;  // ranges count 4294967295
  LaserScanMsg m;
  const DecodeResult r = DecodeLaserScan(ros1.data(), ros1.size(), WireFormat::kRos1, &m);
  EXPECT_EQ(r.failure, DecodeFailure::kTooShort);
  EXPECT_EQ(r.offset, 50u);
  EXPECT_TRUE(m.ranges_m.empty());
  std::vector<uint8_t> cdr = EncodeNmeaSentence(NmeaSentenceMsg(), WireFormat::kCdr);
  cdr[4 + 8] = cdr[4 + 9] = cdr[4 + 10] = cdr[4 + 11] = 0xff;  // frame_id length
  NmeaSentenceMsg n;
  EXPECT_EQ(DecodeNmeaSentence(cdr.data(), cdr.size(), WireFormat::kCdr, &n).failure,
            DecodeFailure::kTooShort);
}

TEST(DecodeFailureTest, EncapsulationTrailingBytesAndMissingNul) {
  std::vector<uint8_t> cdr = EncodeQuaternionStamped(QuaternionMsg(), WireFormat::kCdr);
  QuaternionMsg q;
  std::vector<uint8_t> xcdr2 = cdr;
  xcdr2[1] = 0x07;  // XCDR2 little endian
  DecodeResult r = DecodeQuaternionStamped(xcdr2.data(), xcdr2.size(), WireFormat::kCdr, &q);
  EXPECT_EQ(r.failure, DecodeFailure::kBadEncapsulation);
  EXPECT_EQ(r.offset, 0u);

  std::vector<uint8_t> padded = cdr;
  padded.insert(padded.end(), {0, 0, 0});
  EXPECT_TRUE(DecodeQuaternionStamped(padded.data(), padded.size(), WireFormat::kCdr, &q).ok());
  padded.push_back(0);
  r = DecodeQuaternionStamped(padded.data(), padded.size(), WireFormat::kCdr, &q);
  EXPECT_EQ(r.failure, DecodeFailure::kTrailingBytes);
  EXPECT_EQ(r.offset, cdr.size());

  std::vector<uint8_t> ros1 = EncodeQuaternionStamped(QuaternionMsg(), WireFormat::kRos1);
  ros1.push_back(0);
  r = DecodeQuaternionStamped(ros1.data(), ros1.size(), WireFormat::kRos1, &q);
  EXPECT_EQ(r.failure, DecodeFailure::kTrailingBytes);

  NmeaSentenceMsg s;
  s.sentence = "abc";
  std::vector<uint8_t> no_nul = EncodeNmeaSentence(s, WireFormat::kCdr);
  no_nul.back() = 'x';  // the sentence's NUL is the payload's last byte
  NmeaSentenceMsg back;
  r = DecodeNmeaSentence(no_nul.data(), no_nul.size(), WireFormat::kCdr, &back);
  EXPECT_EQ(r.failure, DecodeFailure::kBadLength);
  EXPECT_EQ(r.offset, no_nul.size() - 4);
}

TEST(TimeCodecTest, StampsRoundToTheNanosecond) {
  QuaternionMsg q;
  q.header.stamp_s = 1282836370.970876455;
  const std::vector<uint8_t> bytes = EncodeQuaternionStamped(q, WireFormat::kRos1);
  uint32_t sec, nsec;
  std::memcpy(&sec, &bytes[4], 4);
  std::memcpy(&nsec, &bytes[8], 4);
  EXPECT_EQ(sec, 1282836370u);
  EXPECT_NEAR(nsec, 970876455u, 200);  // a double near 1.3e9 s resolves ~0.24 µs
  q.header.stamp_s = 5.9999999999;     // rounds up into the next second
  const std::vector<uint8_t> carry = EncodeQuaternionStamped(q, WireFormat::kCdr);
  int32_t csec;
  std::memcpy(&csec, &carry[4], 4);
  std::memcpy(&nsec, &carry[8], 4);
  EXPECT_EQ(csec, 6);
  EXPECT_EQ(nsec, 0u);
}

}  // namespace
}  // namespace wallcal::recording
