// SPDX-License-Identifier: Apache-2.0
// The mistakes a new user makes and what the outputs promise, each at the program level: the
// real `wallcal calibrate` (and `wallcal inspect`) on a copy of the bundled sample, changed to
// make the mistake. Checked: the exit status, the message, and which files are written or not.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include <yaml-cpp/yaml.h>

#include "common/sha256.h"
#include "test/support/expect_text.h"
#include "test/support/program_runner.h"
#include "test/support/sample_session.h"
#include "test/support/scratch_files.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

using namespace testing_support;  // NOLINT: the test helpers of test/support

const fs::path& kSample = kSampleSession;
const std::string kCalibrate = testing_support::WallcalCommand("calibrate");
const std::string kInspect = testing_support::WallcalCommand("inspect");

using RunOut = testing_support::ProgramRun;

// Runs `program args` as the shell splits them.
RunOut Exec(const std::string& program, const std::string& args) {
  return testing_support::RunShell("exec " + program + " " + args);
}

// A fresh copy of the sample (without an offsets.yaml) in its own folder, in this process's
// scratch folder (removed when the process ends).
fs::path Copy(const std::string& name) {
  static const testing_support::ScratchDir scratch("wallcal_verdict_");
  const fs::path dir = scratch.path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const auto& entry : fs::directory_iterator(kSample)) {
    if (entry.path().filename() != "offsets.yaml") fs::copy(entry.path(), dir / entry.path().filename());
  }
  return dir;
}

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// One tree of transforms, z stated, a well-formed URDF.
TEST(VerdictTest, EmitsOneTreeAndSaysWhenTheHeightIsUnknown) {
  const fs::path dir = Copy("tree");
  std::ofstream(dir / "session.yaml", std::ios::app) << "antenna_in_base: {x: -0.4, y: 0.0, z: 2.1}\n";
  const RunOut tf = Exec(kCalibrate, dir.string() + " --emit ros2-static-tf --quiet");
  ASSERT_EQ(tf.exit_code, 0) << tf.err;
  testing_support::ExpectContains(tf.out, {
      "--frame-id base_link --child-frame-id gnss_antenna",
      "--frame-id gnss_antenna --child-frame-id laser"
  });
  EXPECT_FALSE(Has(tf.out, "--frame-id base_link --child-frame-id laser")) << tf.out;
  EXPECT_TRUE(Has(tf.out, "# gnss_antenna -> laser: z = 0: the scanner's height")) << tf.out;

  const RunOut urdf = Exec(kCalibrate, dir.string() + " --emit urdf --quiet");
  ASSERT_EQ(urdf.exit_code, 0) << urdf.err;
  EXPECT_EQ(urdf.out.rfind("<?xml version=\"1.0\"?>\n", 0), 0u) << urdf.out;
  EXPECT_TRUE(Has(urdf.out, "<robot name=\"wallcal_mount\">")) << urdf.out;
  // Every link is the child of at most one joint: one tree.
  EXPECT_EQ(urdf.out.find("<child link=\"laser\"/>"), urdf.out.rfind("<child link=\"laser\"/>"));
  EXPECT_TRUE(Has(urdf.out, "<child link=\"gnss_antenna\"/>"));
  const fs::path urdf_file = dir / "mount.urdf";
  WriteFile(urdf_file, urdf.out);
  // check_urdf (liburdfdom-tools) when installed; otherwise xmllint's well-formedness check.
  if (testing_support::RunShell("command -v check_urdf").exit_code == 0) {
    const RunOut check = Exec("check_urdf", urdf_file.string());
    EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  } else if (testing_support::RunShell("command -v xmllint").exit_code == 0) {
    EXPECT_EQ(Exec("xmllint", "--noout " + urdf_file.string()).exit_code, 0);
  }

  // With the height in session.yaml it is used and the note goes away.
  ReplaceInFile(dir / "session.yaml", "  time_offset_s: 0\n", "  time_offset_s: 0\n  z_m: -0.85\n");
  const RunOut known = Exec(kCalibrate, dir.string() + " --emit ros2-static-tf --quiet");
  ASSERT_EQ(known.exit_code, 0) << known.err;
  EXPECT_TRUE(Has(known.out, "--z -0.85 ")) << known.out;
  EXPECT_FALSE(Has(known.out, "z = 0")) << known.out;
}

