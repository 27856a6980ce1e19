// SPDX-License-Identifier: Apache-2.0
#include "io/text/nmea_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "io/writers/writers.h"
#include "common/angles.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;
using testing_support::WriteScratchFile;

// "$body*hh" with the right checksum.
std::string S(const std::string& body) { return "$" + body + "*" + NmeaChecksum(body); }

int64_t Count(const NmeaLog& log, const std::string& reason) {
  const auto it = log.skipped.by_reason.find(reason);
  return it == log.skipped.by_reason.end() ? 0 : it->second;
}

TEST(NmeaReaderTest, ReadsLoggerTimePrefixedSentences) {
  const std::string log =
      // The example of docs/session-format.md, checksum as printed there.
      "1747031522.113 $GNGGA,051202.10,4304.27407,N,14120.39259,E,4,14,0.7,53.10,M,19.21,M,"
      "1.0,0000*64\n"
      "1747031522.120 " +
      S("GNGST,051202.10,0.01,0.02,0.01,0.0,0.012,0.015,0.03") +
      "\n"
      "1747031522.150 $HEHDT,123.456,T*28\n"
      "1747031522.200 " +
      S("INTHS,123.45,A") + "\n";
  const NmeaLog nmea = ReadNmea(WriteScratchFile("prefixed.nmea", log));
  ASSERT_EQ(nmea.fixes.size(), 1u);
  const GnssFix& fix = nmea.fixes[0];
  EXPECT_DOUBLE_EQ(fix.stamp_s, 1747031522.113);
  EXPECT_NEAR(fix.lat_deg, 43.0 + 4.27407 / 60.0, 1e-12);
  EXPECT_NEAR(fix.lon_deg, 141.0 + 20.39259 / 60.0, 1e-12);
  EXPECT_NEAR(fix.height_m, 53.10 + 19.21, 1e-9);
  EXPECT_EQ(fix.quality, 4);
  EXPECT_EQ(fix.satellites, 14);
  EXPECT_DOUBLE_EQ(fix.hdop, 0.7);
  EXPECT_DOUBLE_EQ(fix.sigma_lat_m, 0.012);
  EXPECT_DOUBLE_EQ(fix.sigma_lon_m, 0.015);
  EXPECT_EQ(fix.line, 1);
  ASSERT_EQ(nmea.headings.size(), 2u);
  EXPECT_DOUBLE_EQ(nmea.headings[0].stamp_s, 1747031522.150);
  EXPECT_NEAR(nmea.headings[0].heading_rad, 123.456 * kDegToRad, 1e-12);
  EXPECT_DOUBLE_EQ(nmea.headings[1].stamp_s, 1747031522.200);
  EXPECT_NEAR(nmea.headings[1].heading_rad, 123.45 * kDegToRad, 1e-12);
  EXPECT_EQ(nmea.fixes_by_quality.at(4), 1);
  EXPECT_EQ(nmea.skipped.Total(), 0);
  EXPECT_EQ(nmea.lines_read, 4);
}

// LF, CRLF and a CR alone each end a line: the same records, with the same line numbers.
TEST(NmeaReaderTest, ReadsEveryLineEnd) {
  for (const std::string eol : {"\n", "\r\n", "\r"}) {
    SCOPED_TRACE(eol == "\r" ? "CR" : eol == "\n" ? "LF" : "CRLF");
    const std::string log =
        "1747031522.113 $GNGGA,051202.10,4304.27407,N,14120.39259,E,4,14,0.7,53.10,M,19.21,M,"
        "1.0,0000*64" + eol + "1747031522.150 $HEHDT,123.456,T*28" + eol +
        "1747031522.200 " + S("INTHS,123.45,A") + eol;
    const NmeaLog nmea = ReadNmea(WriteScratchFile("eol.nmea", log));
    ASSERT_EQ(nmea.fixes.size(), 1u);
    EXPECT_EQ(nmea.fixes[0].quality, 4);
    ASSERT_EQ(nmea.headings.size(), 2u);
    EXPECT_EQ(nmea.headings[1].line, 3);
    EXPECT_DOUBLE_EQ(nmea.headings[1].stamp_s, 1747031522.200);
    EXPECT_EQ(nmea.skipped.Total(), 0);
    EXPECT_EQ(nmea.lines_read, 3);
  }
}

