// SPDX-License-Identifier: Apache-2.0
// Sessions whose streams are robot recordings (session.yaml `topic:`), end to end, and the
// message -> record conversions of io/recording_streams.h.
//
// The end-to-end check: one simulated session, written as text and converted to each
// recording format, must calibrate to the same mount within 0.1 σ. The recordings carry the
// same numbers as the text logs (float ranges bit for bit, stamps to the nanosecond, headings
// as quaternions of the logged value), so the only differences are rounding: far below 0.1 σ
// (σ is millimetres; rounding is nanometres). The scenario keeps 10 % of the time in RTK float
// (σ ×10 = 0.15 m in GST): the text session drops them by quality (min_fix_quality 4), the
// recordings by gnss.max_sigma_m (0.05 m), so both paths must drop the same fixes.

#include "sim/recording_session.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/angles.h"
#include "io/config/session_reader.h"
#include "io/text/nmea_reader.h"
#include "pipeline/calibration.h"
#include "recording/recording_streams.h"
#include "recording/writers/rosbag1_writer.h"
#include "sim/simulated_session.h"
#include "test/support/expect_text.h"
#include "test/support/program_runner.h"
#include "test/support/scratch_files.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

using testing_support::ReplaceInFile;
using testing_support::FreshScratchDir;

// A short stop-and-go scenario (6 stations of 3 s): a calibration takes about a second.
sim::SimulationConfig ShortScenario() {
  sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/lms291_sapporo.yaml");
  config.num_stations = 6;
  config.dwell_s = 3.0;
  config.float_fraction = 0.1;
  return config;
}

// The text session, simulated once per test process.
const fs::path& TextSession() {
  static const fs::path dir = [] {
    const fs::path d = FreshScratchDir("text");
    sim::WriteSimulatedSession(ShortScenario(), 5, d.string());
    return d;
  }();
  return dir;
}