// The closed form writes no σ, and says so.
TEST(VerdictTest, ClosedFormWritesNoSigmaAndAWarning) {
  const fs::path dir = Copy("barawid");
  const RunOut run = Exec(kCalibrate, dir.string() + " --method barawid --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  testing_support::ExpectContains(run.out, {"no sigma", "verdict    REVIEW"});
  const YAML::Node doc = YAML::LoadFile((dir / "offsets.yaml").string());
  EXPECT_TRUE(doc["scanner_mount"]["stddev"].IsNull());
  EXPECT_TRUE(doc["scanner_mount"]["covariance"].IsNull());
  ASSERT_GE(doc["warnings"].size(), 1u);
  EXPECT_TRUE(Has(ReadFile(dir / "offsets.yaml"), "no σ: the closed form"));
}

// A preset that does not fit the data stops the run, naming both; inspect agrees.
TEST(VerdictTest, WrongPresetIsRefusedNamingBoth) {
  for (const std::string& model : {std::string("hokuyo_urg04lx"), std::string("sick_lms200")}) {
    const fs::path dir = Copy("preset_" + model);
    ReplaceInFile(dir / "session.yaml", "model: sick_lms291", "model: " + model);
    const RunOut run = Exec(kCalibrate, dir.string() + " --quiet");
    EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
    EXPECT_TRUE(Has(run.err, "scanner.model '" + model + "' does not fit")) << run.err;
    EXPECT_TRUE(Has(run.err, model == "sick_lms200" ? "maximum range 8.18 m" : "181 beams"))
        << run.err;
    EXPECT_FALSE(fs::exists(dir / "offsets.yaml"));
    const RunOut inspect = Exec(kInspect, dir.string());
    EXPECT_FALSE(Has(inspect.out, "VERDICT: enough data")) << inspect.out;
    EXPECT_TRUE(Has(inspect.out, "does not fit")) << inspect.out;
    const RunOut forced = Exec(kCalibrate, dir.string() + " --quiet --force");
    if (forced.exit_code == 0) {
      EXPECT_TRUE(Has(ReadFile(dir / "offsets.yaml"), "FORCED: scanner.model"));
    }
  }
}

// A survey that is not where the GNSS track is, and a mount far from the guess.
TEST(VerdictTest, SurveyFarFromTheTrackIsASurveyMistake) {
  const fs::path dir = Copy("far");
  ReplaceInFile(dir / "session.yaml", "lat: 43.07129002690411", "lat: 43.17129002690411");
  ReplaceInFile(dir / "session.yaml", "lat: 43.07128991302616", "lat: 43.17128991302616");
  const RunOut run = Exec(kCalibrate, dir.string() + " --quiet");
  EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
  testing_support::ExpectContains(run.err, {
      "the GNSS track passes no closer than",
      "control points"
  });
  EXPECT_FALSE(Has(run.err, "stations")) << run.err;
  EXPECT_FALSE(fs::exists(dir / "offsets.yaml"));
}

TEST(VerdictTest, MountGuessToleranceRefusesAGrossError) {
  const fs::path dir = Copy("guess");
  ReplaceInFile(dir / "session.yaml", "  time_offset_s: 0\n",
          "  time_offset_s: 0\n  mount_guess: {x: 2.0, y: 0.05, yaw_deg: 2.8, tolerance_m: 0.2}\n");
  const RunOut run = Exec(kCalibrate, dir.string() + " --quiet");
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;
  testing_support::ExpectContains(run.err, {"from scanner.mount_guess", "tolerance_m 0.200 m"});
  EXPECT_FALSE(fs::exists(dir / "offsets.yaml"));
  const RunOut forced = Exec(kCalibrate, dir.string() + " --quiet --force");
  EXPECT_EQ(forced.exit_code, 0) << forced.err;
  EXPECT_TRUE(Has(forced.out, "verdict    REJECT")) << forced.out;
}

// The refusal for σ follows the dominant term, with the counts of the final pass.
TEST(VerdictTest, SigmaRefusalFollowsTheDominantTermAndCountsTheScans) {
  const fs::path dir = Copy("sigma");
  WriteFile(dir / "strict.yaml", "solver: {max_sigma_xy_m: 0.01}\n");
  const RunOut run = Exec(kCalibrate, dir.string() + " --quiet --config " + (dir / "strict.yaml").string());
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;
  EXPECT_TRUE(Has(run.err, "of its variance comes from the")) << run.err;
  EXPECT_FALSE(Has(run.err, "turned ≥ 30°")) << run.err;
  testing_support::ExpectLacks(run.out, {" 0 used", "headings 0.0..0.0"});
  EXPECT_FALSE(fs::exists(dir / "offsets.yaml"));
}

// Frame names validated as tf2 does, and written into offsets.yaml.
TEST(VerdictTest, FrameNamesAreValidatedAndWritten) {
  const fs::path dir = Copy("frames");
  const RunOut run =
      Exec(kCalibrate, dir.string() + " --quiet --parent-frame gps --child-frame laser_front");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const YAML::Node doc = YAML::LoadFile((dir / "offsets.yaml").string());
  EXPECT_EQ(doc["scanner_mount"]["parent_frame"].as<std::string>(), "gps");
  EXPECT_EQ(doc["scanner_mount"]["child_frame"].as<std::string>(), "laser_front");
  fs::remove(dir / "offsets.yaml");
  const RunOut bad = Exec(kCalibrate, dir.string() + " --child-frame /laser");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_TRUE(Has(bad.err, "leading slash")) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "offsets.yaml"));
}

