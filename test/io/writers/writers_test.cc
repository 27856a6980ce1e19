// SPDX-License-Identifier: Apache-2.0
#include "io/writers/writers.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "io/text/carmen_reader.h"
#include "io/text/nmea_reader.h"
#include "io/config/session_reader.h"
#include "io/survey/survey_reader.h"
#include "common/angles.h"
#include "test/support/scratch_files.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;
using testing_support::FreshScratchFolder;
using testing_support::WriteFile;

TEST(WritersTest, NmeaChecksumOfTheSessionExample) {
  EXPECT_EQ(NmeaChecksum("HEHDT,123.456,T"), "28");
  EXPECT_EQ(
      NmeaChecksum("GNGGA,051202.10,4304.27407,N,14120.39259,E,4,14,0.7,53.10,M,19.21,M,1.0,0000"),
      "64");
  EXPECT_EQ(NmeaChecksum("GPHDT,,T"), "1B");
}

TEST(WritersTest, NmeaLinesReadBack) {
  GnssFix north_east;
  north_east.stamp_s = 1747031522.125;  // 2025-05-12 06:32:02.125 UTC (10 ms field: .12/.13)
  north_east.lat_deg = 43.07123456789;
  north_east.lon_deg = 141.33987654321;
  north_east.height_m = 72.3105;
  north_east.quality = 4;
  north_east.satellites = 14;
  north_east.hdop = 0.7;
  north_east.sigma_lat_m = 0.012;
  north_east.sigma_lon_m = 0.015;
  GnssFix south_west = north_east;
  south_west.stamp_s += 0.1;
  south_west.lat_deg = -33.99999999999;  // rounds up to whole degrees in the minutes field
  south_west.lon_deg = -0.00000012345;
  south_west.quality = 5;
  south_west.hdop = kNaN;
  const double headings_rad[] = {0.0, 1.2345678, 2 * kPi - 1e-9, 4.0};

  std::string log;
  for (const GnssFix& fix : {north_east, south_west}) {
    log += FormatGstLine(fix) + "\n" + FormatGgaLine(fix) + "\n";
  }
  for (int i = 0; i < 4; ++i) log += FormatHdtLine(1747031523.0 + i * 0.05, headings_rad[i]) + "\n";
  EXPECT_EQ(FormatGgaLine(north_east).find('\n'), std::string::npos);
  EXPECT_EQ(FormatGgaLine(north_east).rfind("1747031522.125 $GNGGA,063202.1", 0), 0u)
      << FormatGgaLine(north_east);

  const NmeaLog nmea = ReadNmea(WriteFile(FreshScratchFolder("nmea") + "/gnss.nmea", log));
  EXPECT_EQ(nmea.skipped.Total(), 0);
  ASSERT_EQ(nmea.fixes.size(), 2u);
  const GnssFix* expected[] = {&north_east, &south_west};
  for (size_t i = 0; i < 2; ++i) {
    const GnssFix& fix = nmea.fixes[i];
    SCOPED_TRACE(i);
    EXPECT_NEAR(fix.stamp_s, expected[i]->stamp_s, 1e-6);
    EXPECT_NEAR(fix.lat_deg, expected[i]->lat_deg, 1e-9);
    EXPECT_NEAR(fix.lon_deg, expected[i]->lon_deg, 1e-9);
    EXPECT_NEAR(fix.height_m, expected[i]->height_m, 1e-4);
    EXPECT_EQ(fix.quality, expected[i]->quality);
    EXPECT_EQ(fix.satellites, 14);
    EXPECT_NEAR(fix.sigma_lat_m, 0.012, 1e-9);
    EXPECT_NEAR(fix.sigma_lon_m, 0.015, 1e-9);
  }
  EXPECT_DOUBLE_EQ(nmea.fixes[0].hdop, 0.7);
  EXPECT_TRUE(std::isnan(nmea.fixes[1].hdop));
  ASSERT_EQ(nmea.headings.size(), 4u);
  EXPECT_NEAR(nmea.headings[0].heading_rad, 0.0, 1e-6);
  EXPECT_NEAR(nmea.headings[1].heading_rad, 1.2345678, 1e-6);
  EXPECT_NEAR(nmea.headings[2].heading_rad, 0.0, 1e-6);  // 359.99999.. deg prints as 0.0000
  EXPECT_NEAR(nmea.headings[3].heading_rad, 4.0, 1e-6);
  EXPECT_DOUBLE_EQ(nmea.headings[3].stamp_s, 1747031523.15);
}

