// SPDX-License-Identifier: Apache-2.0
#include "io/survey/survey_reader.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"
#include "test/support/survey_points.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;
using testing_support::ExpectPoint;
using testing_support::WriteScratchFile;

TEST(SurveyReaderTest, ReadsTheSessionExample) {
  const std::vector<SurveyPoint> points = ReadSurvey(WriteScratchFile(
      "example.csv", "id,x,y,z,code\nC1,0.000,0.000,0.000,CTRL\nW001,1.002,10.013,0.512,WALL1\n"));
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].id, "C1");
  EXPECT_EQ(points[0].code, "CTRL");
  ExpectPoint(points[1], {SurveyFrame::kLocal, "W001", "WALL1", {1.002, 10.013, 0.512}, 0.0, 3});
  EXPECT_EQ(points[1].source, SurveySource::kCoordinates);
  EXPECT_EQ(points[1].observations, 1);
}

// LF, CRLF and a CR alone each end a line: the same points, with the same line numbers.
TEST(SurveyReaderTest, ReadsEveryLineEnd) {
  for (const std::string eol : {"\n", "\r\n", "\r"}) {
    SCOPED_TRACE(eol == "\r" ? "CR" : eol == "\n" ? "LF" : "CRLF");
    const std::vector<SurveyPoint> points = ReadSurvey(WriteScratchFile(
        "eol.csv", "# job" + eol + "id,x,y,z,code" + eol + "C1,0.000,0.000,0.000,CTRL" + eol +
                       eol + "W001,1.002,10.013,0.512,WALL1" + eol));
    ASSERT_EQ(points.size(), 2u);
    ExpectPoint(points[1], {SurveyFrame::kLocal, "W001", "WALL1", {1.002, 10.013, 0.512}, 0.0, 5});
  }
}

// Surveyors' exports: units in the header, semicolons with decimal commas, tabs.
// Expects the one point each spelling of the sample row gives: W001 of WALL1 at (1.002, 10.013,
// 0.512).
void ExpectOnlyW001(const std::vector<SurveyPoint>& points) {
  ASSERT_EQ(points.size(), 1u);
  ExpectPoint(points[0], {SurveyFrame::kLocal, "W001", "WALL1", {1.002, 10.013, 0.512}});
}

TEST(SurveyReaderTest, ReadsUnitsSemicolonsDecimalCommasAndTabs) {
  const std::string variants[] = {
      "Point,Easting (m),Northing (m),Elev [m],Code\nW001,1.002,10.013,0.512,WALL1\n",
      "Point;Easting;Northing;Elevation;Code\nW001;1,002;10,013;0,512;WALL1\n",
      "Point\tE [m]\tN [m]\tZ [m]\tDescription\nW001\t1.002\t10.013\t0.512\tWALL1\n",
      "Point\tEasting\tNorthing\tHeight\tCode\nW001\t1,002\t10,013\t0,512\tWALL1\n",
      "Point\tEasting\tNorthing\tHeight\tCode\nW001\t\t10,013\t0,512\tWALL1\n",
  };
  for (size_t i = 0; i < 4; ++i) {
    SCOPED_TRACE(variants[i]);
    const std::vector<SurveyPoint> points = ReadSurvey(WriteScratchFile("variant.csv", variants[i]));
    ExpectOnlyW001(points);
  }
  // An empty field between two tabs stays a field of its own: the easting is missing.
  try {
    ReadSurvey(WriteScratchFile("empty.csv", variants[4]));
    ADD_FAILURE() << "an empty easting was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("column 2 (easting) is empty"), std::string::npos)
        << e.what();
  }
}

