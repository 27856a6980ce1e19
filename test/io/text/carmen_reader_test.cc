// SPDX-License-Identifier: Apache-2.0
#include "io/text/carmen_reader.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include "common/angles.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;
using testing_support::ReadFile;
using testing_support::ScratchPath;
using testing_support::WriteScratchFile;

std::string Ranges(int n, double first_m, double step_m) {
  std::string text;
  for (int i = 0; i < n; ++i) text += " " + std::to_string(first_m + step_m * i);
  return text;
}

// RAWLASER1 with `n` beams from -90 deg in 1 deg steps.
std::string Rawlaser(int n, double stamp_s) {
  return "RAWLASER1 0 -1.5707963 3.1415927 0.017453293 80.0 0.01 0 " + std::to_string(n) +
         Ranges(n, 1.0, 0.01) + " 0 " + std::to_string(stamp_s) + " host " +
         std::to_string(stamp_s);
}

std::vector<ScanRecord> ReadAll(CarmenReader& reader) {
  std::vector<ScanRecord> scans;
  ScanRecord scan;
  while (reader.Next(&scan)) scans.push_back(scan);
  return scans;
}

TEST(CarmenReaderTest, ReadsRawlaser1) {
  CarmenReader reader(WriteScratchFile("raw.clf", Rawlaser(181, 1000.5) + "\n"));
  const std::vector<ScanRecord> scans = ReadAll(reader);
  ASSERT_EQ(scans.size(), 1u);
  const ScanRecord& scan = scans[0];
  EXPECT_DOUBLE_EQ(scan.stamp_s, 1000.5);
  EXPECT_NEAR(scan.start_angle_rad, -kPi / 2, 1e-7);
  EXPECT_NEAR(scan.angular_step_rad, kPi / 180, 1e-9);
  EXPECT_DOUBLE_EQ(scan.max_range_m, 80.0);
  ASSERT_EQ(scan.ranges_m.size(), 181u);
  EXPECT_FLOAT_EQ(scan.ranges_m[0], 1.0f);
  EXPECT_FLOAT_EQ(scan.ranges_m[180], 2.8f);
  EXPECT_EQ(scan.line, 1);
  EXPECT_EQ(reader.scans_read(), 1);
  EXPECT_EQ(reader.lines_read(), 1);
  EXPECT_EQ(reader.skipped().Total(), 0);
}

// A log being appended: a reader opened at the line start an earlier one reported reads the
// rest with the same line numbers, the line that was cut off at the first read included.
TEST(CarmenReaderTest, ReadsOnFromWhereAnEarlierReaderStopped) {
  const std::string first = "PARAM x 1\n" + Rawlaser(181, 10.0) + "\r\n" + Rawlaser(181, 10.1) + "\n";
  const std::string third = Rawlaser(181, 10.2) + "\n";
  const std::string path = WriteScratchFile("growing.clf", first + third.substr(0, 40));
  int64_t third_byte = 0;
  int64_t second_line = 0;
  {
    CarmenReader reader(path);
    const std::vector<ScanRecord> scans = ReadAll(reader);
    ASSERT_EQ(scans.size(), 2u);
    EXPECT_EQ(reader.skipped().Problems(), 1);  // the cut-off line
    second_line = scans[1].line;
    third_byte = reader.line_start_byte();  // the cut-off line's start
  }
  EXPECT_EQ(third_byte, static_cast<int64_t>(first.size()));
  std::ofstream(path, std::ios::binary | std::ios::app) << third.substr(40);
  CarmenReader reader(path, third_byte, second_line + 1);
  const std::vector<ScanRecord> scans = ReadAll(reader);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_DOUBLE_EQ(scans[0].stamp_s, 10.2);
  EXPECT_EQ(scans[0].line, 4);
  EXPECT_EQ(reader.line_start_byte(), third_byte);
  EXPECT_EQ(reader.skipped().Total(), 0);
}

