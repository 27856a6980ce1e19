// SPDX-License-Identifier: Apache-2.0
// The attitude sentences of the NMEA reader: $PASHR and $PTNL,AVR into NmeaLog::attitudes, the
// published examples (gpsd's NMEA.adoc, Trimble's PTNL,AVR page) read as their definitions say,
// every kind of bad sentence skipped and counted with its first line, and the simulator's
// writers read back.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "common/angles.h"
#include "io/text/nmea_reader.h"
#include "io/writers/writers.h"
#include "test/support/scratch_files.h"

namespace wallcal::io {
namespace {

using testing_support::WriteScratchFile;

// "$body*hh" with the right checksum.
std::string S(const std::string& body) { return "$" + body + "*" + NmeaChecksum(body); }

NmeaLog Parse(const std::string& text) {
  std::istringstream in(text);
  return ParseNmea(in, "attitude.nmea");
}

int64_t Count(const NmeaLog& log, const std::string& reason) {
  const auto it = log.skipped.by_reason.find(reason);
  return it == log.skipped.by_reason.end() ? 0 : it->second;
}

int FirstLine(const NmeaLog& log, const std::string& reason) {
  const auto it = log.skipped.first_line.find(reason);
  return it == log.skipped.first_line.end() ? 0 : it->second;
}

// gpsd's example of the sentence (www/NMEA.adoc, "PASHR - RT300 proprietary roll and pitch
// sentence"), checksum as printed there.
const char kGpsdPashr[] =
    "$PASHR,085335.000,224.19,T,-01.26,+00.83,+00.00,0.101,0.113,0.267,1,0*06";

TEST(NmeaAttitudeTest, ReadsPashrRollPitchAndTheirSigma) {
  const NmeaLog log = Parse(std::string("1747031522.500 ") + kGpsdPashr + "\n");
  ASSERT_EQ(log.attitudes.size(), 1u);
  const AttitudeSample& a = log.attitudes[0];
  EXPECT_DOUBLE_EQ(a.stamp_s, 1747031522.5);          // the logger's stamp, as a heading's
  EXPECT_NEAR(a.roll_rad, -1.26 * kDegToRad, 1e-12);  // left side down
  EXPECT_NEAR(a.pitch_rad, 0.83 * kDegToRad, 1e-12);  // nose up
  EXPECT_NEAR(a.roll_sigma_rad, 0.101 * kDegToRad, 1e-12);
  EXPECT_NEAR(a.pitch_sigma_rad, 0.113 * kDegToRad, 1e-12);
  EXPECT_EQ(a.line, 1);
  EXPECT_EQ(log.attitudes_by_source.at("$PASHR"), 1);
  // The heading it carries is not a heading sample.
  EXPECT_TRUE(log.headings.empty());
  EXPECT_EQ(log.skipped.Total(), 0);
}

TEST(NmeaAttitudeTest, PlainPashrIsStampedByItsOwnTimeOnTheLogsDate) {
  const NmeaLog log = Parse(S("GPZDA,085335.00,12,05,2025,00,00") + "\n" + kGpsdPashr + "\n");
  ASSERT_EQ(log.attitudes.size(), 1u);
  // 2025-05-12 08:53:35 UTC.
  EXPECT_DOUBLE_EQ(log.attitudes[0].stamp_s, 1747040015.0);
  EXPECT_EQ(log.attitudes[0].line, 2);
}

TEST(NmeaAttitudeTest, ReadsTrimbleAvrTiltAsPitchAndRollAsRoll) {
  // Trimble's examples of the sentence (OEM receiver help, NMEA-0183 message PTNL,AVR): one
  // receiver's vector along the vehicle (Tilt), the other's across it (Roll).
  const NmeaLog log = Parse(
      "1.0 $PTNL,AVR,212405.20,+52.1531,Yaw,-0.0806,Tilt,,,12.575,3,1.4,16*39\n"
      "2.0 $PTNL,AVR,212604.30,+52.1800,Yaw,,,-0.0807,Roll,12.579,3,1.4,16*21\n"
      "3.0 $PTNL,AVR,181059.6,+149.4688,Yaw,+0.0134,Tilt,,,60.191,3,2.5,6*00\n");
  ASSERT_EQ(log.attitudes.size(), 3u);
  EXPECT_NEAR(log.attitudes[0].pitch_rad, -0.0806 * kDegToRad, 1e-12);
  EXPECT_TRUE(std::isnan(log.attitudes[0].roll_rad));  // the sentence does not measure it
  EXPECT_TRUE(std::isnan(log.attitudes[1].pitch_rad));
  EXPECT_NEAR(log.attitudes[1].roll_rad, -0.0807 * kDegToRad, 1e-12);
  EXPECT_NEAR(log.attitudes[2].pitch_rad, 0.0134 * kDegToRad, 1e-12);
  for (const AttitudeSample& a : log.attitudes) {
    EXPECT_TRUE(std::isnan(a.roll_sigma_rad) && std::isnan(a.pitch_sigma_rad));
  }
  EXPECT_EQ(log.attitudes_by_source.at("$PTNL,AVR"), 3);
  EXPECT_TRUE(log.headings.empty());
}

TEST(NmeaAttitudeTest, SkipsPashrWithABadChecksum) {
  // The second line is gpsd's example with its time changed and the checksum left as printed:
  // the sentence is corrupt, not a roll of -1.26°.
  const NmeaLog log = Parse(std::string("1.0 ") + kGpsdPashr + "\n" +
                            "2.0 $PASHR,085335.100,224.19,T,-01.26,+00.83,+00.00,0.101,0.113,"
                            "0.267,1,0*06\n");
  EXPECT_EQ(log.attitudes.size(), 1u);
  EXPECT_EQ(Count(log, "bad checksum"), 1);
  EXPECT_EQ(FirstLine(log, "bad checksum"), 2);
}

TEST(NmeaAttitudeTest, SkipsPashrWithMissingFields) {
  const NmeaLog log =
      Parse("1.0 " + S("PASHR,085335.000,224.19,T,,+00.83,+00.00,0.101,0.113,0.267,1,0") + "\n" +
            "2.0 " + S("PASHR,085335.100,224.19,T,-01.26") + "\n" +
            // No logger stamp and no time of its own: nothing to stamp it with.
            S("PASHR,,224.19,T,-01.26,+00.83,+00.00,0.101,0.113,0.267,1,0") + "\n");
  EXPECT_TRUE(log.attitudes.empty());
  EXPECT_EQ(Count(log, "empty field"), 3);
  EXPECT_EQ(FirstLine(log, "empty field"), 1);
}

TEST(NmeaAttitudeTest, SkipsARollOf95DegreesAndAnythingBeyond30) {
  const NmeaLog log = Parse(
      "1.0 " + S("PASHR,085335.000,224.19,T,+95.00,+00.83,+00.00,0.101,0.113,0.267,1,0") + "\n" +
      "2.0 " + S("PASHR,085335.100,224.19,T,-01.26,-90.00,+00.00,0.101,0.113,0.267,1,0") + "\n" +
      "3.0 " + S("PTNL,AVR,212405.20,+52.1531,Yaw,+30.0001,Tilt,,,12.575,3,1.4,16") + "\n" +
      "4.0 " + S("PTNL,AVR,212405.30,+52.1531,Yaw,,,-31.5,Roll,12.575,3,1.4,16") + "\n" +
      // 30° itself and a steep yard's grade are a vehicle's.
      "5.0 " + S("PASHR,085335.500,224.19,T,-30.00,+29.99,+00.00,0.101,0.113,0.267,1,0") + "\n" +
      "6.0 " + S("PTNL,AVR,212405.60,+52.1531,Yaw,+12.5000,Tilt,,,12.575,3,1.4,16") + "\n");
  ASSERT_EQ(log.attitudes.size(), 2u);
  EXPECT_EQ(log.attitudes[0].line, 5);
  EXPECT_NEAR(log.attitudes[0].roll_rad, -30.0 * kDegToRad, 1e-12);
  EXPECT_EQ(log.attitudes[1].line, 6);
  EXPECT_EQ(Count(log, "roll or pitch beyond 30 deg"), 4);
  EXPECT_EQ(FirstLine(log, "roll or pitch beyond 30 deg"), 1);
  EXPECT_EQ(log.skipped.Problems(), 4);  // a warning, not a line a healthy log has
}

TEST(NmeaAttitudeTest, SkipsNonNumericNanAndNegativeSigmaFields) {
  const NmeaLog log = Parse(
      "1.0 " + S("PTNL,AVR,212405.20,+52.1531,Yaw,abc,Tilt,,,12.575,3,1.4,16") + "\n" + "2.0 " +
      S("PTNL,AVR,212405.30,+52.1531,Yaw,-0.0806,Tilt,,,12.575,three,1.4,16") + "\n" + "3.0 " +
      S("PASHR,085335.000,224.19,T,nan,+00.83,+00.00,0.101,0.113,0.267,1,0") + "\n" + "4.0 " +
      S("PASHR,085335.100,224.19,T,-01.26,+00.83,+00.00,-0.1,0.113,0.267,1,0") + "\n" + "5.0 " +
      S("PASHR,085335.200,224.19,T,-01.26,+00.83,+00.00,0.101,0.113,0.267,1,0") + "\n" +
      // A value without its label is not the AVR sentence.
      "6.0 " + S("PTNL,AVR,212405.40,+52.1531,Yaw,-0.0806,Roll,,,12.575,3,1.4,16") + "\n" + "7.0 " +
      S("PASHR,085335.300,2x4.19,T,-01.26,+00.83,+00.00,0.101,0.113,0.267,1,0") + "\n");
  ASSERT_EQ(log.attitudes.size(), 1u);
  EXPECT_EQ(log.attitudes[0].line, 5);
  EXPECT_EQ(Count(log, "bad field"), 6);
  EXPECT_EQ(FirstLine(log, "bad field"), 1);
}

TEST(NmeaAttitudeTest, UsesOnlyRtkFixedAvrVectors) {
  const NmeaLog log =
      Parse("1.0 " + S("PTNL,AVR,212405.20,+52.1531,Yaw,-0.0806,Tilt,,,12.575,0,1.4,16") + "\n" +
            "2.0 " + S("PTNL,AVR,212405.30,+52.1531,Yaw,-0.0806,Tilt,,,12.575,2,1.4,16") + "\n" +
            "3.0 " + S("PTNL,AVR,212405.40,+52.1531,Yaw,-0.0806,Tilt,,,12.575,,1.4,16") + "\n" +
            "4.0 " + S("PTNL,AVR,212405.50,+52.1531,Yaw,,,,,12.575,3,1.4,16") + "\n");
  EXPECT_TRUE(log.attitudes.empty());
  EXPECT_EQ(Count(log, "AVR without a vector fix (quality 0)"), 1);
  EXPECT_EQ(Count(log, "AVR vector not RTK fixed (quality 1, 2 or 4)"), 1);
  EXPECT_EQ(Count(log, "empty field"), 2);  // no quality; neither tilt nor roll
}

TEST(NmeaAttitudeTest, OtherProprietarySentencesAreOtherSentences) {
  const NmeaLog log = Parse("1.0 " + S("PASHR,ATT,230000.00,123.5,1.2,-0.7,0.01,0.02,0") + "\n" +
                            "2.0 " + S("PTNL,GGK,102939.00,051910,5000.97323841,N") + "\n");
  EXPECT_TRUE(log.attitudes.empty());
  EXPECT_EQ(Count(log, "other sentence (PASHR,ATT)"), 1);
  EXPECT_EQ(Count(log, "other sentence (PTNL,GGK)"), 1);
  EXPECT_EQ(log.skipped.Problems(), 0);  // informational, as other sentences are
}

TEST(NmeaAttitudeTest, SkipsAttitudesNotLaterThanThePreviousOne) {
  const NmeaLog log = Parse(
      "2.0 " + S("PASHR,085335.000,224.19,T,-01.26,+00.83,+00.00,0.101,0.113,0.267,1,0") + "\n" +
      "2.0 " + S("PASHR,085335.000,224.19,T,-01.26,+00.83,+00.00,0.101,0.113,0.267,1,0") + "\n" +
      "1.5 " + S("PASHR,085335.000,224.19,T,-01.26,+00.83,+00.00,0.101,0.113,0.267,1,0") + "\n" +
      "1.9 $HEHDT,123.456,T*28\n");
  EXPECT_EQ(log.attitudes.size(), 1u);
  EXPECT_EQ(log.headings.size(), 1u);  // its own order, not the attitudes'
  EXPECT_EQ(Count(log, "time not increasing"), 2);
}

TEST(NmeaAttitudeTest, ASigmaOfZeroIsNotGiven) {
  const NmeaLog log =
      Parse("1.0 " + S("PASHR,085335.000,224.19,T,-01.26,+00.83,+00.00,0.000,,0.267,1,0") + "\n");
  ASSERT_EQ(log.attitudes.size(), 1u);
  EXPECT_TRUE(std::isnan(log.attitudes[0].roll_sigma_rad));
  EXPECT_TRUE(std::isnan(log.attitudes[0].pitch_sigma_rad));
}

TEST(NmeaAttitudeTest, TheSimulatorsSentencesReadBackWithinTheirFourDecimals) {
  AttitudeSample sample;
  sample.stamp_s = 1747031522.25;
  sample.roll_rad = 2.345678 * kDegToRad;
  sample.pitch_rad = -1.234567 * kDegToRad;
  sample.roll_sigma_rad = 0.05 * kDegToRad;
  sample.pitch_sigma_rad = 0.0625 * kDegToRad;
  AttitudeSample no_sigma = sample;
  no_sigma.stamp_s += 0.25;
  no_sigma.roll_sigma_rad = no_sigma.pitch_sigma_rad = kNaN;
  const std::string text = FormatPashrLine(sample, 4.0) + "\n" + FormatPashrLine(no_sigma, kNaN) +
                           "\n" + FormatAvrLine(no_sigma, 4.0) + "\n";
  const NmeaLog log = ReadNmea(WriteScratchFile("written.nmea", text));
  ASSERT_EQ(log.attitudes.size(), 2u) << text;  // the AVR comes at the same stamp: skipped
  const double step_rad = 0.5e-4 * kDegToRad;
  for (const AttitudeSample& a : log.attitudes) {
    EXPECT_NEAR(a.roll_rad, sample.roll_rad, step_rad);
    EXPECT_NEAR(a.pitch_rad, sample.pitch_rad, step_rad);
  }
  EXPECT_NEAR(log.attitudes[0].stamp_s, sample.stamp_s, 1e-6);
  EXPECT_NEAR(log.attitudes[0].roll_sigma_rad, sample.roll_sigma_rad, step_rad);
  EXPECT_NEAR(log.attitudes[0].pitch_sigma_rad, sample.pitch_sigma_rad, step_rad);
  EXPECT_TRUE(std::isnan(log.attitudes[1].roll_sigma_rad));
  EXPECT_EQ(Count(log, "time not increasing"), 1);

  const NmeaLog avr = ReadNmea(WriteScratchFile("avr.nmea", FormatAvrLine(sample, 4.0) + "\n"));
  ASSERT_EQ(avr.attitudes.size(), 1u);
  EXPECT_NEAR(avr.attitudes[0].roll_rad, sample.roll_rad, step_rad);
  EXPECT_NEAR(avr.attitudes[0].pitch_rad, sample.pitch_rad, step_rad);
}

TEST(NmeaAttitudeTest, AFollowerReadsAttitudesOnAsTheLogGrows) {
  const std::string first =
      "1.0 " + S("PASHR,000001.00,224.19,T,-01.26,+00.83,+00.00,0.101,0.113,0.267,1,0") + "\n";
  const std::string second =
      "2.0 " + S("PTNL,AVR,000002.00,+52.1531,Yaw,-0.0806,Tilt,,,12.575,3,1.4,16") + "\n";
  const std::string path = WriteScratchFile("growing.nmea", first);
  NmeaFollower follower(path);
  follower.ReadMore();
  EXPECT_EQ(follower.Log().attitudes.size(), 1u);
  WriteScratchFile("growing.nmea", first + second);
  EXPECT_EQ(follower.ReadMore(), static_cast<int64_t>(first.size()));
  const NmeaLog grown = follower.Log();
  ASSERT_EQ(grown.attitudes.size(), 2u);
  EXPECT_EQ(grown.attitudes[1].line, 2);
  EXPECT_EQ(grown.attitudes_by_source.at("$PTNL,AVR"), 1);
}

}  // namespace
}  // namespace wallcal::io