// W001 at easting 1.002, northing 10.013, elevation 0.512, code WALL1, in every variant:
// x/E is east, y/N north, whatever the column order.
TEST(SurveyReaderTest, AcceptsSurveyorHeadersInAnyOrderAndCase) {
  const std::string variants[] = {
      "# exported by the total station\r\n\r\nCode , N , E , Z , "
      "ID\r\nWALL1,10.013,1.002,0.512,W001\r\n",
      "\xEF\xBB\xBF"
      "Point,Northing,Easting,Elevation,Description\nW001,10.013,1.002,0.512,WALL1\n",
      "POINT ID,EASTING,NORTHING,ELEV,DESC,Remark\nW001,1.002,10.013,0.512,WALL1,ok\n",
      "pt,description,north,east,height\nW001,WALL1,10.013,1.002,0.512\n",
      " ID , Code , X , Y , Z , Date\nW001,WALL1,1.002,10.013,+0.512,2024-05-12\n",
      "\"id\",\"code\",\"x\",\"y\",\"z\"\n\"W001\",\"WALL1\",1.002,10.013,0.512\n",
      "id,x_m,y_m,z_m,code\nW001,1.00200,10.01300,0.51200,WALL1\n",  // the dump's own header
  };
  int index = 0;
  for (const std::string& content : variants) {
    SCOPED_TRACE(content);
    const std::vector<SurveyPoint> points =
        ReadSurvey(WriteScratchFile("variant" + std::to_string(index++) + ".csv", content));
    ExpectOnlyW001(points);
  }
}

TEST(SurveyReaderTest, ReadsHeaderlessPnezdAndPenzd) {
  // A description with a comma, quoted as spreadsheets write it; the last row has none.
  const std::string pnezd = "1,10.013,1.002,0.512,\"WALL1, north\"\n2,20,3,0.5\n";
  const std::vector<SurveyPoint> a = ReadSurvey(WriteScratchFile("pnezd.csv", pnezd), SurveyColumns::kPNEZD);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].id, "1");
  EXPECT_EQ(a[0].code, "WALL1, north");
  EXPECT_DOUBLE_EQ(a[0].x_m, 1.002);   // easting: the third column of PNEZD
  EXPECT_DOUBLE_EQ(a[0].y_m, 10.013);  // northing: the second
  EXPECT_DOUBLE_EQ(a[0].z_m, 0.512);
  EXPECT_EQ(a[1].code, "");
  EXPECT_DOUBLE_EQ(a[1].x_m, 3.0);
  EXPECT_DOUBLE_EQ(a[1].y_m, 20.0);

  const std::vector<SurveyPoint> b =
      ReadSurvey(WriteScratchFile("penzd.csv", "1,1.002,10.013,0.512,WALL1\n"), SurveyColumns::kPENZD);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_DOUBLE_EQ(b[0].x_m, 1.002);
  EXPECT_DOUBLE_EQ(b[0].y_m, 10.013);

  // A header row in a file said to have none: the first row's number fails, with a hint.
  try {
    ReadSurvey(WriteScratchFile("pnezd_header.csv", "Point,Northing,Easting,Elevation,Description\n"),
               SurveyColumns::kPNEZD);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":1: column 3 (easting) is not a finite number"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("survey.columns: PNEZD says the file has no header"),
              std::string::npos)
        << e.what();
  }
}

