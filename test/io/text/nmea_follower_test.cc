// SPDX-License-Identifier: Apache-2.0
// io::NmeaFollower: an NMEA log read in pieces, as a logger writes it (cut at any byte: inside a
// sentence, inside a CRLF, between a GGA and its GST), gives exactly what one whole read of the
// same bytes gives: the fixes, headings, counts and skipped lines with their first line numbers.
// io::NmeaLineFeed: the same lines handed over one at a time (a recording's sentence messages)
// give what one whole read of them gives, after each line.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "io/text/nmea_reader.h"
#include "io/writers/writers.h"
#include "test/support/nmea_logs.h"
#include "test/support/scratch_files.h"

namespace wallcal::io {
namespace {

using testing_support::ExpectSameLog;
using testing_support::ScratchPath;
using testing_support::WriteFile;

// "$body*hh" with the right checksum.
std::string S(const std::string& body) { return "$" + body + "*" + NmeaChecksum(body); }

// Writes `text` up to each cut in turn and reads on after each; every time, the follower's log
// must be the whole read of what the file holds then. Returns the bytes each read started at.
std::vector<int64_t> ReadInPieces(const std::string& text, std::vector<size_t> cuts,
                                  const std::string& name) {
  cuts.push_back(text.size());
  const std::string path = ScratchPath(name);
  WriteFile(path, "");
  NmeaFollower follower(path);
  std::vector<int64_t> from_bytes;
  size_t written = 0;
  for (const size_t cut : cuts) {
    if (cut > written) {
      std::ofstream(path, std::ios::binary | std::ios::app)
          .write(text.data() + written, static_cast<std::streamsize>(cut - written));
      written = cut;
    }
    from_bytes.push_back(follower.ReadMore());
    EXPECT_EQ(follower.bytes_read(), static_cast<int64_t>(cut));
    ExpectSameLog(follower.Log(), ReadNmea(path), name + " cut at byte " + std::to_string(cut));
  }
  return from_bytes;
}

// A plain capture (no logger stamps): dates from RMC and ZDA, a midnight crossing, GSTs after
// and before their GGA, a GST whose GGA never comes, headings stamped by the last timed
// sentence, bad lines of every kind, a repeated epoch, CRLF and lone CR line ends.
std::string PlainCapture() {
  std::string t;
  t += "# receiver capture\r\n";
  t += S("GPRMC,235958.00,A,4304.2741,N,14120.3917,E,0.0,0.0,261126,,,A") + "\r\n";
  t += S("GPGGA,235958.00,4304.2741,N,14120.3917,E,4,14,0.7,72.0,M,19.2,M,,") + "\r\n";
  t += S("GPGST,235958.00,0.02,0.01,0.01,0.0,0.011,0.012,0.03") + "\r\n";
  t += S("HEHDT,35.5,T") + "\r";  // a lone CR ends a line too
  t += S("GPGST,235959.00,0.02,0.01,0.01,0.0,0.013,0.014,0.03") + "\n";  // before its GGA
  t += S("GPGGA,235959.00,4304.2742,N,14120.3918,E,4,14,0.7,72.1,M,19.2,M,,") + "\n";
  t += "$GPGGA,235959.50,4304.2742,N,14120.3918,E,4,14,0.7,72.1,M,19.2,M,,*00\n";      // checksum
  t += S("GPGGA,235959.00,4304.2742,N,14120.3918,E,4,14,0.7,72.1,M,19.2,M,,") + "\n";  // again
  t += S("GPGSV,3,1,11,01,02,03,04") + "\n";
  t += S("HEHDT,,T") + "\n";
  t += S("INTHS,36.0,V") + "\n";
  t += S("GPGGA,000000.00,4304.2743,N,14120.3919,E,4,14,0.7,72.2,M,19.2,M,,") + "\n";  // midnight
  t += S("GPGST,000000.00,0.02,0.01,0.01,0.0,0.015,0.016,0.03") + "\n";
  t += S("INTHS,36.5,A") + "\n";
  t += S("GPGST,000001.00,0.02,0.01,0.01,0.0,0.015,0.016,0.03") + "\n";  // its GGA never comes
  t += S("GPZDA,000002.00,27,11,2026,00,00") + "\n";
  t += S("GPGGA,000002.00,9104.2743,N,14120.3919,E,4,14,0.7,72.2,M,19.2,M,,") + "\n";  // lat
  t += S("GPGGA,000003.00,4304.2743,N,14120.3919,E,4,02,0.7,72.2,M,19.2,M,,") + "\n";
  t += S("GPGGA,000004.00,4304.2744,N,14120.3920,E,1,08,1.2,72.3,M,19.2,M,,") + "\n";
  t += S("HEHDT,361.0,T") + "\n";
  t += S("HEHDT,37.0,T") + "\n";
  t += "no line end at the end $GPGGA";
  return t;
}

// Every byte of the capture as the one cut (the whole read of each prefix), then pieces cut at
// random bytes.
TEST(NmeaFollowerTest, PiecesAtEveryByteReadAsTheWhole) {
  const std::string text = PlainCapture();
  for (size_t cut = 0; cut <= text.size(); ++cut) {
    ReadInPieces(text, {cut}, "every_byte.nmea");
  }
  std::mt19937 random(5);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<size_t> cuts(1 + random() % 8);
    for (size_t& cut : cuts) cut = random() % (text.size() + 1);
    std::sort(cuts.begin(), cuts.end());
    ReadInPieces(text, cuts, "random_pieces.nmea");
  }
}

// The cuts that matter named one by one: between a GGA and its GST, between a GST and its GGA,
// inside a CRLF, just after a lone CR.
TEST(NmeaFollowerTest, ReadsOnAfterCutsBetweenSentencesThatBelongTogether) {
  const std::string text = PlainCapture();
  const auto after = [&text](const std::string& what) {
    const size_t at = text.find(what);
    EXPECT_NE(at, std::string::npos) << what;
    return at + what.size();
  };
  const size_t gga_then_gst = after("72.0,M,19.2,M,,*") + 4;  // after the GGA's CRLF
  ASSERT_EQ(text.compare(gga_then_gst, 6, "$GPGST"), 0);
  const size_t gst_then_gga = after("0.013,0.014,0.03*") + 3;  // after the GST's LF
  ASSERT_EQ(text.compare(gst_then_gga, 6, "$GPGGA"), 0);
  const size_t gga_start = text.find("$GPGGA,235958.00");
  const size_t inside_crlf = after("72.0,M,19.2,M,,*") + 3;  // between the GGA's CR and LF
  ASSERT_EQ(text[inside_crlf], '\n');
  const size_t hdt_start = text.find("$HEHDT,35.5");
  const size_t after_cr = after("HEHDT,35.5,T*") + 3;  // a CR that a LF could still follow
  const std::vector<int64_t> from =
      ReadInPieces(text, {inside_crlf, gga_then_gst, after_cr, gst_then_gga}, "named_cuts.nmea");
  // Each read goes on from the start of the line it could not finish, never from the file's
  // start again (the date is on line 2, which the first read saw).
  EXPECT_EQ(from, (std::vector<int64_t>{
                      0, static_cast<int64_t>(gga_start), static_cast<int64_t>(gga_then_gst),
                      static_cast<int64_t>(hdt_start), static_cast<int64_t>(gst_then_gga)}));
}

// A logged capture (logger-time prefixes, no RMC/ZDA): the sample session's GNSS and heading
// logs cut at random bytes.
TEST(NmeaFollowerTest, ReadsTheSampleLogsInPieces) {
  for (const char* name : {"gnss.nmea", "heading.nmea"}) {
    std::ifstream in(std::string(WALLCAL_SOURCE_DIR) + "/samples/lms291-sapporo/" + name,
                     std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(text.size(), 10000u);
    std::mt19937 random(11);
    for (int trial = 0; trial < 5; ++trial) {
      std::vector<size_t> cuts(10);
      for (size_t& cut : cuts) cut = random() % text.size();
      std::sort(cuts.begin(), cuts.end());
      const std::vector<int64_t> from = ReadInPieces(text, cuts, name);
      for (size_t i = 1; i < from.size(); ++i) {
        EXPECT_LE(from[i], static_cast<int64_t>(cuts[i - 1]));
        EXPECT_GT(from[i], static_cast<int64_t>(cuts[i - 1]) - 200);  // the cut line only
      }
    }
  }
}

// Plain sentences before the log's first date are dated with it (ParseNmea): when that date
// arrives after them, the log is read again from its start.
TEST(NmeaFollowerTest, ReadsAgainWhenTheFirstDateComesLate) {
  std::string text;
  text += S("GPGGA,120000.00,4304.2741,N,14120.3917,E,4,14,0.7,72.0,M,19.2,M,,") + "\n";
  text += S("HEHDT,35.5,T") + "\n";
  const size_t before_date = text.size();
  text += S("GPRMC,120001.00,A,4304.2741,N,14120.3917,E,0.0,0.0,261126,,,A") + "\n";
  text += S("GPGGA,120001.00,4304.2742,N,14120.3918,E,4,14,0.7,72.1,M,19.2,M,,") + "\n";
  const size_t after_date = text.size();
  text += S("GPGGA,120002.00,4304.2743,N,14120.3919,E,4,14,0.7,72.2,M,19.2,M,,") + "\n";
  const std::vector<int64_t> from = ReadInPieces(text, {before_date, after_date}, "late_date.nmea");
  EXPECT_EQ(from, (std::vector<int64_t>{0, 0, static_cast<int64_t>(after_date)}));
}

// A log shorter than what was read is a new log under the same name: read from its start.
TEST(NmeaFollowerTest, ReadsANewLogUnderTheSameNameFromItsStart) {
  const std::string path = ScratchPath("replaced.nmea");
  const std::string first = S("HEHDT,10.0,T") + "\n";
  WriteFile(path, "1000.0 " + first + "1000.1 " + first);
  NmeaFollower follower(path);
  EXPECT_EQ(follower.ReadMore(), 0);
  EXPECT_EQ(follower.Log().headings.size(), 2u);
  WriteFile(path, "2000.0 " + S("HEHDT,20.0,T") + "\n");
  EXPECT_EQ(follower.ReadMore(), 0);
  ExpectSameLog(follower.Log(), ReadNmea(path), "replaced");
  ASSERT_EQ(follower.Log().headings.size(), 1u);
  EXPECT_EQ(follower.Log().headings[0].stamp_s, 2000.0);
}

// The lines of `text` as ParseNmea splits them ('\n', "\r\n" or a lone '\r' ends one),
// handed to a line feed one at a time: after each, the feed's log is the whole read of the
// lines so far.
void FeedLineByLine(const std::string& text, const std::string& name) {
  NmeaLineFeed feed(name);
  std::string so_far;
  size_t start = 0;
  int lines = 0;
  while (start < text.size()) {
    size_t end = text.find_first_of("\r\n", start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    start = end + (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n' ? 2 : 1);
    feed.Add(line);
    so_far += line + "\n";
    std::istringstream whole(so_far);
    ExpectSameLog(feed.Log(), ParseNmea(whole, name),
                  name + " after line " + std::to_string(++lines));
  }
  EXPECT_GT(lines, 0);
}

TEST(NmeaLineFeedTest, LineByLineReadsAsTheWhole) {
  FeedLineByLine(PlainCapture(), "capture");
  // The first date after plain sentences: they are dated again when it comes.
  std::string late;
  late += S("GPGGA,120000.00,4304.2741,N,14120.3917,E,4,14,0.7,72.0,M,19.2,M,,") + "\n";
  late += "1700000000.5 " + S("GPGGA,120000.50,4304.2741,N,14120.3917,E,4,14,0.7,72.0,M,19.2,M,,") +
          "\n";
  late += S("HEHDT,35.5,T") + "\n";
  late += S("GPRMC,120001.00,A,4304.2741,N,14120.3917,E,0.0,0.0,261126,,,A") + "\n";
  late += S("GPGGA,120002.00,4304.2743,N,14120.3919,E,4,14,0.7,72.2,M,19.2,M,,") + "\n";
  FeedLineByLine(late, "late date");
  std::ifstream in(std::string(WALLCAL_SOURCE_DIR) + "/samples/lms291-sapporo/gnss.nmea",
                   std::ios::binary);
  const std::string sample((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  FeedLineByLine(sample.substr(0, sample.find('\n', 20000) + 1), "sample gnss.nmea");
}

}  // namespace
}  // namespace wallcal::io
