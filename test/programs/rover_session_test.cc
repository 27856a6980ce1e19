// SPDX-License-Identifier: Apache-2.0
// A wall surveyed by an RTK rover, no total station, at the program level: `wallcal simulate`
// writes the session (configs/simulate/bench_lms291_rover.yaml: 16 points, 10 mm per horizontal
// axis, in latitude, longitude and ellipsoidal height, no survey.control), `wallcal inspect`
// summarises the survey file and `wallcal calibrate` calibrates it, each run as a user would.
// Checked: the printed mount against truth.yaml within 4 printed σ, that the points' σ (the
// session's survey.point_sigma_m or the file's column) reaches the adjustment, and the two
// refusals (control points with a rover survey, a total-station survey without them).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <yaml-cpp/yaml.h>

#include "test/support/program_runner.h"
#include "test/support/scratch_files.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

const fs::path kScenario =
    fs::path(WALLCAL_SOURCE_DIR) / "configs" / "simulate" / "bench_lms291_rover.yaml";
const fs::path kSample = fs::path(WALLCAL_SOURCE_DIR) / "samples" / "lms291-sapporo";
constexpr double kDegToRad = 0.017453292519943295;

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// The simulated rover session of `seed`, written once per test.
fs::path SimulatedRoverSession(int seed) {
  const fs::path dir = testing_support::FreshScratchDir("rover_" + std::to_string(seed));
  const testing_support::ProgramRun run = testing_support::RunWallcal(
      {"simulate", "--config", kScenario.string(), "--seed", std::to_string(seed), "--output",
       dir.string()});
  EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
  return dir;
}

// "x = 2.5633 ± 0.0131 m": the value and σ printed after `label` on the summary's mount line.
struct Printed {
  double value = NAN, sigma = NAN;
};
Printed PrintedAfter(const std::string& out, const std::string& label) {
  Printed p;
  const size_t mount = out.find("  mount ");
  if (mount == std::string::npos) return p;
  const size_t at = out.find(label, mount);
  if (at == std::string::npos) return p;
  std::istringstream in(out.substr(at + label.size()));
  std::string plus_minus;
  in >> p.value >> plus_minus >> p.sigma;
  return p;
}

TEST(RoverSessionTest, SimulatedRoverWallInspectsAndCalibratesToTheTruth) {
  const fs::path dir = SimulatedRoverSession(15);
  const std::string survey = ReadText(dir / "survey.csv");
  EXPECT_EQ(survey.substr(0, survey.find('\n')), "Name,Latitude,Longitude,Ellipsoidal height,Code");
  const YAML::Node session = YAML::LoadFile((dir / "session.yaml").string());
  EXPECT_FALSE(session["survey"]["control"]);
  EXPECT_DOUBLE_EQ(session["survey"]["point_sigma_m"].as<double>(), 0.010);

  const testing_support::ProgramRun inspect =
      testing_support::RunWallcal({"inspect", (dir / "survey.csv").string()});
  ASSERT_EQ(inspect.exit_code, 0) << inspect.out << inspect.err;
  EXPECT_NE(inspect.out.find("rover CSV (latitude, longitude, ellipsoidal height)"),
            std::string::npos)
      << inspect.out;
  EXPECT_NE(inspect.out.find("16 observations, 16 points"), std::string::npos) << inspect.out;

  const testing_support::ProgramRun calibrate =
      testing_support::RunWallcal({"calibrate", dir.string()});
  ASSERT_EQ(calibrate.exit_code, 0) << calibrate.out << calibrate.err;
  EXPECT_NE(calibrate.out.find("survey     rover points (no tie)"), std::string::npos)
      << calibrate.out;
  // The walls' place comes from the rover points alone: they carry most of yaw's variance.
  EXPECT_NE(calibrate.out.find("yaw: rover points"), std::string::npos) << calibrate.out;
  EXPECT_TRUE(fs::exists(dir / "offsets.yaml"));

  const YAML::Node truth = YAML::LoadFile((dir / "truth.yaml").string())["truth"];
  const Printed x = PrintedAfter(calibrate.out, "x = ");
  const Printed y = PrintedAfter(calibrate.out, "y = ");
  const Printed yaw = PrintedAfter(calibrate.out, "yaw = ");
  for (const Printed& p : {x, y, yaw}) ASSERT_GT(p.sigma, 0.0) << calibrate.out;
  EXPECT_LT(std::abs(x.value - truth["x"].as<double>()), 4.0 * x.sigma) << calibrate.out;
  EXPECT_LT(std::abs(y.value - truth["y"].as<double>()), 4.0 * y.sigma) << calibrate.out;
  EXPECT_LT(std::abs(yaw.value - truth["yaw_deg"].as<double>()), 4.0 * yaw.sigma)
      << calibrate.out;
}

