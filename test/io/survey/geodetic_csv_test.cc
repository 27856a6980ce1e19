// SPDX-License-Identifier: Apache-2.0
// Rover surveys (latitude, longitude, ellipsoidal height) through the public survey reader.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "io/survey/survey_reader.h"
#include "test/support/scratch_dir.h"
#include "test/support/survey_points.h"

namespace wallcal::io {
namespace {

using testing_support::ExpectPoint;

std::string WriteFile(const std::string& name, const std::string& content) {
  static const testing_support::ScratchDir scratch("geodetic_csv_test_");
  const std::string path = (scratch.path() / name).string();
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

// The message of the InputError `path` raises ("" when it reads).
std::string ErrorOf(const std::string& path) {
  try {
    ReadSurvey(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(GeodeticCsvTest, ReadsARoverExport) {
  const std::vector<SurveyPoint> points = ReadSurvey(
      WriteFile("rover.csv",
                "Name,Latitude,Longitude,Ellipsoidal height,Code\n"
                "R001,43.071308123,141.339712345,72.5012,WALL1\n"
                "R002,-34.600000001,-58.400000002,25.25,WALL1\n"));
  ASSERT_EQ(points.size(), 2u);
  // No precision column: sigma_m 0, the session's applies.
  ExpectPoint(points[0], {SurveyFrame::kGeodetic, "R001", "WALL1",
                          {43.071308123, 141.339712345, 72.5012}, 0.0, 2});
  EXPECT_DOUBLE_EQ(points[1].lat_deg, -34.600000001);
  EXPECT_DOUBLE_EQ(points[1].lon_deg, -58.400000002);
}

// The same point in the forms rover apps write: units in the header, another column order and
// case, a precision column, semicolons with decimal commas, tabs, CR and CRLF line ends.
TEST(GeodeticCsvTest, AcceptsRoverAppVariants) {
  const std::string variants[] = {
      "Code,Point ID,Lat (deg),Lon (deg),H ell [m],H prec (m)\nWALL1,R001,43.0713,141.3397,72.5,"
      "0.012\n",
      "name;latitude;longitude;ellipsoidal height;code;sigma\nR001;43,0713;141,3397;72,5;WALL1;"
      "0,012\n",
      "Name\tLatitude\tLongitude\tEllipsoidal height\tCode\tHRMS\nR001\t43.0713\t141.3397\t72.5\t"
      "WALL1\t0.012\n",
      "Name,Latitude,Longitude,Ellipsoidal height,Code,Sigma\rR001,43.0713,141.3397,72.5,WALL1,"
      "0.012\r",
      "\xEF\xBB\xBF# from the rover\r\nName,Latitude,Longitude,Ellipsoidal height,Code,Sigma\r\n"
      "\"R001\",43.0713,141.3397,72.5,\"WALL1\",0.012\r\n",
  };
  int index = 0;
  for (const std::string& content : variants) {
    SCOPED_TRACE(content);
    const std::vector<SurveyPoint> points =
        ReadSurvey(WriteFile("variant" + std::to_string(index++) + ".csv", content));
    ASSERT_EQ(points.size(), 1u);
    ExpectPoint(points[0],
                {SurveyFrame::kGeodetic, "R001", "WALL1", {43.0713, 141.3397, 72.5}, 0.012});
  }
}

TEST(GeodeticCsvTest, ATotalStationFileStaysLocal) {
  const std::vector<SurveyPoint> points =
      ReadSurvey(WriteFile("local.csv", "id,x,y,z,code\nW001,1.0,2.0,3.0,WALL1\n"));
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0].frame, SurveyFrame::kLocal);
}

TEST(GeodeticCsvTest, NamesWhatIsWrongWithFileAndLine) {
  const std::string header = "Name,Latitude,Longitude,Ellipsoidal height,Code,Sigma\n";
  struct Case {
    std::string content;
    std::string expected;  // a part of the message
  };
  const Case cases[] = {
      {"Name,Latitude,Longitude\nR001,43.0,141.0\n", "names no code"},
      {header + "R001,93.0,141.0,72.0,WALL1,0.01\n", ":2: column 2 (latitude) is beyond ±90°"},
      {header + "R001,43.0,191.0,72.0,WALL1,0.01\n", ":2: column 3 (longitude) is beyond ±180°"},
      {header + "R001,43°04',141.0,72.0,WALL1,0.01\n", ":2: column 2 (latitude) is not a finite"},
      {header + "R001,43.0,141.0,72.0,WALL1,0\n", ":2: column 6 (precision) is not in (0, 1] m"},
      {header + "R001,43.0,141.0,72.0,WALL1,12\n", ":2: column 6 (precision) is not in (0, 1] m"},
      {header + ",43.0,141.0,72.0,WALL1,0.01\n", ":2: column 1 (point id) is empty"},
      {header + "R001,43.0,141.0,72.0\n", ":2: 4 fields; expected 6"},
      {header, ": no survey points"},
      {"Lat,Latitude,Longitude,Name,Code\n", "column 1 and column 2 both name the latitude"},
  };
  int index = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.content);
    const std::string path = WriteFile("bad" + std::to_string(index++) + ".csv", c.content);
    const std::string message = ErrorOf(path);
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace wallcal::io