// LF, CRLF and a CR alone each end a line: the same scans, with the same line numbers.
TEST(CarmenReaderTest, ReadsEveryLineEnd) {
  for (const std::string eol : {"\n", "\r\n", "\r"}) {
    SCOPED_TRACE(eol == "\r" ? "CR" : eol == "\n" ? "LF" : "CRLF");
    const std::string log = "# header" + eol + Rawlaser(181, 1000.5) + eol + eol +
                            Rawlaser(181, 1000.6) + eol;
    CarmenReader reader(WriteScratchFile("eol.clf", log));
    const std::vector<ScanRecord> scans = ReadAll(reader);
    ASSERT_EQ(scans.size(), 2u);
    EXPECT_EQ(scans[0].line, 2);
    EXPECT_EQ(scans[1].line, 4);
    EXPECT_DOUBLE_EQ(scans[1].stamp_s, 1000.6);
    EXPECT_EQ(scans[1].ranges_m.size(), 181u);
    EXPECT_EQ(reader.skipped().Total(), 2);  // the comment and the blank line
    EXPECT_EQ(reader.skipped().Problems(), 0);
  }
}

TEST(CarmenReaderTest, ReadsRawlaser1WithRemissions) {
  const std::string line = "RAWLASER1 0 -0.5 1.0 0.5 30 0.01 1 3 1.5 2.5 3.5 3 10 20 30 7.0 h 8.0";
  CarmenReader reader(WriteScratchFile("rem.clf", line + "\n"));
  const std::vector<ScanRecord> scans = ReadAll(reader);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_DOUBLE_EQ(scans[0].stamp_s, 8.0);  // logger_timestamp, not ipc_timestamp
  EXPECT_DOUBLE_EQ(scans[0].start_angle_rad, -0.5);
  EXPECT_DOUBLE_EQ(scans[0].angular_step_rad, 0.5);
  ASSERT_EQ(scans[0].ranges_m.size(), 3u);
  EXPECT_FLOAT_EQ(scans[0].ranges_m[2], 3.5f);
}

TEST(CarmenReaderTest, ReadsRobotlaser1) {
  const std::string line =
      "ROBOTLASER1 0 -2.0 4.0 0.01 5.6 0.01 0 4 1.0 1.1 1.2 1.3 0 "
      "0.1 0.2 0.3 1.1 1.2 1.3 0.5 0.0 0.2 0.1 0.0 12.25 robot 12.5";
  CarmenReader reader(WriteScratchFile("robot.clf", "# header\n" + line + "\n"));
  const std::vector<ScanRecord> scans = ReadAll(reader);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_DOUBLE_EQ(scans[0].stamp_s, 12.5);
  EXPECT_DOUBLE_EQ(scans[0].start_angle_rad, -2.0);
  EXPECT_DOUBLE_EQ(scans[0].angular_step_rad, 0.01);
  EXPECT_DOUBLE_EQ(scans[0].max_range_m, 5.6);
  ASSERT_EQ(scans[0].ranges_m.size(), 4u);
  EXPECT_FLOAT_EQ(scans[0].ranges_m[3], 1.3f);
  EXPECT_EQ(scans[0].line, 2);
}

TEST(CarmenReaderTest, ReadsFlaserWithCarmenGeometry) {
  std::string log;
  log += "FLASER 180" + Ranges(180, 2.0, 0.0) + " 1 2 0.5 1 2 0.5 100.0 pippo 100.25\n";
  log += "FLASER 361" + Ranges(361, 3.0, 0.0) + " 1 2 0.5 1 2 0.5 101.0 pippo 101.25\n";
  log += "FLASER 5" + Ranges(5, 4.0, 0.0) + " 1 2 0.5 1 2 0.5 102.0 pippo 102.25\n";
  CarmenReader reader(WriteScratchFile("flaser.clf", log));
  const std::vector<ScanRecord> scans = ReadAll(reader);
  ASSERT_EQ(scans.size(), 3u);
  EXPECT_DOUBLE_EQ(scans[0].stamp_s, 100.25);
  EXPECT_DOUBLE_EQ(scans[0].start_angle_rad, -kPi / 2);
  EXPECT_DOUBLE_EQ(scans[0].angular_step_rad, kPi / 180);  // 180 beams: 1 deg, last one dropped
  EXPECT_DOUBLE_EQ(scans[0].max_range_m, 0.0);
  EXPECT_EQ(scans[0].ranges_m.size(), 180u);
  EXPECT_DOUBLE_EQ(scans[1].angular_step_rad, kPi / 360);
  EXPECT_EQ(scans[1].ranges_m.size(), 361u);
  EXPECT_DOUBLE_EQ(scans[2].angular_step_rad, kPi / 4);  // other counts: 180 deg / (n - 1)
  EXPECT_FLOAT_EQ(scans[2].ranges_m[4], 4.0f);
}