fs::path SessionAs(const std::string& format) {
  const fs::path dir = FreshScratchDir(format);
  fs::copy(TextSession(), dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  sim::ConvertSessionToRecording(dir.string(), *sim::ParseSessionFormat(format));
  return dir;
}

pipeline::CalibrationResult Calibrate(const fs::path& dir) {
  pipeline::CalibrateRequest request;
  request.session_path = dir.string();
  return pipeline::RunCalibration(request, nullptr);
}

using testing_support::CommandRun;
using testing_support::RunCommand;

const std::string kCalibrate = testing_support::WallcalCommand("calibrate");

TEST(RecordingSessionTest, EveryFormatCalibratesToTheSameMount) {
  const pipeline::CalibrationResult text = Calibrate(TextSession());
  ASSERT_TRUE(text.solve.estimate.usable) << text.solve.estimate.message;
  const Eigen::Matrix3d& cov = text.solve.estimate.covariance;
  const double sx = std::sqrt(cov(0, 0)), sy = std::sqrt(cov(1, 1)), syaw = std::sqrt(cov(2, 2));
  for (const std::string format : {"ros1", "ros1-bz2", "ros1-lz4", "mcap", "db3"}) {
    SCOPED_TRACE(format);
    const pipeline::CalibrationResult r = Calibrate(SessionAs(format));
    ASSERT_TRUE(r.solve.estimate.usable) << r.solve.estimate.message;
    std::printf("[ formats  ] %-9s x %.6f y %.6f yaw %.6f deg; text x %.6f y %.6f yaw %.6f\n",
                format.c_str(), r.solve.estimate.mount.x_m, r.solve.estimate.mount.y_m,
                r.solve.estimate.mount.yaw_rad * kRadToDeg, text.solve.estimate.mount.x_m,
                text.solve.estimate.mount.y_m, text.solve.estimate.mount.yaw_rad * kRadToDeg);
    EXPECT_LT(std::abs(r.solve.estimate.mount.x_m - text.solve.estimate.mount.x_m), 0.1 * sx);
    EXPECT_LT(std::abs(r.solve.estimate.mount.y_m - text.solve.estimate.mount.y_m), 0.1 * sy);
    EXPECT_LT(std::abs(r.solve.estimate.mount.yaw_rad - text.solve.estimate.mount.yaw_rad),
              0.1 * syaw);
    EXPECT_EQ(r.detection.scans_total, text.detection.scans_total);
    EXPECT_EQ(r.poses.fixes_used, text.poses.fixes_used);  // float fixes dropped by σ as by quality
    EXPECT_EQ(r.poses.headings_used, text.poses.headings_used);
  }
}

// nmea_msgs/Sentence (GGA, GST, HDT through the text reader) and sensor_msgs/Imu, in one ROS 1
// bag whose receive times are the logger stamps + 0.25 s.
TEST(RecordingSessionTest, SentencesImuAndReceiveStamps) {
  const fs::path dir = FreshScratchDir("sentences");
  fs::copy(TextSession(), dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  const io::NmeaLog text_gnss = io::ReadNmea((dir / "gnss.nmea").string());
  const io::NmeaLog text_heading = io::ReadNmea((dir / "heading.nmea").string());
  {
    recording::Ros1BagWriter bag((dir / "poses.bag").string(), recording::ChunkCompression::kNone);
    const int nmea = bag.AddConnection("/nmea", recording::RosType::kNmeaSentence);
    const int imu = bag.AddConnection("/imu", recording::RosType::kImu);
    std::ifstream in(dir / "gnss.nmea");
    std::string line;
    while (std::getline(in, line)) {
      recording::NmeaSentenceMsg msg;
      const size_t space = line.find(' ');
      msg.header.stamp_s = std::stod(line.substr(0, space));
      msg.sentence = line.substr(space + 1);
      bag.Write(nmea, msg.header.stamp_s + 0.25,
                recording::EncodeNmeaSentence(msg, recording::WireFormat::kRos1));
    }
    for (const io::HeadingSample& h : text_heading.headings) {
      recording::QuaternionMsg msg;
      msg.header.stamp_s = h.stamp_s;
      const double yaw = kPi / 2 - h.heading_rad;
      msg.z = std::sin(yaw / 2);
      msg.w = std::cos(yaw / 2);
      bag.Write(imu, h.stamp_s + 0.25, recording::EncodeImu(msg, recording::WireFormat::kRos1));
    }
    bag.Close();
  }
  ReplaceInFile(dir / "session.yaml", "  log: gnss.nmea\n", "  log: poses.bag\n  topic: /nmea\n");
  ReplaceInFile(dir / "session.yaml", "  log: heading.nmea\n", "  log: poses.bag\n  topic: /imu\n");
  io::SessionSpec spec = io::ReadSession(dir.string());
  recording::PoseLogs logs = recording::ReadPoseLogs(spec);
  ASSERT_EQ(logs.gnss.fixes.size(), text_gnss.fixes.size());
  ASSERT_EQ(logs.headings.headings.size(), text_heading.headings.size());
  EXPECT_EQ(logs.gnss.fixes_by_quality, text_gnss.fixes_by_quality);  // GGA qualities kept
  for (size_t i = 0; i < text_gnss.fixes.size(); i += 50) {
    EXPECT_NEAR(logs.gnss.fixes[i].stamp_s, text_gnss.fixes[i].stamp_s, 1e-6);  // header stamp
    EXPECT_DOUBLE_EQ(logs.gnss.fixes[i].lat_deg, text_gnss.fixes[i].lat_deg);
    EXPECT_DOUBLE_EQ(logs.gnss.fixes[i].sigma_lat_m, text_gnss.fixes[i].sigma_lat_m);  // GST
  }
  for (size_t i = 0; i < text_heading.headings.size(); i += 50) {
    EXPECT_NEAR(logs.headings.headings[i].heading_rad, text_heading.headings[i].heading_rad, 1e-9);
    EXPECT_EQ(logs.headings.headings[i].line, static_cast<int>(i + 1));  // message index + 1
  }
  spec.gnss_stamp = io::StampSource::kReceive;
  spec.heading_stamp = io::StampSource::kReceive;
  logs = recording::ReadPoseLogs(spec);
  ASSERT_FALSE(logs.gnss.fixes.empty());
  EXPECT_NEAR(logs.gnss.fixes[3].stamp_s - text_gnss.fixes[3].stamp_s, 0.25, 1e-6);
  EXPECT_NEAR(logs.headings.headings[3].stamp_s - text_heading.headings[3].stamp_s, 0.25, 1e-6);
  // The whole session with these streams calibrates (header stamps).
  EXPECT_TRUE(Calibrate(dir).solve.estimate.usable);

  ReplaceInFile(dir / "session.yaml", "  topic: /nmea\n", "  topic: /nmea\n  stamp: later\n");
  try {
    io::ReadSession(dir.string());
    ADD_FAILURE() << "stamp: later accepted";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("header"), std::string::npos) << e.what();
  }
}

TEST(RecordingSessionTest, WrongTypeMissingTopicAndPresetMismatchExitTwoWithTheNames) {
  const fs::path dir = SessionAs("ros1-lz4");
  ReplaceInFile(dir / "session.yaml", "  topic: \"/fix\"\n", "  topic: /heading\n");
  CommandRun run = RunCommand(kCalibrate + " " + dir.string());
  EXPECT_EQ(run.status, 2) << run.out;
  EXPECT_NE(run.out.find("topic /heading has type geometry_msgs/QuaternionStamped"),
            std::string::npos) << run.out;
  EXPECT_NE(run.out.find("sensor_msgs/NavSatFix or nmea_msgs/Sentence"), std::string::npos)
      << run.out;

  ReplaceInFile(dir / "session.yaml", "  topic: /heading\n", "  topic: /gps/fix\n");
  run = RunCommand(kCalibrate + " " + dir.string());
  testing_support::ExpectExitSaying(run.status, 2, run.out, {
      "no topic '/gps/fix'",
      "/fix (sensor_msgs/NavSatFix)",
      "/scan (sensor_msgs/LaserScan)"
  });

  ReplaceInFile(dir / "session.yaml", "  topic: /gps/fix\n", "  topic: /fix\n");
  ReplaceInFile(dir / "session.yaml", "model: sick_lms291", "model: hokuyo_urg04lx");
  run = RunCommand(kCalibrate + " " + dir.string());
  testing_support::ExpectExitSaying(run.status, 2, run.out, {
      "181 beams",
      "the preset hokuyo_urg04lx has 682 beams",
      "another scanner",
      "topic /scan message 1"
  });
}

TEST(RecordingSessionTest, TopicOnATextLogIsAnError) {
  const fs::path dir = FreshScratchDir("topic_on_text");
  fs::copy(TextSession(), dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  ReplaceInFile(dir / "session.yaml", "  log: gnss.nmea\n", "  log: gnss.nmea\n  topic: /fix\n");
  const CommandRun run = RunCommand(kCalibrate + " " + dir.string());
  EXPECT_EQ(run.status, 2) << run.out;
  EXPECT_NE(run.out.find("gnss.topic '/fix' given, but this is a text log"), std::string::npos)
      << run.out;
}

TEST(RecordingStreamsTest, LaserScanOutOfRangeIsNoReturnAndNegativeIncrementKept) {
  recording::LaserScanMsg msg;
  msg.angle_min_rad = 1.0f;
  msg.angle_increment_rad = -0.5f;
  msg.range_min_m = 0.1f;
  msg.range_max_m = 30.0f;
  msg.ranges_m = {5.0f, NAN, INFINITY, -INFINITY, 0.05f, 31.0f, 29.5f};
  const io::ScanRecord scan = recording::ScanFromLaserScan(msg, 12.5, 7);
  EXPECT_DOUBLE_EQ(scan.stamp_s, 12.5);
  EXPECT_EQ(scan.line, 7);
  EXPECT_DOUBLE_EQ(scan.angular_step_rad, -0.5);
  EXPECT_DOUBLE_EQ(scan.max_range_m, 30.0);
  ASSERT_EQ(scan.ranges_m.size(), 7u);
  EXPECT_EQ(scan.ranges_m[0], 5.0f);
  for (int i = 1; i <= 5; ++i) EXPECT_EQ(scan.ranges_m[i], 30.0f) << i;  // no return
  EXPECT_EQ(scan.ranges_m[6], 29.5f);
}

TEST(RecordingStreamsTest, NavSatFixAcceptedBySigmaAndStatus) {
  recording::NavSatFixMsg msg;
  msg.status = 2;
  msg.latitude_deg = 43.0;
  msg.longitude_deg = 141.0;
  msg.altitude_m = 70.0;
  msg.position_covariance_type = 2;
  msg.position_covariance[0] = 0.02 * 0.02;  // east
  msg.position_covariance[4] = 0.03 * 0.03;  // north
  io::GnssFix fix = recording::FixFromNavSatFix(msg, 1.0, 0.05, 1);
  EXPECT_EQ(fix.quality, 4);
  EXPECT_NEAR(fix.sigma_lat_m, 0.03, 1e-12);
  EXPECT_NEAR(fix.sigma_lon_m, 0.02, 1e-12);
  EXPECT_DOUBLE_EQ(fix.height_m, 70.0);
  msg.position_covariance[0] = 0.3 * 0.3;  // float: σ east 0.3 m
  EXPECT_EQ(recording::FixFromNavSatFix(msg, 1.0, 0.05, 1).quality, 1);
  EXPECT_EQ(recording::FixFromNavSatFix(msg, 1.0, 0.5, 1).quality, 4);
  msg.status = -1;
  EXPECT_EQ(recording::FixFromNavSatFix(msg, 1.0, 0.5, 1).quality, 0);
  msg.status = 0;
  msg.position_covariance_type = 0;
  EXPECT_EQ(recording::FixFromNavSatFix(msg, 1.0, 0.05, 1).quality, 4);
}

TEST(RecordingStreamsTest, EnuYawBecomesHeadingClockwiseFromNorth) {
  auto heading_deg = [](double yaw_deg) {
    const double yaw = yaw_deg * kDegToRad;
    return recording::HeadingFromEnuQuaternion(0, 0, std::sin(yaw / 2), std::cos(yaw / 2)) *
           kRadToDeg;
  };
  EXPECT_NEAR(heading_deg(0.0), 90.0, 1e-9);     // facing east
  EXPECT_NEAR(heading_deg(90.0), 0.0, 1e-9);     // facing north
  EXPECT_NEAR(heading_deg(180.0), 270.0, 1e-9);  // facing west
  EXPECT_NEAR(heading_deg(-90.0), 180.0, 1e-9);  // facing south
  EXPECT_NEAR(heading_deg(120.0), 330.0, 1e-9);
}

}  // namespace
}  // namespace wallcal