// The rover points' σ is the walls' prior: four times the σ makes yaw's σ (92 % the rover
// points' at 10 mm) grow by more than twice; a σ column in the file gives the same as the
// session's survey.point_sigma_m, since the file's σ comes first.
TEST(RoverSessionTest, PointSigmaFromSessionOrFileEntersTheAdjustment) {
  const fs::path dir = SimulatedRoverSession(4);
  const std::string session = ReadText(dir / "session.yaml");
  const std::string survey = ReadText(dir / "survey.csv");
  const auto yaw_sigma = [&dir]() {
    const testing_support::ProgramRun run =
        testing_support::RunWallcal({"calibrate", dir.string()});
    EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
    return PrintedAfter(run.out, "yaw = ").sigma;
  };
  const double at_10mm = yaw_sigma();

  const std::string key = "point_sigma_m: 0.01";
  ASSERT_NE(session.find(key), std::string::npos) << session;
  std::string wide = session;
  wide.replace(wide.find(key), key.size(), "point_sigma_m: 0.04");
  WriteText(dir / "session.yaml", wide);
  const double at_40mm = yaw_sigma();
  EXPECT_GT(at_40mm, 2.0 * at_10mm);

  // The session says 10 mm again; each point says 40 mm in a precision column.
  WriteText(dir / "session.yaml", session);
  std::istringstream lines(survey);
  std::string line, with_sigma;
  std::getline(lines, line);
  with_sigma = line + ",H prec (m)\n";
  while (std::getline(lines, line)) {
    if (!line.empty()) with_sigma += line + ",0.040\n";
  }
  WriteText(dir / "survey.csv", with_sigma);
  EXPECT_NEAR(yaw_sigma(), at_40mm, 0.002);
}

TEST(RoverSessionTest, ControlPointsWithARoverSurveyAreRefused) {
  const fs::path dir = SimulatedRoverSession(6);
  std::string session = ReadText(dir / "session.yaml");
  const std::string key = "  point_sigma_m: 0.01\n";
  ASSERT_NE(session.find(key), std::string::npos) << session;
  session.replace(session.find(key), key.size(),
                  key +
                      "  control:\n"
                      "    - {id: R001, lat: 43.0713, lon: 141.3397, h: 72.0}\n"
                      "    - {id: R016, lat: 43.0713, lon: 141.3401, h: 72.0}\n");
  WriteText(dir / "session.yaml", session);
  const testing_support::ProgramRun run = testing_support::RunWallcal({"calibrate", dir.string()});
  EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
  EXPECT_NE(run.err.find("session.yaml:"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("survey.control given, but"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("rover points"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(dir / "offsets.yaml"));
}

TEST(RoverSessionTest, TotalStationSurveyWithoutControlIsRefused) {
  const fs::path dir = testing_support::FreshScratchDir("no_control");
  fs::copy(kSample, dir, fs::copy_options::recursive);
  std::string session = ReadText(dir / "session.yaml");
  const size_t control = session.find("  control:\n");
  const size_t walls = session.find("walls:");
  ASSERT_NE(control, std::string::npos);
  ASSERT_NE(walls, std::string::npos);
  session.erase(control, walls - control);
  WriteText(dir / "session.yaml", session);
  const testing_support::ProgramRun run = testing_support::RunWallcal({"calibrate", dir.string()});
  EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
  EXPECT_NE(run.err.find("no survey.control, but"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("or a rover survey in latitude and longitude"), std::string::npos)
      << run.err;
  EXPECT_FALSE(fs::exists(dir / "offsets.yaml"));
}

}  // namespace
}  // namespace wallcal
