// SPDX-License-Identifier: Apache-2.0
// The first hour in the field, at the program level: `calibrate` and `inspect` run as
// subprocesses (each under `timeout 120`) on a copy of samples/lms291-sapporo changed the way a
// new user's session goes wrong or an ordinary surveyor's export differs. Checked: the exit
// status, the message (file, line, what to do), which files are written or left alone, and that
// ordinary export variants calibrate to the same mount as the plain CSV.

#include <gtest/gtest.h>

#include "test/support/expect_text.h"
#include "test/support/program_runner.h"
#include "test/support/sample_session.h"
#include "test/support/scratch_files.h"
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "common/sha256.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

using namespace testing_support;  // NOLINT: the test helpers of test/support

const fs::path& kSample = kSampleSession;
const fs::path kShippedPresets = fs::path(WALLCAL_SOURCE_DIR) / "configs" / "scanners";
const fs::path kRealData = fs::path(WALLCAL_SOURCE_DIR) / ".." / "shared" / "testdata" / "real";

std::string Quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// Every line end of `text` ("\n") as `eol`.
std::string WithLineEnds(const std::string& text, const std::string& eol) {
  std::string out;
  for (char c : text) out += c == '\n' ? eol : std::string(1, c);
  return out;
}

struct Outcome {
  int status = -1;  // exit code; -1 when it did not exit (killed at the time limit)
  std::string out, err;
  std::string all() const { return out + err; }
};

class FieldTest : public testing_support::SampleSessionTest {
 protected:

  // Runs `wallcal subcommand args` (args already shell-quoted) in the session folder, with
  // `env` ("NAME=value ...") in front, through the shared runner.
  Outcome Run(const std::string& subcommand, const std::string& args, const std::string& env = "") {
    testing_support::RunOptions options;
    options.cwd = session_.string();
    options.timeout_s = 120;
    const testing_support::ProgramRun run = testing_support::RunShell(
        env + " " + Quote(testing_support::WallcalPath()) + " " + subcommand + " " + args, options);
    Outcome outcome;
    outcome.status = run.exited() ? run.exit_code : -1;
    outcome.out = run.out;
    outcome.err = run.err;
    return outcome;
  }
  Outcome Calibrate(const std::string& args, const std::string& env = "") {
    return Run("calibrate", args, env);
  }
  Outcome Inspect(const std::string& args, const std::string& env = "") {
    return Run("inspect", args, env);
  }

  // The mount (x, y, yaw) and the whole document of an offsets.yaml.
  static YAML::Node Offsets(const fs::path& path) { return YAML::LoadFile(path.string()); }

};

// ---- outputs never replace an input -------------------------------------------------------

TEST_F(FieldTest, OutputNamingThePresetInTheSessionIsRefused) {
  fs::create_directories(session_ / "scanners");
  fs::copy_file(kShippedPresets / "sick_lms291.yaml", session_ / "scanners" / "sick_lms291.yaml");
  const std::string before = ReadFile(session_ / "scanners" / "sick_lms291.yaml");
  const Outcome run = Calibrate(". --output scanners/sick_lms291.yaml");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"names an input"});
  EXPECT_EQ(ReadFile(session_ / "scanners" / "sick_lms291.yaml"), before);
}

TEST_F(FieldTest, OutputNamingTheShippedPresetIsRefused) {
  // The shipped folder, copied (WALLCAL_CONFIG_DIR is searched first): a failure here must not
  // overwrite the build's own share/wallcal.
  const fs::path shipped = root_ / "share" / "wallcal";
  fs::create_directories(shipped);
  fs::copy(kShippedPresets, shipped / "scanners", fs::copy_options::recursive);
  const fs::path preset = shipped / "scanners" / "sick_lms291.yaml";
  const std::string before = ReadFile(preset);
  const Outcome run = Calibrate(". --output " + Quote(preset.string()),
                                "WALLCAL_CONFIG_DIR=" + Quote(shipped.string()));
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"names an input"});
  EXPECT_EQ(ReadFile(preset), before);
}