TEST(NmeaReaderTest, AttachesGstBeforeOrAfterItsGga) {
  const std::string log = "100.0 " + S("GPGST,120000.00,,,,,0.5,0.6,1.0") +
                          "\n"  // before its GGA
                          "100.1 " +
                          S("GPGGA,120000.00,4000.0,N,10000.0,W,4,10,1.0,10.0,M,0.0,M,,") +
                          "\n"
                          "101.0 " +
                          S("GPGGA,120001.00,4000.0,N,10000.0,W,4,10,1.0,10.0,M,0.0,M,,") +
                          "\n"
                          "101.1 " +
                          S("GPGGA,120002.00,4000.0,N,10000.0,W,4,10,1.0,10.0,M,0.0,M,,") +
                          "\n"
                          "101.2 " +
                          S("GPGST,120001.00,,,,,0.7,0.8,1.0") +
                          "\n"  // after, one epoch late
                          "101.3 " +
                          S("GPGST,115959.00,,,,,0.1,0.1,1.0") + "\n";  // no GGA at all
  const NmeaLog nmea = ReadNmea(WriteScratchFile("gst.nmea", log));
  ASSERT_EQ(nmea.fixes.size(), 3u);
  EXPECT_DOUBLE_EQ(nmea.fixes[0].sigma_lat_m, 0.5);
  EXPECT_DOUBLE_EQ(nmea.fixes[0].sigma_lon_m, 0.6);
  EXPECT_DOUBLE_EQ(nmea.fixes[1].sigma_lat_m, 0.7);
  EXPECT_DOUBLE_EQ(nmea.fixes[1].sigma_lon_m, 0.8);
  EXPECT_TRUE(std::isnan(nmea.fixes[2].sigma_lat_m));
  EXPECT_EQ(Count(nmea, "GST without its GGA"), 1);
}

TEST(NmeaReaderTest, TimesPlainCaptureFromUtcAndDate) {
  // 2020-03-18 = 18339 days after 1970-01-01.
  const double day_s = 18339 * 86400.0;
  const std::string log =
      "# plain capture, no prefix\n" + S("GPHDT,10.0,T") + "\n" +  // nothing timed yet
      S("GNGGA,132819.60,4134.49795459,N,09345.03431408,W,2,10,0.9,278.161,M,-31.442,M,6.6,0133") +
      "\n" + S("GNHDT,20.0,T") + "\n" +
      S("GNRMC,132819.70,A,4134.49795443,N,09345.03431421,W,0.355,139.060,180320,11.5985,E,D") +
      "\n" + S("GNGGA,235959.90,4134.0,N,09345.0,W,4,10,0.9,278.0,M,-31.442,M,,") + "\n" +
      S("GNGGA,000000.10,4134.0,N,09345.0,W,4,10,0.9,278.0,M,-31.442,M,,") + "\n" +  // midnight
      S("GNTHS,30.0,A") + "\n";
  const NmeaLog nmea = ReadNmea(WriteScratchFile("plain.nmea", log));
  ASSERT_EQ(nmea.fixes.size(), 3u);
  // Before the RMC: the first date of the file.
  EXPECT_NEAR(nmea.fixes[0].stamp_s, day_s + 13 * 3600 + 28 * 60 + 19.6, 1e-6);
  EXPECT_NEAR(nmea.fixes[0].lat_deg, 41.0 + 34.49795459 / 60.0, 1e-12);
  EXPECT_NEAR(nmea.fixes[0].lon_deg, -(93.0 + 45.03431408 / 60.0), 1e-12);
  EXPECT_NEAR(nmea.fixes[0].height_m, 278.161 - 31.442, 1e-9);
  EXPECT_NEAR(nmea.fixes[1].stamp_s, day_s + 86399.9, 1e-6);
  EXPECT_NEAR(nmea.fixes[2].stamp_s, day_s + 86400.1, 1e-6);
  ASSERT_EQ(nmea.headings.size(), 2u);
  EXPECT_NEAR(nmea.headings[0].stamp_s, nmea.fixes[0].stamp_s, 1e-9);  // last timed sentence
  EXPECT_NEAR(nmea.headings[0].heading_rad, 20.0 * kDegToRad, 1e-12);
  EXPECT_NEAR(nmea.headings[1].stamp_s, nmea.fixes[2].stamp_s, 1e-9);
  EXPECT_EQ(Count(nmea, "no time yet"), 1);
  EXPECT_EQ(Count(nmea, "not NMEA"), 1);
}

