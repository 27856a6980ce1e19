// SPDX-License-Identifier: Apache-2.0
#include "io/config/session_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/writers/writers.h"
#include "common/angles.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;
using testing_support::ScratchFolder;

using testing_support::WriteFile;

// The session of docs/session-format.md, as printed there.
const char kExample[] = R"(name: sapporo-north-wall          # free text
utm_zone: 54N                     # optional
scanner:
  model: sick_lms291              # a preset in configs/scanners/
  log: scans.clf                  # CARMEN log, see below
  time_offset_s: 0.0              # optional, added to every scan time
gnss:
  log: gnss.nmea                  # NMEA 0183 GGA (GST optional), logger-time prefixed
  min_fix_quality: 4              # optional
heading:
  log: heading.nmea               # NMEA 0183 HDT or THS, logger-time prefixed
  reference: true_north           # or grid_north
survey:
  points: survey.csv              # total-station export in its local frame, see below
  control:                        # survey points whose position RTK-GNSS also measured (WGS84)
    - {id: C1, lat: 43.0712345, lon: 141.3398765, h: 72.31}
    - {id: C2, lat: 43.0713012, lon: 141.3401123, h: 72.29}
  # With one control point only, give the rotation of Eq. 4-5 of Barawid 2007 instead:
  # rotation_deg: 12.5            # counter-clockwise from the local x axis to grid east
walls:
  - id: north_wall
    code: WALL1                   # the survey points whose code is WALL1 lie on this wall
)";

TEST(SessionReaderTest, ReadsTheSessionExample) {
  const std::string dir = ScratchFolder("example");
  WriteFile(dir + "/session.yaml", kExample);
  const SessionSpec spec = ReadSession(dir);  // the folder holding session.yaml
  EXPECT_EQ(spec.file, (fs::path(dir) / "session.yaml").lexically_normal().string());
  EXPECT_EQ(spec.name, "sapporo-north-wall");
  ASSERT_TRUE(spec.utm_zone.has_value());
  EXPECT_EQ(spec.utm_zone->zone, 54);
  EXPECT_TRUE(spec.utm_zone->north);
  EXPECT_EQ(spec.scanner_model, "sick_lms291");
  EXPECT_EQ(spec.scanner_log, (fs::path(dir) / "scans.clf").string());
  EXPECT_EQ(spec.gnss_log, (fs::path(dir) / "gnss.nmea").string());
  EXPECT_EQ(spec.heading_log, (fs::path(dir) / "heading.nmea").string());
  EXPECT_EQ(spec.survey_points, (fs::path(dir) / "survey.csv").string());
  EXPECT_EQ(spec.min_fix_quality, 4);
  EXPECT_EQ(spec.heading_reference, HeadingReference::kTrueNorth);
  ASSERT_EQ(spec.control.size(), 2u);
  EXPECT_EQ(spec.control[1].id, "C2");
  EXPECT_DOUBLE_EQ(spec.control[1].lat_deg, 43.0713012);
  EXPECT_DOUBLE_EQ(spec.control[1].lon_deg, 141.3401123);
  EXPECT_DOUBLE_EQ(spec.control[1].h_m, 72.29);
  EXPECT_EQ(spec.control[1].line, 17);
  EXPECT_FALSE(spec.survey_rotation_rad.has_value());
  ASSERT_EQ(spec.walls.size(), 1u);
  EXPECT_EQ(spec.walls[0].id, "north_wall");
  EXPECT_EQ(spec.walls[0].code, "WALL1");
  EXPECT_FALSE(spec.mount_guess.has_value());
  EXPECT_FALSE(spec.antenna_in_base.has_value());
}