TEST(SurveyReaderTest, KeepsEveryObservationAndCombinesRepeats) {
  const std::string csv =
      "id,e,n,z,code\n"
      "C1,0.000,0.000,0.000,CTRL\n"
      "W1,1.000,10.000,0.500,WALL1\n"  // face I
      "W1,1.010,10.000,0.520,WALL1\n"  // face II: 22.4 mm from face I
      "C1,50.000,0.000,0.000,CTRL\n";  // the same id 50 m away: another point
  const std::vector<SurveyPoint> observations = ReadSurvey(WriteScratchFile("repeats.csv", csv));
  ASSERT_EQ(observations.size(), 4u);
  EXPECT_EQ(FormatSurveyDumpCsv(observations),
            "id,x_m,y_m,z_m,code\n"
            "C1,0.00000,0.00000,0.00000,CTRL\n"
            "W1,1.00000,10.00000,0.50000,WALL1\n"
            "W1,1.01000,10.00000,0.52000,WALL1\n"
            "C1,50.00000,0.00000,0.00000,CTRL\n");

  const SurveyCombination combined = CombineSurveyObservations(observations);
  ASSERT_EQ(combined.points.size(), 3u);
  EXPECT_EQ(combined.points[0].id, "C1");
  EXPECT_EQ(combined.points[1].id, "W1");
  EXPECT_EQ(combined.points[1].observations, 2);
  EXPECT_EQ(combined.points[1].line, 3);
  EXPECT_DOUBLE_EQ(combined.points[1].x_m, 1.005);
  EXPECT_DOUBLE_EQ(combined.points[1].z_m, 0.51);
  EXPECT_EQ(combined.points[2].id, "C1");
  EXPECT_DOUBLE_EQ(combined.points[2].x_m, 50.0);
  EXPECT_EQ(combined.repeated_points, 1);
  EXPECT_NEAR(combined.max_repeat_spread_m, 0.5 * std::hypot(0.01, 0.02), 1e-12);
  EXPECT_EQ(combined.ids_naming_several_places, 1);
  ASSERT_EQ(combined.warnings.size(), 1u);
  EXPECT_NE(combined.warnings[0].find("lines 2 and 5, 50.000 m apart"), std::string::npos)
      << combined.warnings[0];

  // A tighter tolerance keeps the two faces apart.
  EXPECT_EQ(CombineSurveyObservations(observations, 0.01).points.size(), 4u);
}

// The grouping looks at neighbouring grid cells only; it must still find the first group in
// reach across a cell border, and keep places apart that are just beyond the tolerance.
TEST(SurveyReaderTest, CombiningJoinsAcrossCellBordersAndKeepsFarPlacesApart) {
  std::vector<SurveyPoint> observations(5);
  for (SurveyPoint& p : observations) p.id = "P";
  observations[0].x_m = 0.0299;   // cell 0 (3 cm cells)
  observations[1].x_m = 0.0301;   // cell 1, 0.2 mm away: joins group 0
  observations[2].x_m = 0.0700;   // 40.1 mm from the first anchor: a new place
  observations[3].x_m = 0.0990;   // 29 mm from the second anchor, 69 mm from the first: joins it
  observations[4].x_m = -0.00005;  // 29.95 mm from the first anchor: joins it
  const SurveyCombination combined = CombineSurveyObservations(observations);
  ASSERT_EQ(combined.points.size(), 2u);
  EXPECT_EQ(combined.points[0].observations, 3);
  EXPECT_NEAR(combined.points[0].x_m, (0.0299 + 0.0301 - 0.00005) / 3, 1e-15);
  EXPECT_EQ(combined.points[1].observations, 2);
  EXPECT_NEAR(combined.points[1].x_m, (0.07 + 0.099) / 2, 1e-15);
  EXPECT_EQ(combined.ids_naming_several_places, 1);

  // Many observations of one id, all far apart, stay separate (and quickly).
  std::vector<SurveyPoint> spread(20000);
  for (size_t i = 0; i < spread.size(); ++i) {
    spread[i].id = "same";
    spread[i].x_m = static_cast<double>(i);
  }
  EXPECT_EQ(CombineSurveyObservations(spread).points.size(), 20000u);
}

TEST(SurveyReaderTest, DumpQuotesIdsAndCodesAndReadsBack) {
  std::vector<SurveyPoint> points(2);
  points[0].id = "A,1";
  points[0].code = "say \"hi\"";
  points[0].x_m = 1.234567;
  points[1].id = "B";
  points[1].code = " padded ";
  points[1].y_m = -2.5;
  const std::string dump = FormatSurveyDumpCsv(points);
  EXPECT_EQ(dump,
            "id,x_m,y_m,z_m,code\n"
            "\"A,1\",1.23457,0.00000,0.00000,\"say \"\"hi\"\"\"\n"
            "B,0.00000,-2.50000,0.00000,\" padded \"\n");
  const std::vector<SurveyPoint> back = ReadSurvey(WriteScratchFile("dump.csv", dump));
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].id, "A,1");
  EXPECT_EQ(back[0].code, "say \"hi\"");
  EXPECT_EQ(back[1].code, " padded ");
  EXPECT_DOUBLE_EQ(back[1].y_m, -2.5);
}