TEST(NmeaReaderTest, SkipsAndCountsBadSentences) {
  const std::string good_gga = "GPGGA,120000.00,4000.0,N,10000.0,E,4,10,1.0,10.0,M,0.0,M,,";
  std::string bad_checksum = S("GPGGA,120001.00,4000.0,N,10000.0,E,4,10,1.0,10.0,M,0.0,M,,");
  bad_checksum[bad_checksum.size() - 1] = bad_checksum.back() == '0' ? '1' : '0';
  const std::string log =
      "1.0 " + S(good_gga) + "\n" + "2.0 " + bad_checksum + "\n" +
      "3.0 $GPGGA,120003.00,4000.0,N,10000.0,E,4,10,1.0,10.0,M,0.0,M,,\n" +  // no checksum
      "4.0 $GPHDT,,T*1B\n" +                                                 // empty field
      "5.0 " + S("GPTHS,10.0,V") + "\n" +                                    // invalid THS
      "6.0 " + S("GPHDT,abc,T") + "\n" +                                     // non-numeric
      "7.0 " + S("GPGGA,120007.00,9100.0,N,10000.0,E,4,10,1.0,10.0,M,0.0,M,,") + "\n" +
      std::string("\x01\x02\xb5\x62\x00\xff binary\n", 14) + "# a comment\n" + "\n" + "8.0 " +
      S("GPGSV,3,1,12,01,40,083,46") + "\n" + "9.0 " + S("GPGGA,,,,,,0,,,,M,,M,,") + "\n" +
      "10.0 " + S("GPGGA,120010.00,4000.0,X,10000.0,E,4,10,1.0,10.0,M,0.0,M,,") + "\n" +
      "\xb5\x62junk$GP" + S("GPHDT,45.0,T") + "\n" +  // junk before the sentence: kept
      "0.5 " + S("GPGGA,120011.00,4000.0,N,10000.0,E,4,10,1.0,10.0,M,0.0,M,,") + "\n" + "12.0 " +
      S("GPHDT,360.0,T") + "\n";
  const NmeaLog nmea = ReadNmea(WriteScratchFile("bad.nmea", log));
  ASSERT_EQ(nmea.fixes.size(), 1u);
  EXPECT_DOUBLE_EQ(nmea.fixes[0].stamp_s, 1.0);
  EXPECT_EQ(Count(nmea, "bad checksum"), 1);
  EXPECT_EQ(Count(nmea, "no checksum"), 1);
  EXPECT_EQ(Count(nmea, "empty field"), 1);
  EXPECT_EQ(Count(nmea, "THS status V"), 1);
  EXPECT_EQ(Count(nmea, "bad field"), 2);
  EXPECT_EQ(Count(nmea, "not NMEA"), 3);
  EXPECT_EQ(Count(nmea, "other sentence (GSV)"), 1);
  EXPECT_EQ(Count(nmea, "GGA without a fix"), 1);
  EXPECT_EQ(Count(nmea, "time not increasing"), 1);
  EXPECT_EQ(nmea.skipped.first_line.at("bad checksum"), 2);
  // lat 91 deg: 9100.0 has 100 whole degrees... in ddmm that is 91 deg 00': out of range.
  EXPECT_EQ(Count(nmea, "lat/lon out of range"), 1);
  ASSERT_EQ(nmea.headings.size(), 2u);
  // Junk before the sentence, no prefix: the time of the last timed sentence (line 1).
  EXPECT_DOUBLE_EQ(nmea.headings[0].stamp_s, 1.0);
  EXPECT_NEAR(nmea.headings[0].heading_rad, 45.0 * kDegToRad, 1e-12);
  EXPECT_DOUBLE_EQ(nmea.headings[1].stamp_s, 12.0);
  EXPECT_DOUBLE_EQ(nmea.headings[1].heading_rad, 0.0);  // 360 deg wraps to 0
  EXPECT_EQ(nmea.lines_read, 16);
  EXPECT_EQ(nmea.skipped.Total() + static_cast<int64_t>(nmea.fixes.size() + nmea.headings.size()),
            nmea.lines_read);
}