TEST_F(FieldTest, OutputNamingTheComparedOffsetsIsRefusedAndEveryInputIsDigested) {
  fs::create_directories(session_ / "scanners");
  fs::copy_file(kShippedPresets / "sick_lms291.yaml", session_ / "scanners" / "sick_lms291.yaml");
  const Outcome first = Calibrate(". --output previous.yaml");
  ASSERT_EQ(first.status, 0) << first.all();
  const std::string previous = ReadFile(session_ / "previous.yaml");
  const Outcome same = Calibrate(". --compare previous.yaml --output previous.yaml");
  testing_support::ExpectExitSaying(same.status, 2, same.err, {"names an input"});
  EXPECT_EQ(ReadFile(session_ / "previous.yaml"), previous);

  const Outcome second = Calibrate(". --compare previous.yaml --output offsets.yaml");
  ASSERT_EQ(second.status, 0) << second.all();
  const YAML::Node inputs = Offsets(session_ / "offsets.yaml")["source"]["inputs"];
  ASSERT_TRUE(inputs.IsSequence());
  std::string roles;
  for (const YAML::Node& input : inputs) {
    const std::string role = input["role"].as<std::string>();
    roles += role + " ";
    const fs::path path = fs::path(input["path"].as<std::string>());
    const fs::path full = path.is_absolute() ? path : session_ / path;
    EXPECT_EQ(input["sha256"].as<std::string>(), Sha256OfFile(full.string())) << role;
    if (role == "scanner_preset") {
      // The preset actually read: the one in the session's scanners/ folder.
      EXPECT_TRUE(fs::equivalent(full, session_ / "scanners" / "sick_lms291.yaml")) << path;
    }
  }
  for (const char* role : {"session", "scanner_log", "gnss_log", "heading_log", "survey",
                           "scanner_preset", "previous_offsets"}) {
    EXPECT_NE(roles.find(std::string(role) + " "), std::string::npos) << role << " in " << roles;
  }
}

// ---- one preset resolution ----------------------------------------------------------------

TEST_F(FieldTest, InspectFindsAMeasuredPresetInTheSessionAsCalibrateDoes) {
  fs::create_directories(session_ / "scanners");
  fs::copy_file(kShippedPresets / "sick_lms291.yaml",
                session_ / "scanners" / "sick_lms291_measured.yaml");
  ReplaceInFile(session_ / "session.yaml", "model: sick_lms291", "model: sick_lms291_measured");
  const Outcome calibrate = Calibrate(". --output offsets.yaml");
  ASSERT_EQ(calibrate.status, 0) << calibrate.all();
  const Outcome inspect = Inspect(".");
  EXPECT_EQ(inspect.status, 0) << inspect.all();
  testing_support::ExpectLacks(inspect.all(), {"unknown scanner model", "NOT enough data"});
  const Outcome dump = Inspect(". --dump scans");
  EXPECT_EQ(dump.status, 0) << dump.err;
  // The provenance names the measured file.
  const YAML::Node inputs = Offsets(session_ / "offsets.yaml")["source"]["inputs"];
  bool found = false;
  for (const YAML::Node& input : inputs) {
    if (input["role"].as<std::string>() != "scanner_preset") continue;
    found = true;
    EXPECT_NE(input["path"].as<std::string>().find("scanners/sick_lms291_measured.yaml"),
              std::string::npos);
    EXPECT_EQ(input["sha256"].as<std::string>(),
              Sha256OfFile((session_ / "scanners" / "sick_lms291_measured.yaml").string()));
  }
  EXPECT_TRUE(found);
}

// ---- survey mistakes named ----------------------------------------------------------------

