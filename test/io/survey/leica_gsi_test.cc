// SPDX-License-Identifier: Apache-2.0
#include "io/survey/internal/leica_gsi.h"
#include "common/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/survey/survey_reader.h"
#include "test/support/expect_text.h"
#include "test/support/survey_points.h"

namespace wallcal::io {
namespace {

const std::string kRealDir = WALLCAL_SOURCE_DIR "/../shared/testdata/real/gsi";

// The value of the one word on a line "110001+00000001 <word>": the word is the second.
double ValueOf(const std::string& word, GsiQuantity quantity) {
  const std::string line = (word[0] == '*' ? "*110001+0000000000000001 " + word.substr(1)
                                           : "110001+00000001 " + word);
  const std::vector<GsiWord> words = SplitGsiLine(line, "t.gsi", 1);
  EXPECT_EQ(words.size(), 2u);
  return GsiValue(words.at(1), quantity, "t.gsi", 1);
}

TEST(LeicaGsiTest, EveryLengthUnitDigit) {
  // Leica TPS1100 User Manual, "Units of measurement" (position 6 of the word).
  EXPECT_DOUBLE_EQ(ValueOf("81..00+00012345", GsiQuantity::kLength), 12.345);     // 1 mm
  EXPECT_DOUBLE_EQ(ValueOf("81..06+00012345", GsiQuantity::kLength), 1.2345);     // 0.1 mm
  EXPECT_DOUBLE_EQ(ValueOf("81..08+00012345", GsiQuantity::kLength), 0.12345);    // 0.01 mm
  EXPECT_DOUBLE_EQ(ValueOf("81..01+00010000", GsiQuantity::kLength), 3.048);      // 10.000 ft
  EXPECT_DOUBLE_EQ(ValueOf("81..07+00100000", GsiQuantity::kLength), 3.048);      // 10.0000 ft
  EXPECT_DOUBLE_EQ(ValueOf("86..00-00000588", GsiQuantity::kLength), -0.588);     // the sign
  EXPECT_DOUBLE_EQ(ValueOf("*81..00+0000000565300123", GsiQuantity::kLength),  // GSI-16
                   565300.123);
}

TEST(LeicaGsiTest, EveryAngleUnitDigit) {
  EXPECT_NEAR(ValueOf("21.102+10000000", GsiQuantity::kAngle), kPi / 2, 1e-15);  // 100 gon
  EXPECT_NEAR(ValueOf("21.103+09000000", GsiQuantity::kAngle), kPi / 2, 1e-15);  // 90 deg
  EXPECT_NEAR(ValueOf("21.105+16000000", GsiQuantity::kAngle), kPi / 2, 1e-15);  // 1600 mil
  EXPECT_NEAR(ValueOf("21.102+00000001", GsiQuantity::kAngle), 1e-5 * kPi / 200, 1e-20);
  // 123°45'12.0": 123 + 45/60 + 12/3600 = 123.753333...°
  EXPECT_NEAR(ValueOf("21.104+12345120", GsiQuantity::kAngle), 123.7533333333333 * kPi / 180,
              1e-14);
  // The GSI-16 example of the real job: 91°17'51.0", tenths of a second in the last digit.
  EXPECT_NEAR(ValueOf("*22.024+0000000009117515", GsiQuantity::kAngle),
              (91.0 + 17.0 / 60 + 51.5 / 3600) * kPi / 180, 1e-14);
}

TEST(LeicaGsiTest, SexagesimalAnglesSplitWithIntegers) {
  // 359°59'59.9" = 12 959 999 tenths of a second exactly; a split of the decimal 359.59599
  // in floating point can land on 59.8999...".
  const double tenths = ((359.0 * 60 + 59) * 60 + 59) * 10 + 9;
  EXPECT_DOUBLE_EQ(ValueOf("21.104+35959599", GsiQuantity::kAngle),
                   tenths * (kPi / (180.0 * 36000.0)));
  EXPECT_THROW(ValueOf("21.104+12360000", GsiQuantity::kAngle), InputError);  // 60 minutes
  EXPECT_THROW(ValueOf("21.104+12305600", GsiQuantity::kAngle), InputError);  // 60 seconds
}

TEST(LeicaGsiTest, ReducesAPolarObservationFromTheSetUp) {
  const std::string text =
      // Before any set-up: the local origin, no instrument or reflector height. Hz 0, V level.
      "110001+000000P0 21.102+00000000 22.102+10000000 31..00+00005000\r\n"
      // Set-up: station E 100, N 200, H 10, instrument height 1.500.
      "110002+0000STN1 84..10+00100000 85..10+00200000 86..10+00010000 88..10+00001500\r\n"
      // Hz 50 gon (45°), V 100 gon (level), 10 m, reflector 1.300:
      //   E = 100 + 10 sin 45° = 107.0710678, N = 200 + 10 cos 45° = 207.0710678,
      //   H = 10 + 1.5 + 0 - 1.3 = 10.2
      "110003+000000P1 21.102+05000000 22.102+10000000 31..00+00010000 87..10+00001300\r\n"
      // Hz 300 gon (west), V 50 gon (45° up), 10 m, the reflector kept: d = 7.0710678,
      //   E = 100 - 7.0710678 = 92.9289322, N = 200, H = 10 + 1.5 + 7.0710678 - 1.3 = 17.2710678
      "110004+000000P2 21.102+30000000 22.102+05000000 31..00+00010000\r\n"
      // Stored coordinates win over the polar words on the same line.
      "110005+000000P3 21.102+00000000 22.102+10000000 31..00+00001000 81..00+00001000 "
      "82..00+00002000 83..00+00003000 71....+0000WALL\r\n";
  const GsiFile file = ParseGsi(text, "t.gsi");
  ASSERT_EQ(file.records.size(), 4u);
  EXPECT_EQ(file.setups, 1);
  const std::vector<SurveyPoint> points = GsiSurveyPoints(file);
  ASSERT_EQ(points.size(), 4u);
  EXPECT_EQ(points[0].id, "P0");
  EXPECT_EQ(points[0].source, SurveySource::kPolarFromOrigin);
  EXPECT_NEAR(points[0].x_m, 0.0, 1e-12);
  EXPECT_NEAR(points[0].y_m, 5.0, 1e-12);
  EXPECT_NEAR(points[0].z_m, 0.0, 1e-12);
  EXPECT_EQ(points[1].id, "P1");
  EXPECT_EQ(points[1].line, 3);
  EXPECT_EQ(points[1].source, SurveySource::kPolarFromSetup);
  EXPECT_NEAR(points[1].x_m, 107.0710678, 1e-7);
  EXPECT_NEAR(points[1].y_m, 207.0710678, 1e-7);
  EXPECT_NEAR(points[1].z_m, 10.2, 1e-9);
  EXPECT_NEAR(points[2].x_m, 92.9289322, 1e-7);
  EXPECT_NEAR(points[2].y_m, 200.0, 1e-9);
  EXPECT_NEAR(points[2].z_m, 17.2710678, 1e-7);
  EXPECT_EQ(points[3].id, "P3");
  EXPECT_EQ(points[3].code, "WALL");
  EXPECT_EQ(points[3].source, SurveySource::kCoordinates);
  EXPECT_DOUBLE_EQ(points[3].x_m, 1.0);
  EXPECT_DOUBLE_EQ(points[3].y_m, 2.0);
  EXPECT_DOUBLE_EQ(points[3].z_m, 3.0);
}

TEST(LeicaGsiTest, Gsi16LinesAndIdsWithLettersAreRead) {
  const std::string text =
      "*110002+00000000GDEM5415 21.024+0000000009000000 22.024+0000000009000000 "
      "31...0+0000000000010000 87...0+0000000000001300 88...0+0000000000001324 \n";
  std::istringstream in(text);
  const std::vector<SurveyPoint> points = ParseSurvey(in, "t.gsi");
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0].id, "GDEM5415");
  // Hz 90° (east), V 90° (level), 10 m: E 10, N 0, H 1.324 - 1.300 = 0.024.
  EXPECT_NEAR(points[0].x_m, 10.0, 1e-12);
  EXPECT_NEAR(points[0].y_m, 0.0, 1e-12);
  EXPECT_NEAR(points[0].z_m, 0.024, 1e-12);
}