TEST(NmeaReaderTest, FindsTheSentenceAfterBinaryBytes) {
  const std::string log = "100.0 " +
                          S("GPGGA,120000.00,4000.0,N,10000.0,E,4,10,1.0,10.0,M,0.0,M,,") + "\n" +
                          "\xb5\x62$\x01*\x02" + S("GPHDT,45.0,T") + "\n";
  const NmeaLog nmea = ReadNmea(WriteScratchFile("junk.nmea", log));
  ASSERT_EQ(nmea.headings.size(), 1u);
  EXPECT_NEAR(nmea.headings[0].heading_rad, 45.0 * kDegToRad, 1e-12);
  EXPECT_DOUBLE_EQ(nmea.headings[0].stamp_s, 100.0);  // time of the last timed sentence
}

TEST(NmeaReaderTest, DatesAPlainCaptureFromZda) {
  // 2018-09-07 = 17781 days after 1970-01-01; ZDA carries day, month, year.
  const std::string log = S("GPZDA,120000.00,07,09,2018,00,00") + "\n" +
                          S("GPGGA,120000.50,4304.0,N,14120.0,E,4,12,0.8,50.0,M,20.0,M,,") + "\n";
  const NmeaLog nmea = ReadNmea(WriteScratchFile("zda.nmea", log));
  ASSERT_EQ(nmea.fixes.size(), 1u);
  EXPECT_NEAR(nmea.fixes[0].stamp_s, 17781 * 86400.0 + 43200.5, 1e-6);
}

// A binary message between sentences may contain newlines, '$' and '*': its fragments are
// skipped and counted, and the sentences on either side are read whole.
TEST(NmeaReaderTest, BinaryBlobAcrossLinesIsSkipped) {
  static const char kBlob[] = "\xd3\x00\x13\x3e\xd0$\x01*\x7f\n\x02$GPG\x00\n\xb5\x62\x01\x07*\xff";
  const std::string blob(kBlob, sizeof(kBlob) - 1);  // with its NUL bytes
  const std::string log = "1.000 " + S("GPGGA,000001.00,4304.0,N,14120.0,E,4,12,0.8,50.0,M,20.0,M,,") +
                          "\n" + blob + "\n" + "2.000 " +
                          S("GPGGA,000002.00,4305.0,N,14120.0,E,4,12,0.8,50.0,M,20.0,M,,") + "\n";
  const NmeaLog nmea = ReadNmea(WriteScratchFile("blob.nmea", log));
  ASSERT_EQ(nmea.fixes.size(), 2u);
  EXPECT_NEAR(nmea.fixes[0].lat_deg, 43.0 + 4.0 / 60.0, 1e-12);
  EXPECT_NEAR(nmea.fixes[1].lat_deg, 43.0 + 5.0 / 60.0, 1e-12);
  EXPECT_DOUBLE_EQ(nmea.fixes[1].stamp_s, 2.0);
  EXPECT_GE(nmea.skipped.Total(), 3);
}

TEST(NmeaReaderTest, ReadsSouthAndWest) {
  const std::string log =
      "1.0 " + S("GPGGA,120000.00,3352.1234567,S,15112.7654321,W,4,10,1.0,10.0,M,5.0,M,,") + "\n";
  const NmeaLog nmea = ReadNmea(WriteScratchFile("southwest.nmea", log));
  ASSERT_EQ(nmea.fixes.size(), 1u);
  EXPECT_NEAR(nmea.fixes[0].lat_deg, -(33.0 + 52.1234567 / 60.0), 1e-12);
  EXPECT_NEAR(nmea.fixes[0].lon_deg, -(151.0 + 12.7654321 / 60.0), 1e-12);
  EXPECT_NEAR(nmea.fixes[0].height_m, 15.0, 1e-12);
}

