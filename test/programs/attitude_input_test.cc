// SPDX-License-Identifier: Apache-2.0
// Mistaken scanner heights and tilts and hostile attitude streams, at the program level:
// `calibrate` and `inspect` on a copy of samples/lms291-sapporo. Each is a clear error naming
// the file and line (exit 2, nothing written) or a skip counted and reported; never a number
// made from it in silence.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "common/angles.h"
#include "io/writers/writers.h"
#include "recording/attitude_stream.h"
#include "recording/writers/rosbag1_writer.h"
#include "test/support/expect_text.h"
#include "test/support/program_runner.h"
#include "test/support/sample_session.h"
#include "test/support/scratch_files.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;
using testing_support::ExpectContains;
using testing_support::ReplaceInFile;
using testing_support::RunWallcal;

class AttitudeInputTest : public testing_support::SampleSessionTest {
 protected:
  // `wallcal calibrate S --output out.yaml --quiet`.
  testing_support::ProgramRun Calibrate() const {
    return RunWallcal({"calibrate", session_.string(), "--output", output().string(), "--quiet"});
  }
  fs::path output() const { return root_ / "out.yaml"; }
  std::string session_yaml() const { return (session_ / "session.yaml").string(); }

  // imu.bag beside the session: /imu, one sensor_msgs/Imu a second over the sample's 46 s,
  // those whose index is in `without` without orientation (orientation_covariance[0] = -1).
  void WriteImuBag(const std::vector<int>& without) const {
    recording::Ros1BagWriter writer((session_ / "imu.bag").string(),
                                    recording::ChunkCompression::kNone);
    const int imu = writer.AddConnection("/imu", recording::RosType::kImu);
    for (int i = 0; i < 46; ++i) {
      recording::QuaternionMsg m;
      m.from_imu = true;
      m.header.stamp_s = 1747031522.0 + i;
      const recording::UnitQuaternion q =
          recording::EnuQuaternionFromAttitude(0.5 * kDegToRad, 1.0 * kDegToRad, 0.6);
      m.x = q.x;
      m.y = q.y;
      m.z = q.z;
      m.w = q.w;
      if (std::find(without.begin(), without.end(), i) != without.end()) {
        m.orientation_covariance[0] = -1.0;
      }
      writer.Write(imu, m.header.stamp_s, recording::EncodeImu(m, recording::WireFormat::kRos1));
    }
    writer.Close();
    ReplaceInFile(session_yaml(), "survey:\n", "attitude: {log: imu.bag, topic: /imu}\nsurvey:\n");
  }
};

TEST_F(AttitudeInputTest, AScannerHeightOf40MetresIsRefusedWithItsLine) {
  ReplaceInFile(session_yaml(), "  time_offset_s: 0\n", "  time_offset_s: 0\n  z_m: 40\n");
  for (const char* command : {"calibrate", "inspect"}) {
    const testing_support::ProgramRun run = std::string(command) == "calibrate"
                                                ? Calibrate()
                                                : RunWallcal({"inspect", session_.string()});
    EXPECT_EQ(run.exit_code, 2) << command << run.err;
    ExpectContains(run.err, {"session.yaml:6: scanner.z_m: 40 m is not a plausible height of the "
                             "scanner relative to the antenna; expected metres, e.g. -2.5 for a "
                             "scanner 2.5 m below the antenna"});
  }
  EXPECT_FALSE(fs::exists(output()));
}

TEST_F(AttitudeInputTest, AScannerPitchOf60DegreesIsRefusedWithItsLine) {
  ReplaceInFile(session_yaml(), "  time_offset_s: 0\n", "  time_offset_s: 0\n  pitch_deg: 60\n");
  const testing_support::ProgramRun run = Calibrate();
  EXPECT_EQ(run.exit_code, 2) << run.err;
  ExpectContains(run.err,
                 {"session.yaml:6: scanner.pitch_deg: 60 deg is not how a scanner is mounted"});
  EXPECT_FALSE(fs::exists(output()));
}

TEST_F(AttitudeInputTest, AnImuTopicWithoutOrientationIsRefusedNamingTopicAndFile) {
  std::vector<int> all;
  for (int i = 0; i < 46; ++i) all.push_back(i);
  WriteImuBag(all);
  const testing_support::ProgramRun run = Calibrate();
  EXPECT_EQ(run.exit_code, 2) << run.err;
  ExpectContains(run.err, {"imu.bag: attitude.topic /imu: every one of its 46 sensor_msgs/Imu "
                           "messages is without orientation (orientation_covariance[0] = -1)"});
  EXPECT_FALSE(fs::exists(output()));
  // inspect reports it among what blocks a calibration.
  const testing_support::ProgramRun inspect = RunWallcal({"inspect", session_.string()});
  EXPECT_EQ(inspect.exit_code, 0) << inspect.err;
  ExpectContains(inspect.out, {"attitude: unreadable: ", "every one of its 46"});
}

TEST_F(AttitudeInputTest, ImuMessagesWithoutOrientationAreCountedAndReported) {
  WriteImuBag({1, 5});
  const testing_support::ProgramRun inspect = RunWallcal({"inspect", session_.string()});
  EXPECT_EQ(inspect.exit_code, 0) << inspect.err;
  ExpectContains(inspect.out,
                 {"  attitude (topic /imu: sensor_msgs/Imu 44) (imu.bag): 44 records",
                  "    roll      +0.50° .. +0.50°", "    pitch     +1.00° .. +1.00°",
                  "    sigma     none given; attitude.sigma_deg 0.100° stands in",
                  "    skipped   Imu without orientation (covariance[0] = -1): 2, first at line 2",
                  "imu.bag: 2 attitude lines skipped"});
  const testing_support::ProgramRun run = Calibrate();
  EXPECT_EQ(run.exit_code, 0) << run.err;
}

TEST_F(AttitudeInputTest, PashrLinesWithBadChecksumsAreCountedInTheHeadingLog) {
  const std::string good = "PASHR,063202.10,35.00,T,+0.5000,+1.0000,0.00,0.0500,0.0500,,1,0";
  const std::string body = "1747031522.110 $" + good + "*" + io::NmeaChecksum(good) + "\n" +
                           "1747031522.210 $" + good + "*00\n";
  testing_support::WriteFile(
      (session_ / "heading.nmea").string(),
      testing_support::ReadFile((session_ / "heading.nmea").string()) + body);
  ReplaceInFile(session_yaml(), "survey:\n", "attitude: {log: heading.nmea}\nsurvey:\n");
  const testing_support::ProgramRun inspect = RunWallcal({"inspect", session_.string()});
  EXPECT_EQ(inspect.exit_code, 0) << inspect.err;
  ExpectContains(inspect.out,
                 {"  attitude ($PASHR 1) (heading.nmea): 1 records", "bad checksum: 1"});
  const testing_support::ProgramRun dump =
      RunWallcal({"inspect", session_.string(), "--dump", "attitude"});
  EXPECT_EQ(dump.exit_code, 0) << dump.err;
  ExpectContains(dump.out, {"time_s,roll_deg,pitch_deg,roll_sigma_deg,pitch_sigma_deg,line\n",
                            "1747031522.110000,0.500000000,1.000000000,0.050000000,0.050000000,"});
}

}  // namespace
}  // namespace wallcal