// The survey's x and y columns swapped (a PNEZD file read as PENZD): two control points fit
// it by a rotation as well as the right one, the scans tell.
TEST_F(FieldTest, MirroredSurveyIsNamedByCalibrateAndInspect) {
  ReplaceInFile(session_ / "survey.csv", "id,x,y,z,code", "id,y,x,z,code");
  const Outcome calibrate = Calibrate(". --output offsets.yaml");
  testing_support::ExpectExitSaying(calibrate.status, 2, calibrate.err, {
      "mirrored survey", "session.yaml:15"
  });
  EXPECT_FALSE(fs::exists(session_ / "offsets.yaml"));
  const Outcome inspect = Inspect(".");
  EXPECT_EQ(inspect.status, 0) << inspect.all();
  const std::string verdict = inspect.out.substr(inspect.out.find("\nverdict"));
  EXPECT_NE(verdict.find("mirrored survey"), std::string::npos) << verdict;
  testing_support::ExpectLacks(verdict, {"stop at more places", "too few stations"});
}

// C1's latitude typed 0.09° (10 km) off: with two control points either may be the wrong one.
TEST_F(FieldTest, ControlPointTenKilometresOffNamesBothOfTwo) {
  ReplaceInFile(session_ / "session.yaml", "lat: 43.07129002690411", "lat: 43.16129002690411");
  const Outcome run = Calibrate(". --output offsets.yaml");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"C1 and C2", "cannot be told"});
  EXPECT_EQ(run.err.find("worst: C2"), std::string::npos) << run.err;
}

// `inspect --suggest-session` leaves lat: 0.0, lon: 0.0 for the control points.
TEST_F(FieldTest, PlaceholderControlPointIsNamedWithItsLine) {
  ReplaceInFile(session_ / "session.yaml", "lat: 43.07128991302616, lon: 141.34006594797694",
          "lat: 0.0, lon: 0.0");
  const Outcome run = Calibrate(". --output offsets.yaml");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {
      "session.yaml:16", "placeholder", "C2"
  });
  EXPECT_EQ(run.err.find("central meridian"), std::string::npos) << run.err;
  const Outcome inspect = Inspect(".");
  testing_support::ExpectExitSaying(inspect.status, 2, inspect.err, {"placeholder"});
}

// ---- the scanner's geometry from the data -------------------------------------------------

// Every RAWLASER1 line of `text` with its last beam dropped (the field one step narrower), as a
// driver that reports one beam fewer writes it.
std::string DropLastBeam(const std::string& text) {
  std::istringstream in(text);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("RAWLASER1 ", 0) != 0) {
      out += line + "\n";
      continue;
    }
    std::vector<std::string> words;
    std::istringstream fields(line);
    for (std::string w; fields >> w;) words.push_back(w);
    // RAWLASER1 type start fov step max accuracy remission n r_1..r_n ...
    const int n = std::stoi(words[8]);
    words[3] = std::to_string(std::stod(words[3]) - std::stod(words[4]));
    words[8] = std::to_string(n - 1);
    words.erase(words.begin() + 8 + n);
    for (size_t i = 0; i < words.size(); ++i) out += (i ? " " : "") + words[i];
    out += "\n";
  }
  return out;
}

TEST_F(FieldTest, DriverGeometryWithinTheFamilyIsTakenFromTheData) {
  WriteFile(session_ / "scans.clf", DropLastBeam(ReadFile(session_ / "scans.clf")));
  const Outcome run = Calibrate(". --output offsets.yaml");
  testing_support::ExpectExitSaying(run.status, 0, run.out, {
      "from the data: 180 beams (preset 181)"
  });
}

TEST_F(FieldTest, AnotherScannerIsStillRefused) {
  // 181 beams 1° apart (a SICK LMS) against the URG-04LX's 682 beams 0.35° apart.
  ReplaceInFile(session_ / "session.yaml", "model: sick_lms291", "model: hokuyo_urg04lx");
  const Outcome run = Calibrate(". --output offsets.yaml");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"another scanner", "181 beams"});
}

const fs::path kUrgBag = kRealData / "ros1" / "scan_tools-demo.bag";