// A gzip log `name` in the scratch folder of `scans` RAWLASER lines of `beams` beams, stamped
// 10, 11, ... s; its path ("" when it cannot be written).
std::string WriteGzipLog(const std::string& name, int scans, int beams) {
  const std::string path = ScratchPath(name);
  gzFile file = gzopen(path.c_str(), "wb");
  if (file == nullptr) return "";
  for (int i = 0; i < scans; ++i) {
    const std::string line = Rawlaser(beams, 10.0 + i) + "\n";
    gzwrite(file, line.data(), static_cast<unsigned>(line.size()));
  }
  gzclose(file);
  return path;
}

TEST(CarmenReaderTest, ReadsGzipTransparently) {
  const std::string path = WriteGzipLog("scans.clf.gz", 50, 361);
  ASSERT_FALSE(path.empty());
  CarmenReader reader(path);
  const std::vector<ScanRecord> scans = ReadAll(reader);
  ASSERT_EQ(scans.size(), 50u);
  EXPECT_DOUBLE_EQ(scans[49].stamp_s, 59.0);
  EXPECT_EQ(scans[49].ranges_m.size(), 361u);
  EXPECT_EQ(scans[49].line, 50);
}

// A gzip log whose end was lost (logger killed, copy interrupted): the scans before the cut are
// read, the cut is counted, nothing is half-used.
TEST(CarmenReaderTest, TruncatedGzipKeepsTheScansBeforeTheCut) {
  const std::string whole = WriteGzipLog("whole.clf.gz", 400, 181);
  ASSERT_FALSE(whole.empty());
  const std::string bytes = ReadFile(whole);
  ASSERT_GT(bytes.size(), 2000u);
  const std::string cut = WriteScratchFile("cut.clf.gz", bytes.substr(0, bytes.size() * 2 / 3));
  CarmenReader reader(cut);
  const std::vector<ScanRecord> scans = ReadAll(reader);
  EXPECT_GT(scans.size(), 10u);
  EXPECT_LT(scans.size(), 400u);
  for (size_t i = 0; i < scans.size(); ++i) {
    ASSERT_EQ(scans[i].ranges_m.size(), 181u);
    EXPECT_DOUBLE_EQ(scans[i].stamp_s, 10.0 + static_cast<double>(i));
  }
  EXPECT_GE(reader.skipped().Total(), 1);
}

TEST(CarmenReaderTest, ReadsLinesLongerThanOneBuffer) {
  // 9000 beams ~ 80 kB: more than one gzgets chunk.
  CarmenReader reader(WriteScratchFile("long.clf", Rawlaser(9000, 5.0) + "\n" + Rawlaser(3, 6.0) + "\n"));
  const std::vector<ScanRecord> scans = ReadAll(reader);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(scans[0].ranges_m.size(), 9000u);
  EXPECT_EQ(scans[1].line, 2);
}

TEST(CarmenReaderTest, CountsLinesOfOtherKinds) {
  const std::string log =
      "# message formats defined: PARAM SYNC ODOM\n"
      "PARAM robot_width 0.54 1.0 host 1.0\n"
      "ODOM 0 0 0 0 0 0 0.000246 pippo 0.000246\n"
      "\n"
      "NEFF 30 1.0 host 1.0\n" +
      Rawlaser(5, 3.0) + "\n";
  CarmenReader reader(WriteScratchFile("kinds.clf", log));
  const std::vector<ScanRecord> scans = ReadAll(reader);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_EQ(scans[0].line, 6);
  const SkipCounts& skipped = reader.skipped();
  EXPECT_EQ(skipped.by_reason.at("comment"), 1);
  EXPECT_EQ(skipped.by_reason.at("not a scan: PARAM"), 1);
  EXPECT_EQ(skipped.by_reason.at("not a scan: ODOM"), 1);
  EXPECT_EQ(skipped.by_reason.at("not a scan: NEFF"), 1);
  EXPECT_EQ(skipped.by_reason.at("blank line"), 1);
  EXPECT_EQ(skipped.first_line.at("not a scan: ODOM"), 3);
  EXPECT_EQ(skipped.Total(), 5);
  EXPECT_EQ(reader.lines_read(), 6);
}

