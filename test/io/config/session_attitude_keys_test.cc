// SPDX-License-Identifier: Apache-2.0
// session.yaml's keys for a site that is not level: the scanner's height σ and tilt (in
// `scanner:` and in each `scanners:` entry), the plausibility of its height, and the
// `attitude:` stream; each value checked with its file and line, and written back by
// io::FormatSessionYaml to the same session.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "common/angles.h"
#include "io/config/session_reader.h"
#include "io/writers/writers.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;
using testing_support::ExpectContains;
using testing_support::MessageOf;
using testing_support::ScratchFolder;
using testing_support::WriteFile;

const char kRest[] = R"(gnss: {log: gnss.nmea}
heading: {log: heading.nmea}
survey:
  points: survey.csv
  control:
    - {id: C1, lat: 43.0712345, lon: 141.3398765, h: 72.31}
    - {id: C2, lat: 43.0713012, lon: 141.3401123, h: 72.29}
walls:
  - {id: north_wall, code: WALL1}
)";

// A session whose `scanner:` map has `scanner_keys` (one per line, indented) after model and
// log, and `extra` after the rest; returns the session.yaml path.
std::string Session(const std::string& name, const std::string& scanner_keys,
                    const std::string& extra = "") {
  const std::string dir = ScratchFolder(name);
  return WriteFile(dir + "/session.yaml", "scanner:\n  model: sick_lms291\n  log: scans.clf\n" +
                                              scanner_keys + kRest + extra);
}

TEST(SessionAttitudeKeysTest, DefaultsWhenNotGiven) {
  const SessionSpec spec = ReadSession(Session("defaults", ""));
  EXPECT_FALSE(spec.scanner_z_m.has_value());
  EXPECT_DOUBLE_EQ(spec.scanner_z_sigma_m, 0.02);
  EXPECT_FALSE(spec.scanner_tilt.given);
  EXPECT_DOUBLE_EQ(spec.scanner_tilt.pitch_rad, 0.0);
  EXPECT_NEAR(spec.scanner_tilt.sigma_rad, 0.2 * kDegToRad, 1e-15);
  EXPECT_TRUE(spec.attitude_log.empty());
  EXPECT_NEAR(spec.attitude_sigma_rad, 0.1 * kDegToRad, 1e-15);
}

TEST(SessionAttitudeKeysTest, ReadsTheScannersHeightTiltAndTheAttitudeStream) {
  const std::string path = Session("all", R"(  z_m: -0.85
  z_sigma_m: 0.005
  pitch_deg: 2.5
  roll_deg: -1.0
  tilt_sigma_deg: 0.5
)",
                                   R"(attitude:
  log: logs/run.bag
  topic: /imu/data
  stamp: receive
  time_offset_s: -0.02
  sigma_deg: 0.05
)");
  const SessionSpec spec = ReadSession(path);
  const std::string dir = fs::path(path).parent_path().string();
  ASSERT_TRUE(spec.scanner_z_m.has_value());
  EXPECT_DOUBLE_EQ(*spec.scanner_z_m, -0.85);
  EXPECT_DOUBLE_EQ(spec.scanner_z_sigma_m, 0.005);
  EXPECT_TRUE(spec.scanner_tilt.given);
  EXPECT_NEAR(spec.scanner_tilt.pitch_rad, 2.5 * kDegToRad, 1e-15);
  EXPECT_NEAR(spec.scanner_tilt.roll_rad, -1.0 * kDegToRad, 1e-15);
  EXPECT_NEAR(spec.scanner_tilt.sigma_rad, 0.5 * kDegToRad, 1e-15);
  EXPECT_EQ(spec.attitude_log, (fs::path(dir) / "logs/run.bag").string());
  EXPECT_EQ(spec.attitude_topic, "/imu/data");
  EXPECT_EQ(spec.attitude_stamp, StampSource::kReceive);
  EXPECT_DOUBLE_EQ(spec.attitude_time_offset_s, -0.02);
  EXPECT_NEAR(spec.attitude_sigma_rad, 0.05 * kDegToRad, 1e-15);

  // Written back, it reads back to the same session.
  const SessionSpec copy = ReadSession(WriteFile(dir + "/copy.yaml", FormatSessionYaml(spec)));
  EXPECT_DOUBLE_EQ(*copy.scanner_z_m, -0.85);
  EXPECT_DOUBLE_EQ(copy.scanner_z_sigma_m, 0.005);
  EXPECT_TRUE(copy.scanner_tilt.given);
  EXPECT_NEAR(copy.scanner_tilt.pitch_rad, spec.scanner_tilt.pitch_rad, 1e-15);
  EXPECT_NEAR(copy.scanner_tilt.roll_rad, spec.scanner_tilt.roll_rad, 1e-15);
  EXPECT_NEAR(copy.scanner_tilt.sigma_rad, spec.scanner_tilt.sigma_rad, 1e-15);
  EXPECT_EQ(copy.attitude_log, spec.attitude_log);
  EXPECT_EQ(copy.attitude_topic, "/imu/data");
  EXPECT_EQ(copy.attitude_stamp, StampSource::kReceive);
  EXPECT_DOUBLE_EQ(copy.attitude_time_offset_s, -0.02);
  EXPECT_NEAR(copy.attitude_sigma_rad, spec.attitude_sigma_rad, 1e-15);
}