// Bad input: the message names file:line and what was expected, never the file's characters
// (every bad line below carries the id SECRET01 / digits 97531 that must not appear).
void ExpectGsiError(const std::string& text, const std::string& where, const std::string& what) {
  SCOPED_TRACE(text);
  std::istringstream in(text);
  try {
    ParseSurvey(in, "job.gsi");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("job.gsi" + where, 0), 0u) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
    testing_support::ExpectLacks(message, {"SECRET", "97531"});
  }
}

// A job downloaded with CR alone (or CRLF) at the line ends is still recognised as GSI.
TEST(LeicaGsiTest, EveryLineEndIsRecognised) {
  const std::string lines[] = {
      "110001+0000C001 71....+0000CTRL 81..00+00100000 82..00+00200000 83..00+00001000 ",
      "110002+0000W001 71....+000WALL1 81..00+00110000 82..00+00205000 83..00+00001500 ",
  };
  for (const std::string eol : {"\n", "\r\n", "\r"}) {
    SCOPED_TRACE(eol == "\r" ? "CR" : eol == "\n" ? "LF" : "CRLF");
    std::istringstream in(lines[0] + eol + lines[1] + eol);
    const std::vector<SurveyPoint> points = ParseSurvey(in, "job.gsi");
    ASSERT_EQ(points.size(), 2u);
    testing_support::ExpectPoint(
        points[1], {SurveyFrame::kLocal, "W001", "WALL1", {110.0, 205.0, 1.5}, 0.0, 2});
  }
}