TEST(WritersTest, RawlaserLineReadsBack) {
  ScanRecord scan;
  scan.stamp_s = 1747031522.123456;
  scan.start_angle_rad = -kPi / 2;
  scan.angular_step_rad = kPi / 360;
  scan.max_range_m = 80.0;
  for (int i = 0; i < 361; ++i) scan.ranges_m.push_back(1.0f + 0.0137f * static_cast<float>(i));
  const std::string line = FormatCarmenRawlaser(scan);
  EXPECT_EQ(line.rfind("RAWLASER1 0 ", 0), 0u);
  EXPECT_NE(line.find(" wallcal-sim 1747031522.123456"), std::string::npos);
  EXPECT_EQ(line.find('\n'), std::string::npos);

  CarmenReader reader(WriteFile(FreshScratchFolder("carmen") + "/scans.clf", line + "\n"));
  ScanRecord read;
  ASSERT_TRUE(reader.Next(&read));
  EXPECT_DOUBLE_EQ(read.stamp_s, scan.stamp_s);
  EXPECT_DOUBLE_EQ(read.start_angle_rad, scan.start_angle_rad);
  EXPECT_DOUBLE_EQ(read.angular_step_rad, scan.angular_step_rad);
  EXPECT_DOUBLE_EQ(read.max_range_m, 80.0);
  ASSERT_EQ(read.ranges_m.size(), 361u);
  for (size_t i = 0; i < 361; ++i)
    EXPECT_NEAR(read.ranges_m[i], scan.ranges_m[i], 0.00051) << i;  // mm
  EXPECT_FALSE(reader.Next(&read));
  EXPECT_EQ(reader.skipped().Total(), 0);
}

TEST(WritersTest, SurveyCsvReadsBack) {
  const std::vector<SurveyPoint> points = {{"C1", "CTRL", 0.0, 0.0, 0.0, 0},
                                           {"W001", "WALL1", 1.00249, -10.0131, 0.512, 0}};
  const std::string text = FormatSurveyCsv(points);
  EXPECT_EQ(text.rfind("id,x,y,z,code\n", 0), 0u);
  const std::vector<SurveyPoint> read = ReadSurvey(WriteFile(FreshScratchFolder("survey") + "/survey.csv", text));
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[1].id, "W001");
  EXPECT_EQ(read[1].code, "WALL1");
  EXPECT_NEAR(read[1].x_m, 1.0025, 1e-12);
  EXPECT_NEAR(read[1].y_m, -10.0131, 1e-12);
  EXPECT_NEAR(read[1].z_m, 0.512, 1e-12);
}

TEST(WritersTest, SessionYamlRoundTrips) {
  const std::string dir = FreshScratchFolder("session");
  SessionSpec spec;
  spec.dir = dir;
  spec.name = "simulated";
  spec.scanner_model = "sick_lms291";
  spec.scanner_log = dir + "/scans.clf";
  spec.scanner_time_offset_s = 0.02;
  spec.gnss_log = dir + "/gnss.nmea";
  spec.heading_log = dir + "/heading.nmea";
  spec.survey_points = dir + "/survey.csv";
  spec.control = {{"C1", 43.07, 141.34, 70.0, 0}, {"C2", 43.0701234567891, 141.3401, 70.5, 0}};
  spec.walls = {{"north", "WALL1"}, {"true", "yes"}};  // words YAML would take for booleans
  const std::string text = FormatSessionYaml(spec);
  EXPECT_NE(text.find("log: scans.clf\n"), std::string::npos) << text;  // relative to the folder
  const SessionSpec read = ReadSession(WriteFile(dir + "/session.yaml", text));
  EXPECT_EQ(read.name, "simulated");
  EXPECT_FALSE(read.utm_zone.has_value());
  EXPECT_EQ(read.scanner_log, fs::path(spec.scanner_log).lexically_normal().string());
  EXPECT_EQ(read.survey_points, fs::path(spec.survey_points).lexically_normal().string());
  EXPECT_DOUBLE_EQ(read.scanner_time_offset_s, 0.02);
  ASSERT_EQ(read.control.size(), 2u);
  EXPECT_DOUBLE_EQ(read.control[1].lat_deg, 43.0701234567891);  // full precision
  EXPECT_EQ(read.walls[1].id, "true");
  EXPECT_EQ(read.walls[1].code, "yes");
  EXPECT_FALSE(read.mount_guess.has_value());
  EXPECT_FALSE(read.antenna_in_base.has_value());
}

}  // namespace
}  // namespace wallcal::io