TEST(SessionAttitudeKeysTest, TheSameKeysInEachScannersEntry) {
  const std::string dir = ScratchFolder("several");
  const std::string path = WriteFile(dir + "/session.yaml", std::string(R"(scanners:
  - id: front
    model: sick_lms291
    log: front.clf
    z_m: -0.6
    pitch_deg: -3
    tilt_sigma_deg: 1
  - id: rear
    model: sick_lms291
    log: rear.clf
    z_sigma_m: 0.05
    roll_deg: 0.5
)") + kRest);
  const SessionSpec spec = ReadSession(path);
  ASSERT_EQ(spec.scanners.size(), 2u);
  EXPECT_DOUBLE_EQ(*spec.scanners[0].z_m, -0.6);
  EXPECT_NEAR(spec.scanners[0].tilt.pitch_rad, -3.0 * kDegToRad, 1e-15);
  EXPECT_NEAR(spec.scanners[0].tilt.sigma_rad, 1.0 * kDegToRad, 1e-15);
  EXPECT_FALSE(spec.scanners[1].z_m.has_value());
  EXPECT_DOUBLE_EQ(spec.scanners[1].z_sigma_m, 0.05);
  EXPECT_TRUE(spec.scanners[1].tilt.given);
  EXPECT_NEAR(spec.scanners[1].tilt.roll_rad, 0.5 * kDegToRad, 1e-15);
  // Each scanner's one-scanner session carries its own.
  const SessionSpec rear = SessionForScanner(spec, 1);
  EXPECT_DOUBLE_EQ(rear.scanner_z_sigma_m, 0.05);
  EXPECT_NEAR(rear.scanner_tilt.roll_rad, 0.5 * kDegToRad, 1e-15);
  // And written back, read back.
  const SessionSpec copy = ReadSession(WriteFile(dir + "/copy.yaml", FormatSessionYaml(spec)));
  EXPECT_NEAR(copy.scanners[0].tilt.pitch_rad, spec.scanners[0].tilt.pitch_rad, 1e-15);
  EXPECT_DOUBLE_EQ(copy.scanners[1].z_sigma_m, 0.05);
  EXPECT_TRUE(copy.scanners[1].tilt.given);
}

TEST(SessionAttitudeKeysTest, AHeightOf40MetresIsNotAScannersHeight) {
  const std::string path = Session("z40", "  z_m: 40\n");
  const std::string message = MessageOf<InputError>([&] { ReadSession(path); });
  ExpectContains(message, {path + ":4: scanner.z_m: 40 m is not a plausible height of the "
                                  "scanner relative to the antenna; expected metres, e.g. -2.5 "
                                  "for a scanner 2.5 m below the antenna"});
}

TEST(SessionAttitudeKeysTest, APitchOf60DegreesIsNotHowAScannerIsMounted) {
  const std::string path = Session("pitch60", "  pitch_deg: 60\n");
  ExpectContains(
      MessageOf<InputError>([&] { ReadSession(path); }),
      {path + ":4: scanner.pitch_deg: 60 deg is not how a scanner is mounted", "within ±45"});
  const std::string roll = Session("roll", "  roll_deg: -45.5\n");
  ExpectContains(MessageOf<InputError>([&] { ReadSession(roll); }),
                 {roll + ":4: scanner.roll_deg: -45.5 deg"});
}

TEST(SessionAttitudeKeysTest, RefusesBadValuesWithTheirLine) {
  const struct {
    std::string scanner_keys, extra, part;
  } cases[] = {
      {"  z_sigma_m: 0\n", "", ":4: scanner.z_sigma_m: expected the tape's 1σ in metres, > 0"},
      {"  tilt_sigma_deg: -1\n", "", ":4: scanner.tilt_sigma_deg: expected the tilt's 1σ"},
      {"  z_m: .nan\n", "", ":4: scanner.z_m: expected a finite number"},
      {"", "attitude: {log: a.nmea, sigma_deg: 0}\n", ":13: attitude.sigma_deg: expected one"},
      {"", "attitude: {log: a.nmea, stamp: arrival}\n", ":13: attitude.stamp: expected header"},
      {"", "attitude: {log: a.nmea, time_offset_s: 1e11}\n", ":13: attitude.time_offset_s"},
      {"", "attitude: {topic: /imu}\n", ":13: attitude.log is missing"},
      {"", "attitude: {log: a.nmea, sigma: 0.1}\n", ":13: unknown key 'attitude.sigma'"},
      {"  tilt_deg: 1\n", "", ":4: unknown key 'scanner.tilt_deg'"},
  };
  int n = 0;
  for (const auto& c : cases) {
    const std::string path = Session("bad" + std::to_string(n++), c.scanner_keys, c.extra);
    ExpectContains(MessageOf<InputError>([&] { ReadSession(path); }), {path + c.part});
  }
}

}  // namespace
}  // namespace wallcal::io