TEST(LeicaGsiTest, RejectsBadWordsWithFileLineAndWhatWasExpected) {
  const std::string good = "110001+SECRET01 81..00+00097531 82..00+00097531 83..00+00097531\n";
  ExpectGsiError(good + "110002+SECRET01 81..09+00097531 82..00+00097531 83..00+00097531\n",
                 ":2: ", "word 2 (index 81) has unit 9, not a GSI unit; expected a length unit");
  ExpectGsiError("110002+SECRET01 81..0x+00097531 82..00+00097531 83..00+00097531\n", ":1: ",
                 "a unit that is not a digit");
  ExpectGsiError("110002+SECRET01 81..02+00097531 82..00+00097531 83..00+00097531\n", ":1: ",
                 "has an angle unit (2); expected a length unit");
  ExpectGsiError("110002+SECRET01 21.100+00097531 22.102+00097531 31..00+00097531\n", ":1: ",
                 "has a length unit (0); expected an angle unit");
  ExpectGsiError(good + good + "110002+SECRET01 81..00+0009\n", ":3: ",
                 "word 2 is cut short: 11 characters where a GSI-8 word has 15");
  ExpectGsiError("81..00+00097531 82..00+00097531 83..00+00097531\n", ":1: ",
                 "a position without a point id; expected word 11");
  ExpectGsiError("110002+SECRET01 81..00+0000000000097531 82..00+00097531\n", ":1: ",
                 "runs on past the 15 characters of a GSI-8 word");
  ExpectGsiError("110002+SECRET01 81..00*00097531 82..00+00097531 83..00+00097531\n", ":1: ",
                 "no sign");
  ExpectGsiError("110002+SECRET01 81..00+0009753X 82..00+00097531 83..00+00097531\n", ":1: ",
                 "not all digits");
  ExpectGsiError("110002+SECRET01 81..00+00097531 82..00+00097531\n", ":1: ",
                 "target coordinates with 2 of its words 81, 82 and 83; expected all three");
  ExpectGsiError("110002+SECRET01 84..00+00097531 85..00+00097531\n", ":1: ",
                 "a station set-up with 2 of its words 84, 85 and 86");
  ExpectGsiError("110002+SECRET01 21.102+00097531 31..00+00097531\n", ":1: ",
                 "a slope distance (word 31) without both angles");
  ExpectGsiError("110002+SECRET01 81..00+00097531 81..00+00097531 83..00+00097531\n", ":1: ",
                 "repeats an index");
  ExpectGsiError("110002+         81..00+00097531 82..00+00097531 83..00+00097531\n", ":1: ",
                 "the point id (word 11) is blank");
  ExpectGsiError(std::string("110002+SECRET\x01") +
                     "1 81..00+00097531 82..00+00097531 83..00+00097531\n",
                 ":1: ", "unprintable");
  ExpectGsiError("110002+SECRET01 21.102+00097531 22.102+00097531\n", ": ",
                 "no point with a position");
}