// One bad line between two good ones: the bad one is skipped whole and counted by reason.
void ExpectSkipped(const std::string& name, const std::string& bad_line,
                   const std::string& reason) {
  SCOPED_TRACE(name);
  const std::string log = Rawlaser(5, 1.0) + "\n" + bad_line + "\n" + Rawlaser(5, 3.0) + "\n";
  CarmenReader reader(WriteScratchFile(name + ".clf", log));
  const std::vector<ScanRecord> scans = ReadAll(reader);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_DOUBLE_EQ(scans[0].stamp_s, 1.0);
  EXPECT_DOUBLE_EQ(scans[1].stamp_s, 3.0);
  ASSERT_EQ(reader.skipped().by_reason.count(reason), 1u) << "reason not counted: " << reason;
  EXPECT_EQ(reader.skipped().by_reason.at(reason), 1);
  EXPECT_EQ(reader.skipped().first_line.at(reason), 2);
  EXPECT_EQ(reader.skipped().Total(), 1);
}

TEST(CarmenReaderTest, SkipsMalformedScanLinesWhole) {
  ExpectSkipped("nonnumeric", "RAWLASER1 0 -1.5 3.14 0.785 80 0.01 0 5 1 2 x 4 5 0 2.0 h 2.0",
                "RAWLASER1: non-numeric field");
  ExpectSkipped("nonnumeric_header", "RAWLASER1 0 abc 3.14 0.785 80 0.01 0 5 1 2 3 4 5 0 2.0 h 2.0",
                "RAWLASER1: non-numeric field");
  ExpectSkipped("count_low", "RAWLASER1 0 -1.5 3.14 0.785 80 0.01 0 6 1 2 3 4 5 0 2.0 h 2.0",
                "RAWLASER1: beam count disagrees with the line");
  ExpectSkipped("count_high", "FLASER 3 1 2 3 4 1 2 0.5 1 2 0.5 2.0 h 2.0",
                "FLASER: beam count disagrees with the line");
  ExpectSkipped("too_few", "FLASER", "FLASER: too few fields");
  ExpectSkipped("nan_range", "RAWLASER1 0 -1.5 3.14 0.785 80 0.01 0 5 1 nan 3 4 5 0 2.0 h 2.0",
                "RAWLASER1: negative or non-finite range");
  ExpectSkipped("inf_range", "RAWLASER1 0 -1.5 3.14 0.785 80 0.01 0 5 1 2 inf 4 5 0 2.0 h 2.0",
                "RAWLASER1: negative or non-finite range");
  ExpectSkipped("negative_range", "RAWLASER1 0 -1.5 3.14 0.785 80 0.01 0 5 1 2 3 -4 5 0 2.0 h 2.0",
                "RAWLASER1: negative or non-finite range");
  ExpectSkipped("nan_stamp", "RAWLASER1 0 -1.5 3.14 0.785 80 0.01 0 5 1 2 3 4 5 0 2.0 h nan",
                "RAWLASER1: non-finite timestamp");
  ExpectSkipped("robot_short",
                "ROBOTLASER1 0 -2.0 4.0 0.01 5.6 0.01 0 2 1.0 1.1 0 0.1 0.2 0.3 2.0 h 2.0",
                "ROBOTLASER1: beam count disagrees with the line");
}

TEST(CarmenReaderTest, CountsALineCutOffAtEndOfFile) {
  const std::string full = Rawlaser(181, 2.0);
  const std::string cut = full.substr(0, full.size() / 2);  // no newline, too few fields
  CarmenReader reader(WriteScratchFile("cut.clf", Rawlaser(181, 1.0) + "\n" + cut));
  const std::vector<ScanRecord> scans = ReadAll(reader);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_EQ(reader.skipped().by_reason.at("RAWLASER1: line cut off at end of file"), 1);
  EXPECT_EQ(reader.lines_read(), 2);
}

TEST(CarmenReaderTest, AcceptsLastLineWithoutNewline) {
  CarmenReader reader(WriteScratchFile("nonewline.clf", Rawlaser(5, 1.0)));
  EXPECT_EQ(ReadAll(reader).size(), 1u);
  EXPECT_EQ(reader.skipped().Total(), 0);
}

TEST(CarmenReaderTest, MissingFileNamesThePath) {
  const std::string path = ScratchPath("no_such_log.clf");
  testing_support::ExpectContains(
      testing_support::MessageOf<InputError>([&] { CarmenReader reader(path); }), {path});
}

// Real Radish logs (CARMEN FLASER): skip when ../shared is not there.
struct FirstScan {
  int line;
  float range0_m;
  double stamp_s;
};