TEST_F(FieldTest, RealUrgRecordingSuggestsAndFitsTheUrgPreset) {
  if (!fs::exists(kUrgBag)) GTEST_SKIP() << "no real data at " << kUrgBag;
  const Outcome suggest = Inspect(Quote(kUrgBag.string()) + " --suggest-session");
  ASSERT_EQ(suggest.status, 0) << suggest.all();
  testing_support::ExpectContains(suggest.out, {"model: hokuyo_urg04lx", "681 beams (preset 682)"});

  // The bag as the scan log of a session (its GNSS and heading from the sample): the preset
  // is accepted; the run then stops at the logs' times (2010 against the sample's).
  ReplaceInFile(session_ / "session.yaml", "model: sick_lms291\n  log: scans.clf",
          "model: hokuyo_urg04lx\n  log: " + kUrgBag.string() + "\n  topic: /scan");
  const Outcome urg = Calibrate(". --output offsets.yaml");
  EXPECT_EQ(urg.status, 2) << urg.all();
  EXPECT_EQ(urg.err.find("682"), std::string::npos) << urg.err;
  EXPECT_NE(urg.err.find("do not overlap"), std::string::npos) << urg.err;

  ReplaceInFile(session_ / "session.yaml", "model: hokuyo_urg04lx", "model: sick_lms291");
  const Outcome lms = Calibrate(". --output offsets.yaml");
  testing_support::ExpectExitSaying(lms.status, 2, lms.err, {"another scanner"});
}

// ---- survey files: inspect, line ends, exports --------------------------------------------

// A small GSI-8 job: three points with coordinates (words 81, 82, 83) and a code (word 71).
std::string SmallGsi() {
  return "110001+0000C001 71....+0000CTRL 81..00+00100000 82..00+00200000 83..00+00001000 \n"
         "110002+0000W001 71....+000WALL1 81..00+00110000 82..00+00205000 83..00+00001500 \n"
         "110003+0000W002 71....+000WALL1 81..00+00120000 82..00+00205000 83..00+00002500 \n";
}

TEST_F(FieldTest, InspectSummarisesASurveyFile) {
  const Outcome csv = Inspect("survey.csv");
  testing_support::ExpectExitSaying(csv.status, 0, csv.out, {
      "CSV, comma-separated",
      "64 observations",
      "CTRL: 2;",
      "WALL1: 62;",
      "x (east)"
  });

  WriteFile(session_ / "job.gsi", SmallGsi());
  const Outcome gsi = Inspect("job.gsi");
  testing_support::ExpectExitSaying(gsi.status, 0, gsi.out, {
      "Leica GSI", "3 observations", "WALL1: 2;"
  });

  const fs::path real = kRealData / "gsi" / "leica_gsi8_ertola.gsi";
  if (fs::exists(real)) {
    const Outcome job = Inspect(Quote(real.string()));
    testing_support::ExpectExitSaying(job.status, 0, job.out, {"Leica GSI"});
  }
}

// The mount of an offsets.yaml.
struct Mount {
  double x_m = 0, y_m = 0, yaw_deg = 0;
};
Mount MountOf(const fs::path& offsets) {
  const YAML::Node doc = YAML::LoadFile(offsets.string());
  const YAML::Node t = doc["scanner_mount"];
  Mount m;
  m.x_m = t["x"].as<double>();
  m.y_m = t["y"].as<double>();
  m.yaw_deg = t["yaw_deg"].as<double>();
  return m;
}

// Expects the offsets.yaml a run wrote to hold `reference`'s mount: the same bytes of data give
// the same numbers, to round-off.
void ExpectMountOf(const fs::path& offsets, const Mount& reference) {
  const Mount mount = MountOf(offsets);
  EXPECT_NEAR(mount.x_m, reference.x_m, 1e-9);
  EXPECT_NEAR(mount.y_m, reference.y_m, 1e-9);
  EXPECT_NEAR(mount.yaw_deg, reference.yaw_deg, 1e-9);
}