// --- The real jobs (totalopenstation sample data, ../shared/testdata/real/gsi) ---------------

std::string RealFile(const std::string& name) {
  const std::string path = kRealDir + "/" + name;
  return std::filesystem::exists(path) ? path : "";
}

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The GSI-8 job stores coordinates (81/82/83) and the polar observation (21/22/31) on the same
// lines. Where the set-up is in the file (lines 498/499 and 531), the reduction agrees with the
// stored coordinates within the rounding of the words: per horizontal axis 0.5 mm (81/82) +
// 0.5 mm (84/85) + 0.5 mm (31) + angle rounding 0.5e-5 gon × 120 m = 0.01 mm → 1.51 mm; in
// height 0.5 mm each for 83, 86, 87, 88 and 31 → 2.5 mm. Measured (independent Python decode):
// 1.08 mm east, 0.73 mm north, 0.91 mm height. From line 624 the instrument used a station
// that the file does not record: the difference is then a constant shift, checked as such.
TEST(LeicaGsiTest, RealGsi8JobReductionAgreesWithItsStoredCoordinates) {
  const std::string path = RealFile("leica_gsi8_ertola.gsi");
  if (path.empty()) GTEST_SKIP() << "no ../shared/testdata/real (the shared test data)";
  const GsiFile file = ParseGsi(Slurp(path), path);
  EXPECT_EQ(file.records.size(), 695u);  // 699 lines: 4 set-ups
  EXPECT_EQ(file.setups, 4);
  EXPECT_EQ(file.angle_only_lines, 0);
  EXPECT_EQ(file.other_lines, 0);
  EXPECT_FALSE(file.gsi16);

  int agreeing = 0, shifted = 0, before_setup = 0;
  double max_e = 0, max_n = 0, max_h = 0;
  std::vector<GsiPosition> shifts;
  for (const GsiRecord& r : file.records) {
    if (!r.has_coordinates || !r.has_polar) continue;
    if (r.setup.line == 0) {
      ++before_setup;
      continue;
    }
    const GsiPosition reduced = ReduceGsiPolar(r.setup, r.polar);
    const GsiPosition d{r.coordinates.e_m - reduced.e_m, r.coordinates.n_m - reduced.n_m,
                        r.coordinates.h_m - reduced.h_m};
    if (r.line < 624) {
      ++agreeing;
      max_e = std::max(max_e, std::abs(d.e_m));
      max_n = std::max(max_n, std::abs(d.n_m));
      max_h = std::max(max_h, std::abs(d.h_m));
    } else {
      ++shifted;
      shifts.push_back(d);
    }
  }
  EXPECT_EQ(before_setup, 495);  // and line 528 holds coordinates only
  EXPECT_EQ(agreeing, 117);  // lines 500..524 (set-up 498/499) and 532..623 (set-up 531)
  EXPECT_EQ(shifted, 76);
  EXPECT_LT(max_e, 1.51e-3);
  EXPECT_LT(max_n, 1.51e-3);
  EXPECT_LT(max_h, 2.5e-3);
  for (const GsiPosition& d : shifts) {  // mean shift -263.4, +263.6, +80.5 mm
    EXPECT_NEAR(d.e_m, -0.2634, 2e-3);
    EXPECT_NEAR(d.n_m, 0.2636, 2e-3);
    EXPECT_NEAR(d.h_m, 0.0805, 2e-3);
  }

  const std::vector<SurveyPoint> points = ReadSurvey(path);
  ASSERT_EQ(points.size(), 695u);
  int stored = 0, from_setup = 0, from_origin = 0;
  for (const SurveyPoint& p : points) {
    stored += p.source == SurveySource::kCoordinates;
    from_setup += p.source == SurveySource::kPolarFromSetup;
    from_origin += p.source == SurveySource::kPolarFromOrigin;
  }
  EXPECT_EQ(stored, 689);
  EXPECT_EQ(from_setup, 4);   // lines 525, 526, 529, 530
  EXPECT_EQ(from_origin, 2);  // lines 496, 497, before the first set-up
  testing_support::ExpectPoint(points[0],
                               {SurveyFrame::kLocal, "1", "1", {515.836, 525.871, 3.079}});

  // Ids 1.. are used twice for different points (11.7 m to 114 m apart): nothing is averaged.
  const SurveyCombination combined = CombineSurveyObservations(points);
  EXPECT_EQ(combined.points.size(), 695u);
  EXPECT_EQ(combined.repeated_points, 0);
  EXPECT_EQ(combined.ids_naming_several_places, 111);
  EXPECT_EQ(combined.warnings.size(), 2u);  // reused ids; polar before the first set-up
}