TEST(NmeaReaderTest, MissingFileNamesThePath) {
  const std::string path = ::testing::TempDir() + "/nmea_reader_test_no_such.nmea";
  testing_support::ExpectContains(
      testing_support::MessageOf<InputError>([&] { ReadNmea(path); }), {path});
}

// ---- Real receiver logs (gpsd's regression tests) against gpsd's decoding in the .chk ----

const std::string kRealNmeaDir = WALLCAL_SOURCE_DIR "/../shared/testdata/real/nmea/";

double JsonNumber(const std::string& line, const std::string& key, bool* found) {
  const std::string pattern = "\"" + key + "\":";
  const size_t at = line.find(pattern);
  *found = at != std::string::npos;
  return *found ? std::strtod(line.c_str() + at + pattern.size(), nullptr) : 0.0;
}

struct ChkFix {
  double lat_deg, lon_deg, alt_hae_m;
  int status;
};

// gpsd's TPV reports, keyed by the UTC time of day (ms) of the GGA or RMC sentence that preceded
// them (gpsd reports an epoch after its GGA or after its RMC). The first report of an epoch wins.
std::map<int64_t, ChkFix> ChkFixesByEpoch(const std::string& chk_path) {
  std::ifstream in(chk_path);
  std::map<int64_t, ChkFix> fixes;
  std::string line;
  int64_t epoch_ms = -1;
  while (std::getline(in, line)) {
    if (line.rfind("$", 0) == 0) {
      const size_t comma = line.find(',');
      const bool timed =
          comma != std::string::npos && comma >= 6 &&
          (line.compare(comma - 3, 3, "GGA") == 0 || line.compare(comma - 3, 3, "RMC") == 0) &&
          line.size() > comma + 7 && line[comma + 1] != ',';
      if (timed) {
        const int hours = std::stoi(line.substr(comma + 1, 2));
        const int minutes = std::stoi(line.substr(comma + 3, 2));
        const double seconds = std::strtod(line.c_str() + comma + 5, nullptr);
        epoch_ms = std::llround((hours * 3600 + minutes * 60 + seconds) * 1000.0);
      }
    } else if (epoch_ms >= 0 && line.find("\"class\":\"TPV\"") != std::string::npos) {
      bool has_lat = false, has_lon = false, has_alt = false, has_status = false;
      ChkFix fix{};
      fix.lat_deg = JsonNumber(line, "lat", &has_lat);
      fix.lon_deg = JsonNumber(line, "lon", &has_lon);
      fix.alt_hae_m = JsonNumber(line, "altHAE", &has_alt);
      fix.status = static_cast<int>(JsonNumber(line, "status", &has_status));
      if (has_lat && has_lon && has_alt) fixes.emplace(epoch_ms, fix);
    }
  }
  return fixes;
}

std::vector<double> ChkHeadingsDeg(const std::string& chk_path) {
  std::ifstream in(chk_path);
  std::vector<double> headings;
  std::string line;
  while (std::getline(in, line)) {
    if (line.find("\"class\":\"ATT\"") == std::string::npos) continue;
    bool found = false;
    const double heading = JsonNumber(line, "heading", &found);
    // gpsd repeats one heading in several ATT reports: keep each value once in a row.
    if (found && (headings.empty() || headings.back() != heading)) headings.push_back(heading);
  }
  return headings;
}