// The file's error message must name the file, the line when there is one, and the problem,
// and never quote the file: every bad file below holds SECRET, which must not appear.
void ExpectError(const std::string& name, const std::string& content, const std::string& where,
                 const std::string& text, SurveyColumns columns = SurveyColumns::kHeader) {
  SCOPED_TRACE(name);
  const std::string path = WriteScratchFile(name + ".csv", content);
  try {
    ReadSurvey(path, columns);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + where, 0), 0u) << message;
    EXPECT_NE(message.find(text), std::string::npos) << message;
    EXPECT_EQ(message.substr(path.size()).find("SECRET"), std::string::npos) << message;
  }
}

// A bad survey file, where its message points (after the path) and what it says.
struct BadSurvey {
  const char* name;
  const char* content;
  const char* where;
  const char* text;
  SurveyColumns columns = SurveyColumns::kHeader;
};

TEST(SurveyReaderTest, RejectsBadFilesWithFileAndLine) {
  const BadSurvey kBad[] = {
    {"no_header", "# only a comment\n\n", ": ", "no header"},
    {"missing_column", "id,x,SECRET,code\nW1,1,2,WALL1\n", ":1: ",
     "the header's 4 columns name no northing, elevation; expected a header naming"},
    {"unrecognised", "Foo,Bar,SECRET\n1,2,3\n", ":1: ",
     "the header's 3 columns name no point id, easting, northing, elevation, code"},
    {"headerless", "1,2,3,4,SECRET\n", ":1: ", "survey.columns: PNEZD or PENZD"},
    {"no_code", "id,x,y,z\nW1,1,2,3\n", ":1: ", "name no code"},
    {"ambiguous", "id,x,e,y,z,code\nW1,1,1,2,3,W\n", ":1: ",
     "column 2 and column 3 both name the easting; expected one column"},
    {"field_count", "id,x,y,z,code\nW1,1,2,3,WALL1\nW2,1,2,SECRET\n", ":3: ",
     "4 fields; expected 5 as in the header"},
    {"non_numeric", "id,x,y,z,code\nW1,1,2,3,WALL1\n\nW2,1,SECRET,3,WALL1\n", ":4: ",
     "column 3 (northing) is not a finite number (6 characters); expected a number"},
    {"non_finite", "id,x,y,z,code\nW1,1,2,inf,SECRET\n", ":2: ", "finite number"},
    {"nan", "id,x,y,z,code\nW1,nan,2,3,SECRET\n", ":2: ", "finite number"},
    {"empty_coordinate", "id,x,y,z,code\nW1,,2,3,SECRET\n", ":2: ", "column 2 (easting) is empty"},
    {"empty_id", "id,x,y,z,code\n ,1,2,3,SECRET\n", ":2: ", "column 1 (point id) is empty"},
    {"control_char", "id,x,y,z,code\nSECRET\x1b[2J,1,2,3,W\n", ":2: ",
     "the point id has a control character"},
    {"open_quote", "id,x,y,z,code\nW1,1,2,3,\"SECRET\n", ":2: ", "a quoted field is never closed"},
    {"no_points", "id,x,y,z,code\n# nothing\n", ": ", "no survey points"},
    {"huge", "id,x,y,z,code\nW1,1,2,3,SECRET\nW2,1e10,2,3,SECRET\n", ":3: ",
     "a coordinate beyond ±1e9 m"},
    {"pnezd_fields", "1,2,3\n", ":1: ", "3 fields; expected 5 (PNEZD) or 4", SurveyColumns::kPNEZD},
  };
  for (const BadSurvey& bad : kBad) {
    ExpectError(bad.name, bad.content, bad.where, bad.text, bad.columns);
  }
}

TEST(SurveyReaderTest, MissingFileNamesThePath) {
  const std::string path = ::testing::TempDir() + "/survey_reader_test_missing.csv";
  const std::string message = testing_support::MessageOf<InputError>([&] { ReadSurvey(path); });
  EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
}

}  // namespace
}  // namespace wallcal::io