// Provenance, and no names of files a user does not have.
TEST(VerdictTest, OffsetsCarryProvenanceAndNoInternalNames) {
  const fs::path dir = Copy("provenance");
  const RunOut run = Exec(kCalibrate, dir.string() + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_FALSE(Has(run.out, "seed")) << run.out;
  const std::string text = ReadFile(dir / "offsets.yaml");
  EXPECT_FALSE(Has(text, "seed_002")) << text;
  const YAML::Node doc = YAML::Load(text);
  EXPECT_NEAR(doc["barawid_2007_notation"]["b"].as<double>(), doc["scanner_mount"]["x"].as<double>(), 1e-6);
  const YAML::Node source = doc["source"];
  EXPECT_TRUE(std::regex_match(source["created_utc"].as<std::string>(),
                               std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)")));
  EXPECT_FALSE(source["tool_version"].as<std::string>().empty());
  ASSERT_GE(source["command_line"].size(), 3u);
  EXPECT_EQ(source["command_line"][0].as<std::string>(), "wallcal");
  EXPECT_EQ(source["command_line"][1].as<std::string>(), "calibrate");
  EXPECT_EQ(source["command_line"][2].as<std::string>(), dir.string());
  int hashed = 0;
  for (const YAML::Node& input : source["inputs"]) {
    const std::string path = input["path"].as<std::string>();
    EXPECT_EQ(input["sha256"].as<std::string>(), Sha256OfFile(path)) << path;
    hashed += fs::path(path).filename() == "scans.clf" ? 1 : 0;
  }
  EXPECT_EQ(hashed, 1);
  for (const auto& entry : fs::directory_iterator(fs::path(WALLCAL_SOURCE_DIR) / "docs")) {
    if (entry.path().extension() != ".md") continue;
    const std::string doc_text = ReadFile(entry.path());
    for (const char* internal : {"docs/session-format.md", "../shared", "seed 00", "seed_002"}) {
      EXPECT_FALSE(Has(doc_text, internal)) << entry.path() << ": " << internal;
    }
    // Docs state what is: the project's history (its issue and round numbers) is in CHANGELOG.md.
    static const std::regex history("[Ii]ssue [0-9]+|[Rr]ound [0-9]+");
    EXPECT_FALSE(std::regex_search(doc_text, history)) << entry.path();
  }
}

// The verdict, the change since a previous calibration, the report's top.
TEST(VerdictTest, VerdictCompareAndReportTop) {
  const fs::path dir = Copy("compare");
  const RunOut first = Exec(kCalibrate, dir.string() + " --quiet --output " + (dir / "previous.yaml").string());
  ASSERT_EQ(first.exit_code, 0) << first.err;
  testing_support::ExpectContains(first.out, {"  verdict    ", "σ budget"});
  // The same data again: no change.
  const RunOut same = Exec(kCalibrate, dir.string() + " --quiet --compare " + (dir / "previous.yaml").string());
  ASSERT_EQ(same.exit_code, 0) << same.err;
  testing_support::ExpectContains(same.out, {"change     since", "x +0.0 mm, y +0.0 mm"});
  EXPECT_TRUE(Has(ReadFile(dir / "offsets.yaml"), "change_since_previous: {previous:"));
  // A previous calibration 50 mm further forward: REVIEW, naming the move.
  ReplaceInFile(dir / "previous.yaml", "  x: 2.", "  x: 2.05");  // crude: +0.05 m on x's first decimal
  WriteFile(dir / "lenient.yaml", "acceptance: {max_sigma_xy_m: 0.05, max_sigma_yaw_deg: 1.0}\n");
  const RunOut moved = Exec(kCalibrate, dir.string() + " --quiet --config " + (dir / "lenient.yaml").string() +
                                         " --compare " + (dir / "previous.yaml").string() +
                                         " --report " + (dir / "report").string());
  ASSERT_EQ(moved.exit_code, 0) << moved.err;
  testing_support::ExpectContains(moved.out, {
      "verdict    REVIEW",
      "since " + (dir / "previous.yaml").string()
  });
  const std::string html = ReadFile(dir / "report" / "report.html");
  const size_t verdict = html.find("class=\"verdict v-review\"");
  const size_t budget = html.find("Error budget");
  const size_t folded = html.find("<details id=\"diagnostics\">");
  const size_t hough = html.find("<section id=\"hough\">");
  ASSERT_NE(verdict, std::string::npos);
  ASSERT_NE(budget, std::string::npos);
  ASSERT_NE(folded, std::string::npos);
  EXPECT_LT(verdict, budget);
  EXPECT_LT(budget, folded);
  if (hough != std::string::npos) {
    EXPECT_GT(hough, folded);
  }
  testing_support::ExpectContains(html, {
      "error (estimate &#8722; truth)",
      "change since previous"
  });

  // Bootstrap off: no "bootstrap (0)".
  WriteFile(dir / "noboot.yaml", "solver: {bootstrap_samples: 0}\n");
  const RunOut noboot = Exec(kCalibrate, dir.string() + " --quiet --config " + (dir / "noboot.yaml").string());
  ASSERT_EQ(noboot.exit_code, 0) << noboot.err;
  EXPECT_FALSE(Has(noboot.out, "bootstrap (0)")) << noboot.out;
}

}  // namespace
}  // namespace wallcal