// gpsd may hold back the first epoch(s) of a log: `min_compared` fixes must have a report.
void ExpectFixesMatchChk(const std::string& name, size_t expected_fixes, size_t min_compared) {
  const std::string log_path = kRealNmeaDir + name;
  if (!fs::exists(log_path) || !fs::exists(log_path + ".chk")) {
    GTEST_SKIP() << "real test data not available: " << log_path;
  }
  const NmeaLog nmea = ReadNmea(log_path);
  const std::map<int64_t, ChkFix> reference = ChkFixesByEpoch(log_path + ".chk");
  ASSERT_EQ(nmea.fixes.size(), expected_fixes);
  size_t compared = 0;
  for (const GnssFix& fix : nmea.fixes) {
    const int64_t tod_ms = std::llround(std::fmod(fix.stamp_s, 86400.0) * 1000.0);
    const auto it = reference.find(tod_ms);
    if (it == reference.end()) continue;
    EXPECT_NEAR(fix.lat_deg, it->second.lat_deg, 1e-9) << "line " << fix.line;
    EXPECT_NEAR(fix.lon_deg, it->second.lon_deg, 1e-9) << "line " << fix.line;
    EXPECT_NEAR(fix.height_m, it->second.alt_hae_m, 1e-3) << "line " << fix.line;
    // gpsd's status: 2 DGPS, 3 RTK fixed (GGA 4), 4 RTK float (GGA 5).
    const int expected_status = fix.quality == 4 ? 3 : fix.quality == 5 ? 4 : fix.quality;
    if (it->second.status != 0) {
      EXPECT_EQ(it->second.status, expected_status) << "line " << fix.line;
    }
    ++compared;
  }
  EXPECT_GE(compared, min_compared);
}

void ExpectHeadingsMatchChk(const std::string& name, size_t expected_headings) {
  const std::string log_path = kRealNmeaDir + name;
  if (!fs::exists(log_path) || !fs::exists(log_path + ".chk")) {
    GTEST_SKIP() << "real test data not available: " << log_path;
  }
  const NmeaLog nmea = ReadNmea(log_path);
  const std::vector<double> reference_deg = ChkHeadingsDeg(log_path + ".chk");
  std::vector<double> decoded_rad;
  for (const HeadingSample& sample : nmea.headings) {
    if (decoded_rad.empty() || decoded_rad.back() != sample.heading_rad) {
      decoded_rad.push_back(sample.heading_rad);
    }
  }
  ASSERT_EQ(decoded_rad.size(), expected_headings);
  ASSERT_EQ(decoded_rad.size(), reference_deg.size());
  for (size_t i = 0; i < decoded_rad.size(); ++i) {
    EXPECT_NEAR(decoded_rad[i], reference_deg[i] * kDegToRad, 1e-6) << "heading " << i;
  }
}

TEST(NmeaReaderTest, RealTrimbleRtkLogMatchesGpsd) {
  ExpectFixesMatchChk("nmea-rtk.log", 122, 122);
  if (IsSkipped()) return;  // the real data is absent (the helper skipped)
  const NmeaLog nmea = ReadNmea(kRealNmeaDir + "nmea-rtk.log");
  EXPECT_EQ(nmea.fixes_by_quality.at(2), 104);
  EXPECT_EQ(nmea.fixes_by_quality.at(4), 18);
  // Plain capture: UNIX time from the RMC date, 2020-03-18 13:28:19.60 UTC first.
  EXPECT_NEAR(nmea.fixes.front().stamp_s, 1584538099.6, 1e-6);
}

TEST(NmeaReaderTest, RealSkytraqLogMatchesGpsd) {
  ExpectFixesMatchChk("skytraq-PX1172RH_DS.log", 9, 9);
  ExpectHeadingsMatchChk("skytraq-PX1172RH_DS.log", 9);
}

TEST(NmeaReaderTest, RealHemisphereLogMatchesGpsd) {
  ExpectHeadingsMatchChk("hemi.log", 4);
  // gpsd reports a position for only 6 of the 21 GGA epochs (mode 1 before that).
  ExpectFixesMatchChk("hemi.log", 21, 6);
  if (IsSkipped()) return;  // the real data is absent (the helper skipped)
  const NmeaLog nmea = ReadNmea(kRealNmeaDir + "hemi.log");
  // The log has exactly 211 "$GPHDT,,T" lines (grep -c): each one counted, none used.
  EXPECT_EQ(Count(nmea, "empty field"), 211);
  // The log is dated by ZDA only (no RMC): the first fix is 2018-09-07 19:40:50 UTC.
  ASSERT_FALSE(nmea.fixes.empty());
  EXPECT_NEAR(nmea.fixes.front().stamp_s, 1536349250.0, 1e-6);
}

}  // namespace
}  // namespace wallcal::io