TEST_F(FieldTest, EveryLineEndReadsToTheSameMount) {
  const Outcome plain = Calibrate(". --output plain.yaml");
  ASSERT_EQ(plain.status, 0) << plain.all();
  const Mount reference = MountOf(session_ / "plain.yaml");
  const std::string gsi = SmallGsi();
  for (const std::string eol : {"\r\n", "\r"}) {
    SCOPED_TRACE(eol == "\r" ? "CR" : "CRLF");
    for (const char* name : {"scans.clf", "gnss.nmea", "heading.nmea", "survey.csv"}) {
      WriteFile(session_ / name, WithLineEnds(ReadFile(kSample / name), eol));
    }
    const Outcome run = Calibrate(". --output offsets.yaml");
    ASSERT_EQ(run.status, 0) << run.all();
    ExpectMountOf(session_ / "offsets.yaml", reference);
    WriteFile(session_ / "job.gsi", WithLineEnds(gsi, eol));
    const Outcome job = Inspect("job.gsi");
    testing_support::ExpectExitSaying(job.status, 0, job.out, {"Leica GSI", "3 observations"});
  }
}

// The sample's survey.csv (id,x,y,z,code) rewritten as another export: `header` replaces the
// header row; every data row's fields are joined by `delimiter`, with a decimal comma when
// `decimal_comma`, and the codes lower-cased when `lower_codes`.
std::string Export(const std::string& plain, const std::string& header, char delimiter,
                   bool decimal_comma, bool lower_codes) {
  std::istringstream in(plain);
  std::string out, line;
  std::getline(in, line);
  out += header + "\n";
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::istringstream row(line);
    for (std::string f; std::getline(row, f, ',');) fields.push_back(f);
    for (size_t i = 1; i <= 3 && decimal_comma; ++i) {
      for (char& c : fields[i]) c = c == '.' ? ',' : c;
    }
    if (lower_codes) {
      for (char& c : fields[4]) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    for (size_t i = 0; i < fields.size(); ++i) out += (i ? std::string(1, delimiter) : "") + fields[i];
    out += "\n";
  }
  return out;
}

TEST_F(FieldTest, SurveyorExportsReadToTheSamePointsAndMount) {
  const Outcome plain = Calibrate(". --output plain.yaml");
  ASSERT_EQ(plain.status, 0) << plain.all();
  const Mount reference = MountOf(session_ / "plain.yaml");
  const Outcome plain_dump = Inspect("survey.csv --dump survey");
  ASSERT_EQ(plain_dump.status, 0) << plain_dump.all();
  const std::string csv = ReadFile(kSample / "survey.csv");
  struct Variant {
    const char* name;
    std::string text;
  };
  const Variant variants[] = {
      {"units in the header", Export(csv, "Point,Easting (m),Northing (m),Elev [m],Code", ',', false, false)},
      {"semicolons, decimal commas", Export(csv, "Point;Easting;Northing;Elevation;Code", ';', true, false)},
      {"tabs", Export(csv, "Point\tE [m]\tN [m]\tZ [m]\tDescription", '\t', false, false)},
      {"tabs, decimal commas", Export(csv, "Point\tEasting\tNorthing\tHeight\tCode", '\t', true, false)},
      {"lower-case codes", Export(csv, "id,x,y,z,code", ',', false, true)},
  };
  for (const Variant& v : variants) {
    SCOPED_TRACE(v.name);
    WriteFile(session_ / "survey.csv", v.text);
    const Outcome dump = Inspect("survey.csv --dump survey");
    ASSERT_EQ(dump.status, 0) << dump.all();
    if (std::string(v.name) != "lower-case codes") {
      EXPECT_EQ(dump.out, plain_dump.out);
    }
    const Outcome run = Calibrate(". --output offsets.yaml");
    ASSERT_EQ(run.status, 0) << run.all();
    ExpectMountOf(session_ / "offsets.yaml", reference);
  }
}

TEST_F(FieldTest, AWallCodeNotInTheSurveyListsTheCodesFound) {
  ReplaceInFile(session_ / "session.yaml", "code: WALL1", "code: WALL9");
  const Outcome run = Calibrate(". --output offsets.yaml");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"WALL9", "CTRL (2), WALL1 (62)"});
}

}  // namespace
}  // namespace wallcal
