// SPDX-License-Identifier: Apache-2.0
// The attitude stream: a sensor_msgs/Imu's orientation as roll and pitch with REP 103's signs
// turned into AttitudeSample's, its covariance as σ, the messages without orientation skipped
// (every one of them: an error naming the topic), the stream read with the session's other
// streams from text logs (once per file) and recordings, and the real Husky bag's Imu.
#include "recording/attitude_stream.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "common/angles.h"
#include "io/writers/writers.h"
#include "recording/recording.h"
#include "recording/recording_streams.h"
#include "recording/writers/rosbag1_writer.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"

namespace wallcal::recording {
namespace {

using testing_support::ExpectContains;
using testing_support::MessageOf;
using testing_support::ScratchFolder;
using testing_support::WriteFile;

// The body axis `body` (x forward, y left, z up) in the ENU world frame of quaternion q.
void Rotate(const UnitQuaternion& q, const double body[3], double world[3]) {
  const double x = q.x, y = q.y, z = q.z, w = q.w;
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  for (int i = 0; i < 3; ++i) world[i] = r[i][0] * body[0] + r[i][1] * body[1] + r[i][2] * body[2];
}

// Rotation by angle_rad about the unit axis (ax, ay, az), as a quaternion.
UnitQuaternion AboutAxis(double ax, double ay, double az, double angle_rad) {
  UnitQuaternion q;
  q.w = std::cos(0.5 * angle_rad);
  q.x = ax * std::sin(0.5 * angle_rad);
  q.y = ay * std::sin(0.5 * angle_rad);
  q.z = az * std::sin(0.5 * angle_rad);
  return q;
}

TEST(AttitudeStreamTest, NoseUpIsPositivePitchAndRightSideDownPositiveRoll) {
  const double forward[3] = {1, 0, 0}, right[3] = {0, -1, 0};
  double world[3];
  double roll = 0.0, pitch = 0.0;
  // REP 103's pitch about +y (left) by -5°: the nose goes up.
  const UnitQuaternion nose_up = AboutAxis(0, 1, 0, -5.0 * kDegToRad);
  Rotate(nose_up, forward, world);
  ASSERT_GT(world[2], 0.0);
  RollPitchFromEnuQuaternion(nose_up.x, nose_up.y, nose_up.z, nose_up.w, &roll, &pitch);
  EXPECT_NEAR(pitch, 5.0 * kDegToRad, 1e-12);
  EXPECT_NEAR(roll, 0.0, 1e-12);
  // REP 103's roll about +x (forward) by +3°: the left side goes up, the right side down.
  const UnitQuaternion right_down = AboutAxis(1, 0, 0, 3.0 * kDegToRad);
  Rotate(right_down, right, world);
  ASSERT_LT(world[2], 0.0);
  RollPitchFromEnuQuaternion(right_down.x, right_down.y, right_down.z, right_down.w, &roll, &pitch);
  EXPECT_NEAR(roll, 3.0 * kDegToRad, 1e-12);
  EXPECT_NEAR(pitch, 0.0, 1e-12);
}

TEST(AttitudeStreamTest, RollAndPitchDoNotDependOnTheYaw) {
  for (const double yaw_deg : {0.0, 37.0, 135.0, -100.0}) {
    const UnitQuaternion q =
        EnuQuaternionFromAttitude(2.0 * kDegToRad, -7.5 * kDegToRad, yaw_deg * kDegToRad);
    EXPECT_NEAR(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w, 1.0, 1e-12);
    double roll = 0.0, pitch = 0.0;
    // Not of unit length: normalised first.
    RollPitchFromEnuQuaternion(3 * q.x, 3 * q.y, 3 * q.z, 3 * q.w, &roll, &pitch);
    EXPECT_NEAR(roll, 2.0 * kDegToRad, 1e-12) << yaw_deg;
    EXPECT_NEAR(pitch, -7.5 * kDegToRad, 1e-12) << yaw_deg;
    // The vehicle's forward axis points along the yaw, nose down by 7.5°.
    const double forward[3] = {1, 0, 0};
    double world[3];
    Rotate(q, forward, world);
    EXPECT_NEAR(std::atan2(world[1], world[0]), yaw_deg * kDegToRad, 1e-12);
    EXPECT_NEAR(std::asin(world[2]), -7.5 * kDegToRad, 1e-12);
  }
}

QuaternionMsg Imu(double roll_deg, double pitch_deg, double var_roll, double var_pitch) {
  QuaternionMsg msg;
  msg.from_imu = true;
  const UnitQuaternion q =
      EnuQuaternionFromAttitude(roll_deg * kDegToRad, pitch_deg * kDegToRad, 0.3);
  msg.x = q.x;
  msg.y = q.y;
  msg.z = q.z;
  msg.w = q.w;
  msg.orientation_covariance[0] = var_roll;
  msg.orientation_covariance[4] = var_pitch;
  msg.orientation_covariance[8] = 0.01;
  return msg;
}

TEST(AttitudeStreamTest, SigmaFromTheOrientationCovarianceAndTypedSkips) {
  io::AttitudeSample sample;
  ASSERT_EQ(AttitudeFromImu(Imu(1.0, 2.0, 1e-6, 4e-6), &sample), ImuAttitude::kSample);
  EXPECT_NEAR(sample.roll_rad, 1.0 * kDegToRad, 1e-12);
  EXPECT_NEAR(sample.pitch_rad, 2.0 * kDegToRad, 1e-12);
  EXPECT_DOUBLE_EQ(sample.roll_sigma_rad, 1e-3);
  EXPECT_DOUBLE_EQ(sample.pitch_sigma_rad, 2e-3);
  // All zeros: the message's "covariance unknown".
  ASSERT_EQ(AttitudeFromImu(Imu(1.0, 2.0, 0.0, 0.0), &sample), ImuAttitude::kSample);
  EXPECT_TRUE(std::isnan(sample.roll_sigma_rad) && std::isnan(sample.pitch_sigma_rad));
  EXPECT_EQ(AttitudeFromImu(Imu(1.0, 2.0, -1.0, 0.0), &sample), ImuAttitude::kNoOrientation);
  EXPECT_EQ(AttitudeFromImu(Imu(1.0, 2.0, 1e-6, -4e-6), &sample), ImuAttitude::kBadCovariance);
  EXPECT_EQ(AttitudeFromImu(Imu(1.0, 2.0, 1e-6, io::kNaN), &sample), ImuAttitude::kBadCovariance);
  EXPECT_EQ(AttitudeFromImu(Imu(95.0, 2.0, 1e-6, 1e-6), &sample), ImuAttitude::kOutOfRange);
  EXPECT_EQ(AttitudeFromImu(Imu(1.0, -31.0, 1e-6, 1e-6), &sample), ImuAttitude::kOutOfRange);
  EXPECT_EQ(AttitudeFromImu(Imu(-29.0, 29.0, 1e-6, 1e-6), &sample), ImuAttitude::kSample);
  QuaternionMsg zero = Imu(1.0, 2.0, 1e-6, 1e-6);
  zero.x = zero.y = zero.z = zero.w = 0.0;
  EXPECT_EQ(AttitudeFromImu(zero, &sample), ImuAttitude::kBadQuaternion);
  zero.w = io::kNaN;
  EXPECT_EQ(AttitudeFromImu(zero, &sample), ImuAttitude::kBadQuaternion);
}

// A session in `name` whose attitude stream is the Imu topic /imu of a ROS 1 bag holding
// `messages` (stamped 1, 2, 3, ... s); the GNSS and heading logs are text (not read here).
io::SessionSpec BagSession(const std::string& name, const std::vector<QuaternionMsg>& messages) {
  const std::string dir = ScratchFolder(name);
  io::SessionSpec spec;
  spec.dir = dir;
  spec.file = dir + "/session.yaml";
  spec.attitude_log = dir + "/run.bag";
  spec.attitude_topic = "/imu";
  Ros1BagWriter writer(spec.attitude_log, ChunkCompression::kNone);
  const int imu = writer.AddConnection("/imu", RosType::kImu);
  for (size_t i = 0; i < messages.size(); ++i) {
    QuaternionMsg m = messages[i];
    m.header.stamp_s = 1.0 + static_cast<double>(i);
    writer.Write(imu, m.header.stamp_s, EncodeImu(m, WireFormat::kRos1));
  }
  writer.Close();
  return spec;
}

TEST(AttitudeStreamTest, AnImuTopicWithoutOrientationIsAnErrorNamingTopicAndFile) {
  const io::SessionSpec spec = BagSession("no_orientation", {Imu(1, 2, -1, 0), Imu(1, 2, -1, 0)});
  ExpectContains(MessageOf<io::InputError>([&] { ReadAttitudeLog(spec); }),
                 {spec.attitude_log + ": attitude.topic /imu: every one of its 2 sensor_msgs/Imu "
                                      "messages is without orientation"});
}

TEST(AttitudeStreamTest, SomeMessagesWithoutOrientationAreCountedWithTheirFirstMessage) {
  io::SessionSpec spec = BagSession("some_without", {Imu(1, 2, 1e-6, 1e-6), Imu(1, 2, -1, 0),
                                                     Imu(1.5, 2.5, 0, 0), Imu(1, 2, -1, 0)});
  spec.attitude_time_offset_s = 0.25;
  const io::NmeaLog log = ReadAttitudeLog(spec);
  ASSERT_EQ(log.attitudes.size(), 2u);
  EXPECT_EQ(log.lines_read, 4);
  EXPECT_DOUBLE_EQ(log.attitudes[0].stamp_s, 1.25);  // attitude.time_offset_s added
  EXPECT_DOUBLE_EQ(log.attitudes[1].stamp_s, 3.25);
  EXPECT_EQ(log.attitudes[1].line, 3);
  EXPECT_NEAR(log.attitudes[1].roll_rad, 1.5 * kDegToRad, 1e-12);
  const std::string reason = "Imu without orientation (covariance[0] = -1)";
  EXPECT_EQ(log.skipped.by_reason.at(reason), 2);
  EXPECT_EQ(log.skipped.first_line.at(reason), 2);
  EXPECT_EQ(log.attitudes_by_source.at("sensor_msgs/Imu"), 2);
}

TEST(AttitudeStreamTest, AnAttitudeTopicOfAnotherTypeOrMissingIsNamed) {
  io::SessionSpec spec = BagSession("other_type", {Imu(1, 2, 0, 0)});
  spec.attitude_topic = "/imu/data";
  ExpectContains(MessageOf<io::InputError>([&] { ReadAttitudeLog(spec); }),
                 {"attitude.topic: no topic '/imu/data'", "/imu (sensor_msgs/Imu)"});
  spec.attitude_topic = "";
  ExpectContains(MessageOf<io::InputError>([&] { ReadAttitudeLog(spec); }),
                 {"attitude.topic is missing"});
}

std::string S(const std::string& body) { return "$" + body + "*" + io::NmeaChecksum(body); }

TEST(AttitudeStreamTest, ReadsTheAttitudeOfTheHeadingLogWithItsHeadingsOnce) {
  const std::string dir = ScratchFolder("text");
  io::SessionSpec spec;
  spec.gnss_log = WriteFile(dir + "/gnss.nmea", "");
  spec.heading_log =
      WriteFile(dir + "/heading.nmea",
                "10.0 $HEHDT,123.456,T*28\n10.05 " +
                    S("PASHR,000010.05,123.46,T,+1.2500,-0.7500,0.00,0.0500,0.0600,,1,0") +
                    "\n10.1 " + S("PASHR,000010.10,123.46,T,+1.2600,-0.7400,0.00,,,,1,0") + "\n");
  spec.attitude_log = spec.heading_log;
  spec.attitude_time_offset_s = -0.05;
  const PoseLogs logs = ReadPoseLogs(spec);
  ASSERT_EQ(logs.headings.headings.size(), 1u);
  ASSERT_EQ(logs.attitudes.attitudes.size(), 2u);
  EXPECT_DOUBLE_EQ(logs.attitudes.attitudes[0].stamp_s, 10.0);
  EXPECT_EQ(logs.attitudes.attitudes[1].line, 3);
  EXPECT_EQ(logs.attitudes.lines_read, 3);
  EXPECT_TRUE(logs.attitudes.headings.empty());  // the attitude stream only
  // Without the attitude stream asked for, or without one named, nothing.
  EXPECT_TRUE(ReadPoseLogs(spec, true, true, false).attitudes.attitudes.empty());
  spec.attitude_log.clear();
  EXPECT_TRUE(ReadPoseLogs(spec).attitudes.attitudes.empty());
}

TEST(AttitudeStreamTest, AnAttitudeLogWithoutASampleIsAnError) {
  const std::string dir = ScratchFolder("empty");
  io::SessionSpec spec;
  spec.attitude_log = WriteFile(dir + "/attitude.nmea",
                                "1.0 " + S("PASHR,000001.00,123.46,T,+95.0,-0.74,0.00,,,,1,0") +
                                    "\n2.0 " + S("HEHDT,1.0,T") + "\n");
  ExpectContains(
      MessageOf<io::InputError>([&] { ReadAttitudeLog(spec); }),
      {spec.attitude_log + ": attitude.log: no attitude sample (lines read: 2; skipped: ",
       "roll or pitch beyond 30 deg: 1, first at line 1",
       "expected $PASHR or $PTNL,AVR sentences"});
  spec.attitude_topic = "/imu";
  ExpectContains(MessageOf<io::InputError>([&] { ReadAttitudeLog(spec); }),
                 {"attitude.topic '/imu' given, but this is a text log"});
}

// The real Husky bag (robot_localization-test1.bag of the shared real test data): its /imu/data
// is a sensor_msgs/Imu whose driver fills the orientation of its own frame, which is turned on
// the robot: the roll reads 85° to 90°. No sample is the vehicle's attitude; each is counted,
// and the stream is an error naming the topic, never a roll of 88° in silence.
TEST(AttitudeStreamRealTest, TheHuskyBagsImuIsNotTheRobotsAttitude) {
  const std::string bag =
      WALLCAL_SOURCE_DIR "/../shared/testdata/real/ros1/robot_localization-test1.bag";
  if (!std::filesystem::exists(bag)) GTEST_SKIP() << "shared test data absent (" << bag << ")";
  io::SessionSpec spec;
  spec.attitude_log = bag;
  spec.attitude_topic = "/imu/data";
  ExpectContains(MessageOf<io::InputError>([&] { ReadAttitudeLog(spec); }),
                 {bag + ": attitude.topic /imu/data: no attitude sample (messages: 11865; "
                        "skipped: roll or pitch beyond 30 deg: ",
                  "expected sensor_msgs/Imu messages with the vehicle's orientation"});
  // Each message decodes, and its angles are those of an IMU on its side.
  std::unique_ptr<Recording> recording = OpenRecording(bag);
  int64_t messages = 0;
  QuaternionMsg msg;
  recording->ForEach({"/imu/data"}, [&](const RecordedMessage& m) {
    ASSERT_TRUE(DecodeImu(m.data, m.size, m.wire, &msg).ok());
    double roll_rad = 0.0, pitch_rad = 0.0;
    RollPitchFromEnuQuaternion(msg.x, msg.y, msg.z, msg.w, &roll_rad, &pitch_rad);
    if (msg.orientation_covariance[0] != -1.0) {
      ASSERT_GT(std::abs(roll_rad), 80.0 * kDegToRad) << m.index;
      ASSERT_LT(std::abs(pitch_rad), 10.0 * kDegToRad) << m.index;
    }
    ++messages;
  });
  EXPECT_EQ(messages, 11865);
}

}  // namespace
}  // namespace wallcal::recording