TEST(SessionReaderTest, ReadsExtensionKeysAndRoundTrips) {
  const std::string dir = ScratchFolder("extensions");
  fs::create_directories(dir + "/logs");
  WriteFile(dir + "/session.yaml", R"(name: "two walls: east & north"
utm_zone: 33s
scanner:
  model: hokuyo_urg04lx
  log: logs/scans.clf.gz
  time_offset_s: -0.0125
  mount_guess: {x: 2.5, y: -0.05, yaw_deg: 3.0}
gnss: {log: logs/gnss.nmea, min_fix_quality: 5}
heading: {log: /data/heading.nmea, reference: grid_north}
survey:
  points: ../survey.csv
  control: [{id: C1, lat: -33.5, lon: 151.25, h: 20.0}]
  rotation_deg: 12.5
walls:
  - {id: east, code: WALL1}
  - {id: north, code: "007"}
antenna_in_base: {x: 0.1, y: 0.2, z: 1.9}
)");
  const SessionSpec spec = ReadSession(dir + "/session.yaml");
  EXPECT_EQ(spec.name, "two walls: east & north");
  EXPECT_EQ(spec.utm_zone->zone, 33);
  EXPECT_FALSE(spec.utm_zone->north);
  EXPECT_EQ(spec.scanner_log, (fs::path(dir) / "logs/scans.clf.gz").string());
  EXPECT_EQ(spec.heading_log, "/data/heading.nmea");
  EXPECT_EQ(spec.survey_points, (fs::path(dir).parent_path() / "survey.csv").string());
  EXPECT_DOUBLE_EQ(spec.scanner_time_offset_s, -0.0125);
  ASSERT_TRUE(spec.mount_guess.has_value());
  EXPECT_DOUBLE_EQ(spec.mount_guess->x_m, 2.5);
  EXPECT_DOUBLE_EQ(spec.mount_guess->y_m, -0.05);
  EXPECT_NEAR(spec.mount_guess->yaw_rad, 3.0 * kDegToRad, 1e-15);
  EXPECT_EQ(spec.min_fix_quality, 5);
  EXPECT_EQ(spec.heading_reference, HeadingReference::kGridNorth);
  ASSERT_TRUE(spec.survey_rotation_rad.has_value());
  EXPECT_NEAR(*spec.survey_rotation_rad, 12.5 * kDegToRad, 1e-15);
  EXPECT_EQ(spec.walls[1].code, "007");
  ASSERT_TRUE(spec.antenna_in_base.has_value());
  EXPECT_DOUBLE_EQ(spec.antenna_in_base->z_m, 1.9);

  // Written back into the same folder, it reads back to the same session.
  const std::string copy_path = dir + "/copy.yaml";
  WriteFile(copy_path, FormatSessionYaml(spec));
  const SessionSpec copy = ReadSession(copy_path);
  EXPECT_EQ(copy.name, spec.name);
  EXPECT_EQ(copy.utm_zone->zone, 33);
  EXPECT_FALSE(copy.utm_zone->north);
  EXPECT_EQ(copy.scanner_log, spec.scanner_log);
  EXPECT_EQ(copy.gnss_log, spec.gnss_log);
  EXPECT_EQ(copy.heading_log, spec.heading_log);
  EXPECT_EQ(copy.survey_points, spec.survey_points);
  EXPECT_DOUBLE_EQ(copy.scanner_time_offset_s, spec.scanner_time_offset_s);
  EXPECT_NEAR(copy.mount_guess->yaw_rad, spec.mount_guess->yaw_rad, 1e-15);
  EXPECT_EQ(copy.min_fix_quality, 5);
  EXPECT_EQ(copy.heading_reference, HeadingReference::kGridNorth);
  EXPECT_DOUBLE_EQ(copy.control[0].lat_deg, -33.5);
  EXPECT_NEAR(*copy.survey_rotation_rad, *spec.survey_rotation_rad, 1e-15);
  ASSERT_EQ(copy.walls.size(), 2u);
  EXPECT_EQ(copy.walls[1].code, "007");
  EXPECT_DOUBLE_EQ(copy.antenna_in_base->y_m, 0.2);
}