void CountRealLog(const std::string& path, int64_t expected_scans, size_t expected_beams,
                  const FirstScan& first) {
  if (!fs::exists(path)) GTEST_SKIP() << "real test data not available: " << path;
  CarmenReader reader(path);
  ScanRecord scan;
  int64_t scans = 0;
  int64_t beams = 0;
  while (reader.Next(&scan)) {
    if (scans == 0) {
      EXPECT_EQ(scan.line, first.line);
      EXPECT_FLOAT_EQ(scan.ranges_m[0], first.range0_m);
      EXPECT_DOUBLE_EQ(scan.stamp_s, first.stamp_s);
    }
    ++scans;
    beams += static_cast<int64_t>(scan.ranges_m.size());
    ASSERT_EQ(scan.ranges_m.size(), expected_beams) << "line " << scan.line;
    // (Stamps are kept in file order: the Intel log has a few steps back in time.)
    ASSERT_TRUE(std::isfinite(scan.stamp_s)) << "line " << scan.line;
  }
  EXPECT_EQ(beams, expected_scans * static_cast<int64_t>(expected_beams));
  EXPECT_EQ(scans, expected_scans);
  EXPECT_EQ(reader.scans_read(), expected_scans);
  // Everything else in these logs is ODOM, PARAM, other messages or comments.
  for (const auto& [reason, count] : reader.skipped().by_reason) {
    EXPECT_TRUE(reason == "comment" || reason.rfind("not a scan: ", 0) == 0)
        << reason << " x" << count;
  }
  EXPECT_EQ(reader.lines_read(), scans + reader.skipped().Total());
}

TEST(CarmenReaderTest, ReadsRealIntelLog) {
  CountRealLog(WALLCAL_SOURCE_DIR "/../shared/testdata/real/carmen/intel-corrected.log.gz", 910,
               180, {175, 1.09f, 32.9068});
}

TEST(CarmenReaderTest, ReadsRealCsailLog) {
  CountRealLog(WALLCAL_SOURCE_DIR "/../shared/testdata/real/carmen/csail-corrected.log.gz", 406,
               361, {184, 81.91f, 1.13486e+09});
}

}  // namespace
}  // namespace wallcal::io

namespace wallcal::io {
namespace {

// Skimming (the first pass) must see the same scans, at the same lines, as reading whole, and
// count a malformed scan line when it is parsed.
TEST(CarmenReaderTest, SkimmingSeesTheScansNextReads) {
  std::string text = "# comment\nPARAM robot_width 0.5\n";
  for (int k = 0; k < 6; ++k) text += Rawlaser(181, 1000.0 + 0.1 * k) + "\n";
  // Line 9: a scan line whose beam count disagrees with its ranges, stamp still readable.
  text += "RAWLASER1 0 -1.5707963 3.1415927 0.017453293 80.0 0.01 0 181 1.0 2.0 0 host 1000.7\n";
  text += "\n" + Rawlaser(181, 1000.8) + "\n";
  const std::string path = WriteScratchFile("skim.clf", text);

  CarmenReader whole(path);
  const std::vector<ScanRecord> scans = ReadAll(whole);
  ASSERT_EQ(scans.size(), 7u);

  CarmenReader skim(path);
  std::vector<ScanRecord> parsed;
  std::vector<int> lines;
  double stamp_s = 0.0;
  int line = 0;
  while (skim.NextStamp(&stamp_s, &line)) {
    lines.push_back(line);
    ScanRecord scan;
    if (skim.ParseCurrent(&scan)) {
      EXPECT_DOUBLE_EQ(scan.stamp_s, stamp_s);
      EXPECT_EQ(scan.line, line);
      parsed.push_back(scan);
    }
  }
  // The malformed line's stamp is read (8 stamps), its parse refused (7 scans).
  EXPECT_EQ(lines.size(), 8u);
  EXPECT_EQ(lines[6], 9);
  ASSERT_EQ(parsed.size(), scans.size());
  for (size_t i = 0; i < scans.size(); ++i) {
    EXPECT_EQ(parsed[i].line, scans[i].line);
    EXPECT_EQ(parsed[i].ranges_m, scans[i].ranges_m);
  }
  EXPECT_EQ(skim.skipped().Problems(), whole.skipped().Problems());
  EXPECT_EQ(skim.skipped().Problems(), 1);

  // Skimming without parsing: stamps only, the malformed line never looked into.
  CarmenReader stamps_only(path);
  int count = 0;
  while (stamps_only.NextStamp(&stamp_s, &line)) ++count;
  EXPECT_EQ(count, 8);
  EXPECT_EQ(stamps_only.skipped().Problems(), 0);
}

}  // namespace
}  // namespace wallcal::io