namespace wallcal {
namespace {

// Two control points: a mirrored survey cannot be told from the tie; the refusal
// then points at the survey, not at the stations.
TEST(VerdictTest, MirroredSurveyWithTwoControlPointsPointsAtTheSurvey) {
  const fs::path dir = Copy("mirrored");
  std::istringstream in(ReadFile(dir / "survey.csv"));
  std::string line, out;
  std::getline(in, line);
  out = line + "\n";
  while (std::getline(in, line)) {
    // id,x,y,z,code -> id,y,x,z,code
    const size_t a = line.find(','), b = line.find(',', a + 1), c = line.find(',', b + 1);
    out += line.substr(0, a + 1) + line.substr(b + 1, c - b - 1) + "," +
           line.substr(a + 1, b - a - 1) + line.substr(c) + "\n";
  }
  WriteFile(dir / "survey.csv", out);
  const RunOut run = Exec(kCalibrate, dir.string() + " --quiet");
  EXPECT_NE(run.exit_code, 0) << run.out;
  testing_support::ExpectContains(run.err, {"survey", "swapped"});
  EXPECT_FALSE(Has(run.err, "turned ≥ 30°")) << run.err;
  EXPECT_FALSE(fs::exists(dir / "offsets.yaml"));
}

}  // namespace
}  // namespace wallcal
