// SPDX-License-Identifier: Apache-2.0
// gzip-compressed NMEA logs and survey files read like plain ones (the files are written here
// with zlib), and damaged gzip data are reported, not half-read in silence.
#include "io/text/internal/gzip_input.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "io/text/nmea_reader.h"
#include "io/survey/survey_reader.h"
#include "io/writers/writers.h"
#include "test/support/scratch_files.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;
using testing_support::ScratchPath;
using testing_support::WriteScratchFile;

std::string WriteGzip(const std::string& name, const std::string& content) {
  const std::string path = ScratchPath(name);
  gzFile file = gzopen(path.c_str(), "wb");
  EXPECT_NE(file, nullptr);
  EXPECT_EQ(gzwrite(file, content.data(), static_cast<unsigned>(content.size())),
            static_cast<int>(content.size()));
  EXPECT_EQ(gzclose(file), Z_OK);
  return path;
}

std::string Bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string S(const std::string& body) { return "$" + body + "*" + NmeaChecksum(body); }

// A plain capture: the date comes from the RMC after the first GGA, so the reader's first pass
// (the first date in the file) matters; 200 epochs make the file longer than one inflate chunk.
std::string PlainCapture() {
  std::string log = "# a receiver capture\n";
  for (int i = 0; i < 2000; ++i) {
    char time[16];
    std::snprintf(time, sizeof time, "%02d%02d%02d.00", 5, i / 60 % 60, i % 60);
    log += S(std::string("GPGGA,") + time + ",4304.27407,N,14120.39259,E,4,14,0.7,53.10,M,19.21,M,,") + "\r\n";
    if (i == 0) log += S(std::string("GPRMC,") + time + ",A,4304.27407,N,14120.39259,E,0.0,0.0,120525,,,D") + "\r\n";
    log += S("GPHDT," + std::to_string(i % 360) + ".5,T") + "\r\n";
  }
  return log;
}

TEST(GzipInputTest, GzipNmeaLogReadsLikeThePlainOne) {
  const std::string text = PlainCapture();
  const NmeaLog plain = ReadNmea(WriteScratchFile("capture.nmea", text));
  const NmeaLog packed = ReadNmea(WriteGzip("capture.nmea.gz", text));
  ASSERT_EQ(plain.fixes.size(), 2000u);
  ASSERT_EQ(packed.fixes.size(), plain.fixes.size());
  ASSERT_EQ(packed.headings.size(), plain.headings.size());
  for (size_t i = 0; i < plain.fixes.size(); ++i) {
    EXPECT_EQ(packed.fixes[i].stamp_s, plain.fixes[i].stamp_s);
    EXPECT_EQ(packed.fixes[i].lat_deg, plain.fixes[i].lat_deg);
    EXPECT_EQ(packed.fixes[i].line, plain.fixes[i].line);
  }
  // 2025-05-12 05:00:00 UTC: the date of the RMC after the first GGA (first pass).
  EXPECT_DOUBLE_EQ(packed.fixes.front().stamp_s, 1747026000.0);
  EXPECT_EQ(packed.lines_read, plain.lines_read);
  EXPECT_EQ(packed.skipped.by_reason, plain.skipped.by_reason);
  // The name does not matter: a gzip file without .gz is recognised by its first bytes.
  EXPECT_EQ(ReadNmea(WriteGzip("capture_no_suffix.nmea", text)).fixes.size(), 2000u);
}

TEST(GzipInputTest, CutOffGzipNmeaKeepsTheLinesBeforeTheCut) {
  const std::string whole = Bytes(WriteGzip("whole.nmea.gz", PlainCapture()));
  const std::string path = WriteScratchFile("cut.nmea.gz", whole.substr(0, whole.size() / 2));
  const NmeaLog log = ReadNmea(path);
  EXPECT_GT(log.fixes.size(), 100u);
  EXPECT_LT(log.fixes.size(), 2000u);
  ASSERT_EQ(log.skipped.by_reason.count("gzip stream cut off"), 1u);
  EXPECT_EQ(log.skipped.by_reason.at("gzip stream cut off"), 1);
}

TEST(GzipInputTest, CorruptGzipIsAnInputError) {
  std::string bytes = Bytes(WriteGzip("good.nmea.gz", PlainCapture()));
  for (size_t i = bytes.size() / 3; i < bytes.size() / 3 + 64; ++i) bytes[i] ^= 0x5a;
  const std::string path = WriteScratchFile("corrupt.nmea.gz", bytes);
  try {
    ReadNmea(path);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": the gzip data are corrupt after ", 0), 0u)
        << e.what();
  }
}

TEST(GzipInputTest, StreamBufStopsAtItsCapAndRewinds) {
  const std::string text(1000, 'a');
  const std::string path = WriteGzip("thousand.gz", text);
  {
    GzipStreamBuf buffer(path, 1000);  // exactly the size: fine
    std::istream in(&buffer);
    std::string got((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(got, text);
    EXPECT_EQ(buffer.state(), GzipState::kOk);
    in.clear();
    in.seekg(0);  // a second pass reads it all again
    std::string again((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(again, text);
  }
  GzipStreamBuf small(path, 999);
  std::istream in(&small);
  std::string got((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(got.size(), 999u);
  EXPECT_EQ(small.state(), GzipState::kTooLarge);
  EXPECT_NE(small.Problem().find("more than 999 bytes uncompressed"), std::string::npos);
  EXPECT_FALSE(IsGzipFile(WriteScratchFile("plain.txt", "\x1f")));
  EXPECT_TRUE(IsGzipFile(path));
}

TEST(GzipInputTest, GzipSurveyFilesReadLikePlainOnes) {
  const std::string csv = "Point,Northing,Easting,Elevation,Description\n1,10.013,1.002,0.512,W\n";
  const std::vector<SurveyPoint> points = ReadSurvey(WriteGzip("survey.csv.gz", csv));
  ASSERT_EQ(points.size(), 1u);
  EXPECT_DOUBLE_EQ(points[0].x_m, 1.002);
  EXPECT_DOUBLE_EQ(points[0].y_m, 10.013);

  const std::string pnezd = "1,10.013,1.002,0.512,W\n";
  EXPECT_EQ(ReadSurvey(WriteGzip("pnezd.csv.gz", pnezd), SurveyColumns::kPNEZD).size(), 1u);

  const std::string gsi = "110001+00000001 81..00+00001002 82..00+00010013 83..00+00000512\n";
  const std::vector<SurveyPoint> gsi_points = ReadSurvey(WriteGzip("job.gsi.gz", gsi));
  ASSERT_EQ(gsi_points.size(), 1u);
  EXPECT_DOUBLE_EQ(gsi_points[0].y_m, 10.013);

  // A survey cut short would lose points in silence: an error, not a shorter survey.
  std::string rows = "id,x,y,z,code\n";
  for (int i = 0; i < 3000; ++i) rows += "P" + std::to_string(i) + ",1.0,2.0,3.0,W\n";
  const std::string whole = Bytes(WriteGzip("big.csv.gz", rows));
  const std::string cut = WriteScratchFile("cut.csv.gz", whole.substr(0, whole.size() - 20));
  try {
    ReadSurvey(cut);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(": the gzip stream is cut off after "), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace wallcal::io