namespace wallcal {
namespace {

const std::string kInspect = testing_support::WallcalCommand("inspect");
const std::string kRealRos1 = WALLCAL_SOURCE_DIR "/../shared/testdata/real/ros1";

TEST(InspectRecordingTest, SuggestSessionOnTheRealBagsProposesScanAndFix) {
  if (!fs::exists(kRealRos1)) GTEST_SKIP() << kRealRos1 << " absent (shared test data)";
  CommandRun run = RunCommand(kInspect + " " + kRealRos1 + "/scan_tools-demo.bag --suggest-session");
  EXPECT_EQ(run.status, 0) << run.out;
  EXPECT_NE(run.out.find("  topic: /scan  # sensor_msgs/LaserScan, 360 messages"), std::string::npos)
      << run.out;
  run = RunCommand(kInspect + " " + kRealRos1 + "/robot_localization-test1.bag --suggest-session");
  EXPECT_EQ(run.status, 0) << run.out;
  EXPECT_NE(run.out.find("  topic: /fix  # sensor_msgs/NavSatFix, 989 messages"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("  topic: /imu/data  # sensor_msgs/Imu"), std::string::npos) << run.out;
  // Its Imu is turned on the robot (a roll near 90°): no attitude stream proposed.
  EXPECT_NE(run.out.find("# attitude: not /imu/data: its orientation is not the vehicle's"),
            std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("\nattitude:"), std::string::npos) << run.out;
  run = RunCommand(kInspect + " " + kRealRos1 + "/robot_localization-test1.bag");
  EXPECT_EQ(run.status, 0) << run.out;
  EXPECT_NE(run.out.find("/husky_velocity_controller/odom [nav_msgs/Odometry]"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("989 records"), std::string::npos) << run.out;
}

TEST(InspectRecordingTest, SuggestedSessionOfASimulatedRecordingReadsBack) {
  const fs::path dir = SessionAs("mcap");
  const CommandRun suggest = RunCommand(kInspect + " " + (dir / "session.mcap").string() +
                                        " --suggest-session 2>/dev/null");
  ASSERT_EQ(suggest.status, 0) << suggest.out;
  EXPECT_NE(suggest.out.find("model: sick_lms291  # matches"), std::string::npos) << suggest.out;
  EXPECT_NE(suggest.out.find("topic: /heading  # geometry_msgs/msg/QuaternionStamped"),
            std::string::npos) << suggest.out;
  // Its control points are placeholders: read as they are, they are refused, naming the line.
  std::ofstream(dir / "suggested.yaml") << suggest.out;
  try {
    io::ReadSession((dir / "suggested.yaml").string());
    ADD_FAILURE() << "placeholder control points were read";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("placeholder"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("suggested.yaml:"), std::string::npos) << e.what();
  }
  // Filled in (the survey part is the user's), its session keys read back.
  std::string filled = suggest.out;
  for (const char* id : {"C1", "C2"}) {
    const std::string from = std::string("{id: ") + id + ", lat: 0.0, lon: 0.0";
    const size_t at = filled.find(from);
    ASSERT_NE(at, std::string::npos) << filled;
    filled.replace(at, from.size(), std::string("{id: ") + id + ", lat: 43.07, lon: " +
                                        (id[1] == '1' ? "141.34" : "141.35"));
  }
  std::ofstream(dir / "suggested.yaml", std::ios::trunc) << filled;
  const io::SessionSpec spec = io::ReadSession((dir / "suggested.yaml").string());
  EXPECT_EQ(spec.scanner_topic, "/scan");
  EXPECT_EQ(spec.gnss_topic, "/fix");
  EXPECT_EQ(spec.heading_topic, "/heading");
}

TEST(InspectRecordingTest, DumpsOfATopicMatchTheTextLogs) {
  const fs::path text = TextSession();
  const fs::path dir = SessionAs("ros1-bz2");
  const std::string bag = (dir / "session.bag").string();
  const CommandRun from_text = RunCommand(kInspect + " " + (text / "heading.nmea").string() +
                                          " --dump heading");
  const CommandRun from_bag = RunCommand(kInspect + " " + bag + " --dump heading --topic /heading");
  ASSERT_EQ(from_bag.status, 0) << from_bag.out;
  EXPECT_EQ(from_bag.out.substr(0, from_bag.out.find('\n')), "time_s,heading_deg,line");
  // Same rows count; headings equal to the text's 4 decimals.
  EXPECT_EQ(std::count(from_bag.out.begin(), from_bag.out.end(), '\n'),
            std::count(from_text.out.begin(), from_text.out.end(), '\n'));
  const CommandRun scans = RunCommand(kInspect + " " + bag + " --dump scans");
  EXPECT_EQ(scans.status, 0) << scans.out;  // one LaserScan topic: no --topic needed
  EXPECT_EQ(scans.out.rfind("time_s,beams,valid,min_range_m,max_range_m,line\n", 0), 0u);
  // Heading: QuaternionStamped only; two fitting topics for GNSS in a bag with /nmea too.
  const CommandRun wrong = RunCommand(kInspect + " " + bag + " --dump gnss --topic /scan");
  EXPECT_EQ(wrong.status, 2) << wrong.out;
  EXPECT_NE(wrong.out.find("topic /scan has type sensor_msgs/LaserScan"), std::string::npos)
      << wrong.out;
}

TEST(InspectRecordingTest, SeveralCandidateTopicsAreListed) {
  const fs::path dir = FreshScratchDir("two_fixes");
  {
    recording::Ros1BagWriter bag((dir / "two.bag").string(), recording::ChunkCompression::kNone);
    const int a = bag.AddConnection("/fix", recording::RosType::kNavSatFix);
    const int b = bag.AddConnection("/gps/fix", recording::RosType::kNavSatFix);
    recording::NavSatFixMsg msg;
    msg.header.stamp_s = 100.0;
    bag.Write(a, 100.0, recording::EncodeNavSatFix(msg, recording::WireFormat::kRos1));
    bag.Write(b, 100.0, recording::EncodeNavSatFix(msg, recording::WireFormat::kRos1));
    bag.Close();
  }
  const CommandRun run = RunCommand(kInspect + " " + (dir / "two.bag").string() + " --dump gnss");
  EXPECT_EQ(run.status, 2) << run.out;
  EXPECT_NE(run.out.find("several topics fit: /fix (sensor_msgs/NavSatFix), /gps/fix"),
            std::string::npos) << run.out;
  const CommandRun suggest =
      RunCommand(kInspect + " " + (dir / "two.bag").string() + " --suggest-session");
  EXPECT_NE(suggest.out.find("2 topics fit the GNSS"), std::string::npos) << suggest.out;
}

TEST(InspectRecordingTest, SurveyDumpIsEveryObservation) {
  const CommandRun run = RunCommand(kInspect + " " + (TextSession() / "survey.csv").string() +
                                    " --dump survey");
  EXPECT_EQ(run.status, 0) << run.out;
  EXPECT_EQ(run.out.rfind("id,x_m,y_m,z_m,code\n", 0), 0u) << run.out;
  EXPECT_EQ(std::count(run.out.begin(), run.out.end(), '\n'), 65);  // header + 64 points
}

}  // namespace
}  // namespace wallcal
