#include "io/survey_reader.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;

std::string WriteFile(const std::string& name, const std::string& content) {
  const fs::path dir = fs::path(::testing::TempDir()) / "survey_reader_test";
  fs::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

TEST(SurveyReaderTest, ReadsTheSessionExample) {
  const std::vector<SurveyPoint> points = ReadSurvey(WriteFile(
      "example.csv", "id,x,y,z,code\nC1,0.000,0.000,0.000,CTRL\nW001,1.002,10.013,0.512,WALL1\n"));
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].id, "C1");
  EXPECT_EQ(points[0].code, "CTRL");
  EXPECT_EQ(points[1].id, "W001");
  EXPECT_EQ(points[1].code, "WALL1");
  EXPECT_DOUBLE_EQ(points[1].x_m, 1.002);
  EXPECT_DOUBLE_EQ(points[1].y_m, 10.013);
  EXPECT_DOUBLE_EQ(points[1].z_m, 0.512);
  EXPECT_EQ(points[1].line, 3);
}

TEST(SurveyReaderTest, AcceptsOtherHeadersAnyOrderCommentsAndCrlf) {
  const std::string variants[] = {
      "# exported by the total station\r\n\r\nCode , N , E , Z , "
      "ID\r\nWALL1,10.013,1.002,0.512,W001\r\n",
      "\xEF\xBB\xBF"
      "Point,Easting,Northing,Elevation,Id,Code,Remark\nP,1.002,10.013,0.512,W001,WALL1,ok\n",
      " ID , Code , X , Y , Z , Date\nW001,WALL1,1.002,10.013,+0.512,2024-05-12\n",
      "\"id\",\"code\",\"x\",\"y\",\"z\"\n\"W001\",\"WALL1\",1.002,10.013,0.512\n",
  };
  int index = 0;
  for (const std::string& content : variants) {
    SCOPED_TRACE(content);
    const std::vector<SurveyPoint> points =
        ReadSurvey(WriteFile("variant" + std::to_string(index++) + ".csv", content));
    ASSERT_EQ(points.size(), 1u);
    EXPECT_EQ(points[0].id, "W001");
    EXPECT_EQ(points[0].code, "WALL1");
    EXPECT_DOUBLE_EQ(points[0].x_m, 1.002);
    EXPECT_DOUBLE_EQ(points[0].y_m, 10.013);
    EXPECT_DOUBLE_EQ(points[0].z_m, 0.512);
  }
}

// The file's error message must name the file, the line when there is one, and the problem.
void ExpectError(const std::string& name, const std::string& content, const std::string& where,
                 const std::string& text) {
  SCOPED_TRACE(name);
  const std::string path = WriteFile(name + ".csv", content);
  try {
    ReadSurvey(path);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + where, 0), 0u) << message;
    EXPECT_NE(message.find(text), std::string::npos) << message;
  }
}

TEST(SurveyReaderTest, RejectsBadFilesWithFileAndLine) {
  ExpectError("no_header", "# only a comment\n\n", ": ", "no header");
  ExpectError("missing_column", "id,x,y,code\nW1,1,2,WALL1\n",
              ":1: ", "header has the columns id, x, y, code; expected id, code and x,y,z");
  ExpectError("no_code", "id,x,y,z\nW1,1,2,3\n", ":1: ", "expected id, code");
  ExpectError("ambiguous", "id,x,e,y,z,code\nW1,1,1,2,3,W\n", ":1: ", "both give");
  ExpectError("field_count", "id,x,y,z,code\nW1,1,2,3,WALL1\nW2,1,2,WALL1\n",
              ":3: ", "4 fields; expected 5");
  ExpectError("non_numeric", "id,x,y,z,code\nW1,1,2,3,WALL1\n\nW2,1,abc,3,WALL1\n",
              ":4: ", "column 'y' is 'abc'");
  ExpectError("non_finite", "id,x,y,z,code\nW1,1,2,inf,WALL1\n", ":2: ", "finite number");
  ExpectError("nan", "id,x,y,z,code\nW1,nan,2,3,WALL1\n", ":2: ", "finite number");
  ExpectError("empty_coordinate", "id,x,y,z,code\nW1,,2,3,WALL1\n", ":2: ", "column 'x' is ''");
  ExpectError("duplicate", "id,x,y,z,code\nW1,1,2,3,WALL1\nW1,1,2,3,WALL1\n",
              ":3: ", "duplicate id 'W1'");
  ExpectError("empty_id", "id,x,y,z,code\n ,1,2,3,WALL1\n", ":2: ", "empty id");
  ExpectError("no_points", "id,x,y,z,code\n# nothing\n", ": ", "no survey points");
}

TEST(SurveyReaderTest, MissingFileNamesThePath) {
  const std::string path = ::testing::TempDir() + "/survey_reader_test_missing.csv";
  try {
    ReadSurvey(path);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace wallcal::io