// The GSI-16 job is polar only, without a set-up: reduced from the local origin with the
// instrument height of word 88 (1.324 m) and the reflector height of word 87 (1.300 m).
TEST(LeicaGsiTest, RealGsi16JobIsReducedFromTheLocalOrigin) {
  const std::string path = RealFile("leica_gsi16_gurob.gsi");
  if (path.empty()) GTEST_SKIP() << "no ../shared/testdata/real (the shared test data)";
  const std::vector<SurveyPoint> points = ReadSurvey(path);
  ASSERT_EQ(points.size(), 343u);
  for (const SurveyPoint& p : points) EXPECT_EQ(p.source, SurveySource::kPolarFromOrigin);
  // Independent decode: GDEM5415 at line 1, GDEM5829 at line 343.
  EXPECT_EQ(points.front().id, "GDEM5415");
  EXPECT_NEAR(points.front().x_m, 8.07572441881647, 1e-9);
  EXPECT_NEAR(points.front().y_m, 11.21674196188313, 1e-9);
  EXPECT_NEAR(points.front().z_m, -0.28904931218822605, 1e-9);
  EXPECT_EQ(points.back().id, "GDEM5829");
  EXPECT_NEAR(points.back().x_m, -375.9433394831511, 1e-9);
  EXPECT_NEAR(points.back().y_m, 6.232124779101028, 1e-9);
  EXPECT_NEAR(points.back().z_m, -0.25438363304449063, 1e-9);

  // Lines 97..119 are repeated as lines 120..142: 23 points observed twice, identically.
  const SurveyCombination combined = CombineSurveyObservations(points);
  EXPECT_EQ(combined.points.size(), 320u);
  EXPECT_EQ(combined.repeated_points, 23);
  EXPECT_EQ(combined.ids_naming_several_places, 0);
  EXPECT_DOUBLE_EQ(combined.max_repeat_spread_m, 0.0);
  EXPECT_TRUE(combined.warnings.empty());
}

}  // namespace
}  // namespace wallcal::io