// Runs ReadSession on `yaml` and returns the error message ("" if none).
std::string SessionError(const std::string& name, const std::string& yaml) {
  const std::string dir = ScratchFolder(name);
  WriteFile(dir + "/session.yaml", yaml);
  try {
    ReadSession(dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string Without(std::string text, const std::string& line) {
  const size_t at = text.find(line);
  EXPECT_NE(at, std::string::npos) << line;
  return text.erase(at, line.size());
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(SessionReaderTest, MissingSessionFile) {
  const std::string dir = ScratchFolder("empty_folder");
  try {
    ReadSession(dir);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              dir + ": no session.yaml here; expected a session.yaml or a folder holding one");
  }
}

TEST(SessionReaderTest, NamesEachMissingRequiredKey) {
  const std::string example = kExample;
  const struct {
    std::string line;
    std::string key;
  } cases[] = {
      {"  model: sick_lms291              # a preset in configs/scanners/\n", "scanner.model"},
      {"  log: scans.clf                  # CARMEN log, see below\n", "scanner.log"},
      {"  log: gnss.nmea                  # NMEA 0183 GGA (GST optional), logger-time prefixed\n",
       "gnss.log"},
      {"  log: heading.nmea               # NMEA 0183 HDT or THS, logger-time prefixed\n",
       "heading.log"},
      {"  points: survey.csv              # total-station export in its local frame, see below\n",
       "survey.points"},
  };
  for (const auto& c : cases) {
    const std::string message = SessionError("missing", Without(example, c.line));
    EXPECT_NE(message.find(c.key + " is missing"), std::string::npos) << message;
  }
  // Whole sections and lists.
  const size_t walls_at = example.find("walls:");
  EXPECT_NE(SessionError("no_walls", example.substr(0, walls_at)).find("walls is missing"),
            std::string::npos);
  EXPECT_NE(
      SessionError("empty_walls", example.substr(0, walls_at) + "walls: []\n").find("at least one"),
      std::string::npos);
  const std::string no_control =
      Without(Without(Without(example,
                              "  control:                        # survey points whose "
                              "position RTK-GNSS also measured (WGS84)\n"),
                      "    - {id: C1, lat: 43.0712345, lon: 141.3398765, h: 72.31}\n"),
              "    - {id: C2, lat: 43.0713012, lon: 141.3401123, h: 72.29}\n");
  const char* kPointsLine =
      "  points: survey.csv              # total-station export in its local frame, see below\n";
  // No control is a rover survey's session (docs/survey-files.md, "Rover points"): it reads,
  // and the tie refuses a total-station file without control later, knowing the file.
  EXPECT_EQ(SessionError("no_control", no_control), "");
  EXPECT_NE(SessionError("empty_control", Replace(no_control, kPointsLine,
                                                  std::string(kPointsLine) + "  control: []\n"))
                .find("at least one"),
            std::string::npos);
  EXPECT_NE(SessionError("bad_point_sigma", Replace(no_control, kPointsLine,
                                                    std::string(kPointsLine) + "  point_sigma_m: 0\n"))
                .find("point_sigma_m"),
            std::string::npos);
  const std::string message = SessionError(
      "control_without_h", Replace(example, "lat: 43.0712345, lon: 141.3398765, h: 72.31",
                                   "lat: 43.0712345, lon: 141.3398765"));
  testing_support::ExpectContains(message, {"survey.control[0].h is missing", "session.yaml:16:"});
  EXPECT_NE(SessionError("wall_without_code",
                         Without(example,
                                 "    code: WALL1                   # the survey points "
                                 "whose code is WALL1 lie on this wall\n"))
                .find("walls[0].code is missing"),
            std::string::npos);
}

TEST(SessionReaderTest, RejectsUnknownKeysWithTheirLine) {
  const std::string example = kExample;
  std::string message =
      SessionError("unknown", Replace(example, "  time_offset_s: 0.0", "  time_ofset_s: 0.0"));
  EXPECT_NE(message.find("session.yaml:6: unknown key 'scanner.time_ofset_s'"), std::string::npos)
      << message;
  EXPECT_NE(message.find("time_offset_s"), std::string::npos) << message;  // lists valid keys
  message = SessionError("unknown_top", example + "extra: 1\n");
  EXPECT_NE(message.find("session.yaml:23: unknown key 'extra'"), std::string::npos) << message;
  message = SessionError("unknown_in_wall", Replace(example, "    code: WALL1", "    cod: WALL1"));
  EXPECT_NE(message.find("session.yaml:22: unknown key 'walls[0].cod'"), std::string::npos)
      << message;
}

TEST(SessionReaderTest, OneControlPointNeedsTheRotation) {
  const std::string one =
      Without(kExample, "    - {id: C2, lat: 43.0713012, lon: 141.3401123, h: 72.29}\n");
  const std::string message = SessionError("one_control", one);
  EXPECT_NE(message.find("one control point needs survey.rotation_deg (Barawid 2007 Eq. 4-5)"),
            std::string::npos)
      << message;
  EXPECT_EQ(SessionError("one_control_ok",
                         Replace(one, "  # rotation_deg: 12.5", "  rotation_deg: 12.5")),
            "");
}

TEST(SessionReaderTest, RejectsBadValues) {
  const std::string example = kExample;
  for (const std::string zone : {"61N", "0N", "54X", "N54", "54", "abc", "54NN"}) {
    const std::string message =
        SessionError("zone", Replace(example, "utm_zone: 54N", "utm_zone: " + zone));
    EXPECT_NE(message.find("session.yaml:2: utm_zone: expected a zone 1..60 and N or S"),
              std::string::npos)
        << zone << ": " << message;
  }
  std::string message =
      SessionError("quality", Replace(example, "min_fix_quality: 4", "min_fix_quality: 10"));
  EXPECT_NE(message.find("session.yaml:9: gnss.min_fix_quality"), std::string::npos) << message;
  message =
      SessionError("reference", Replace(example, "reference: true_north", "reference: magnetic"));
  EXPECT_NE(message.find("true_north or grid_north"), std::string::npos) << message;
  message = SessionError("offset", Replace(example, "time_offset_s: 0.0", "time_offset_s: soon"));
  EXPECT_NE(
      message.find("session.yaml:6: scanner.time_offset_s: expected a finite number, got 'soon'"),
      std::string::npos)
      << message;
  message = SessionError("lat", Replace(example, "lat: 43.0712345", "lat: 93.0712345"));
  EXPECT_NE(message.find("survey.control[0].lat"), std::string::npos) << message;
  message = SessionError("duplicate_wall", example + "  - {id: north_wall, code: WALL2}\n");
  EXPECT_NE(message.find("given twice"), std::string::npos) << message;
  message = SessionError("syntax", example + "scanner: [unclosed\n");
  EXPECT_NE(message.find("YAML syntax error"), std::string::npos) << message;
}

TEST(SessionReaderTest, ReadsSurveyColumnsForHeaderlessCsv) {
  const std::string example = kExample;
  const std::string dir = ScratchFolder("columns");
  EXPECT_EQ(ReadSession(WriteFile(dir + "/session.yaml", example)).survey_columns,
            SurveyColumns::kHeader);
  const std::pair<const char*, SurveyColumns> cases[] = {{"PNEZD", SurveyColumns::kPNEZD},
                                                         {"penzd", SurveyColumns::kPENZD},
                                                         {"header", SurveyColumns::kHeader}};
  for (const auto& [text, columns] : cases) {
    const std::string yaml = Replace(example, "  points: survey.csv",
                                     std::string("  points: survey.csv\n  columns: ") + text);
    EXPECT_EQ(ReadSession(WriteFile(dir + "/session.yaml", yaml)).survey_columns, columns) << text;
  }
  const std::string message = SessionError(
      "bad_columns", Replace(example, "  points: survey.csv", "  points: survey.csv\n  columns: NEZ"));
  EXPECT_NE(message.find("survey.columns: expected PNEZD, PENZD or header"), std::string::npos)
      << message;
}

// ---- Scanner presets ----

const std::vector<std::string> kPresetDirs = {WALLCAL_SOURCE_DIR "/configs/scanners"};

TEST(SessionReaderTest, LoadsTheShippedScannerPresets) {
  const ScannerPreset lms291 = LoadScannerPreset("sick_lms291", kPresetDirs);
  EXPECT_EQ(lms291.name, "sick_lms291");
  EXPECT_EQ(lms291.num_beams, 181);
  EXPECT_NEAR(lms291.start_angle_rad, -90.0 * kDegToRad, 1e-12);
  EXPECT_NEAR(lms291.angular_step_rad, 1.0 * kDegToRad, 1e-12);
  EXPECT_DOUBLE_EQ(lms291.max_range_m, 80.0);
  EXPECT_DOUBLE_EQ(lms291.range_resolution_m, 0.01);
  EXPECT_DOUBLE_EQ(lms291.range_sigma_m, 0.010);
  EXPECT_TRUE(lms291.max_range_is_no_return);
  EXPECT_DOUBLE_EQ(lms291.range_scale_sigma, 0.0005);
  EXPECT_DOUBLE_EQ(lms291.range_offset_sigma_m, 0.010);

  const ScannerPreset lms200 = LoadScannerPreset("sick_lms200", kPresetDirs);
  EXPECT_EQ(lms200.num_beams, 181);
  EXPECT_DOUBLE_EQ(lms200.range_scale_k, 1.0002);
  EXPECT_DOUBLE_EQ(lms200.range_offset_b_m, -0.0036);
  EXPECT_DOUBLE_EQ(lms200.sim_scale_n, 0.9998);
  EXPECT_DOUBLE_EQ(lms200.sim_offset_c_m, 0.0036);
  EXPECT_DOUBLE_EQ(lms200.range_sigma_m, 0.0053);

  const ScannerPreset urg = LoadScannerPreset("hokuyo_urg04lx", kPresetDirs);
  EXPECT_EQ(urg.num_beams, 682);
  EXPECT_DOUBLE_EQ(urg.error_codes_below_m, 0.020);
  EXPECT_FALSE(urg.max_range_is_no_return);
  EXPECT_NEAR(urg.angular_step_rad, 0.3515625 * kDegToRad, 1e-12);
  EXPECT_NEAR(urg.max_incidence_rad, 70.0 * kDegToRad, 1e-12);
  EXPECT_DOUBLE_EQ(urg.rate_hz, 10.0);
}

TEST(SessionReaderTest, UnknownPresetListsTheAvailableOnes) {
  try {
    LoadScannerPreset("sick_lms999", {"/nonexistent/dir", kPresetDirs[0]});
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("unknown scanner model 'sick_lms999'"), std::string::npos) << message;
    EXPECT_NE(message.find("hokuyo_urg04lx, sick_lms200, sick_lms291"), std::string::npos)
        << message;
  }
  EXPECT_THROW(LoadScannerPreset("../scanners/sick_lms291", kPresetDirs), InputError);
}

TEST(SessionReaderTest, FirstSearchDirWins) {
  const std::string dir = ScratchFolder("presets");
  WriteFile(dir + "/sick_lms291.yaml",
            "num_beams: 361\nstart_angle_deg: -90\nangular_step_deg: 0.5\nmax_range_m: 30\n");
  const ScannerPreset preset = LoadScannerPreset("sick_lms291", {dir, kPresetDirs[0]});
  EXPECT_EQ(preset.num_beams, 361);
  EXPECT_EQ(preset.name, "sick_lms291");  // from the file name
  WriteFile(dir + "/bad.yaml",
            "num_beams: 361\nstart_angle_deg: -90\nangular_step_deg: 0.5\nmax_range_m: 30\n"
            "range_correction: {k: 1.0, b: 0.0}\n");
  EXPECT_THROW(ReadScannerPreset(dir + "/bad.yaml"), InputError);  // b_m, not b

  // A unit's range model σ: absent, the model is taken as exact; out of range, refused by key.
  EXPECT_DOUBLE_EQ(preset.range_scale_sigma, 0.0);
  EXPECT_DOUBLE_EQ(preset.range_offset_sigma_m, 0.0);
  const std::string geometry =
      "num_beams: 361\nstart_angle_deg: -90\nangular_step_deg: 0.5\nmax_range_m: 30\n";
  WriteFile(dir + "/unit.yaml", geometry + "range_model_sigma: {k: 0.0002, b_m: 0.003}\n");
  const ScannerPreset unit = ReadScannerPreset(dir + "/unit.yaml");
  EXPECT_DOUBLE_EQ(unit.range_scale_sigma, 0.0002);
  EXPECT_DOUBLE_EQ(unit.range_offset_sigma_m, 0.003);
  for (const char* bad : {"range_model_sigma: {k: -0.001, b_m: 0.003}\n",
                          "range_model_sigma: {k: 0.001, b_m: 2.0}\n",
                          "range_model_sigma: {k: 0.001, b: 0.003}\n"}) {
    WriteFile(dir + "/bad_unit.yaml", geometry + bad);
    try {
      ReadScannerPreset(dir + "/bad_unit.yaml");
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("range_model_sigma"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace wallcal::io
