// SPDX-License-Identifier: Apache-2.0
// The simulator on a 3-D site: GGA heights that follow the graded yard, the attitude stream
// against the true attitude, the survey of a leaning wall, which shipped scenarios are 3-D,
// the 3-D keys in truth.yaml and session.yaml.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <GeographicLib/LocalCartesian.hpp>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "common/angles.h"
#include "sim/simulated_session.h"
#include "sim/simulator.h"
#include "sim/site_geometry.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"
#include "test/support/shipped_presets.h"
#include "test/support/sim_fixtures.h"

namespace wallcal::sim {
namespace {
using namespace testing_fixtures;  // NOLINT: the shared fixtures
using testing_support::ExpectContains;
using testing_support::ExpectLacks;
namespace fs = std::filesystem;

// A yard rising 4 % towards N30°E, the antenna 2.5 m above it.
SimulationConfig GradedYard(SimulationConfig config) {
  config.yard_grade_pct = 4.0;
  config.yard_grade_dir_rad = 30.0 * kDegToRad;
  config.antenna_height_m = 2.5;
  return config;
}

// Each fix's antenna position in the site's ENU frame.
std::vector<Eigen::Vector3d> FixesEnu(const SimulationConfig& config,
                                      const std::vector<io::GnssFix>& fixes) {
  const GeographicLib::LocalCartesian enu(config.site_lat_deg, config.site_lon_deg,
                                          config.site_height_m);
  std::vector<Eigen::Vector3d> out;
  for (const io::GnssFix& fix : fixes) {
    Eigen::Vector3d p;
    enu.Forward(fix.lat_deg, fix.lon_deg, fix.height_m, p.x(), p.y(), p.z());
    out.push_back(p);
  }
  return out;
}

TEST(Simulator3dTest, GgaHeightsFollowTheGround) {
  const SimulationConfig config = GradedYard(NoiseFreeConfig());
  ASSERT_TRUE(config.IsThreeDSite());
  const Site site = SiteOf(config);
  const Collected run = RunSim(config, CheapPreset(), 5);
  const std::vector<Eigen::Vector3d> antennas = FixesEnu(config, run.session.fixes);
  ASSERT_GT(antennas.size(), 100u);
  double lowest_m = 1e9, highest_m = -1e9;
  for (const Eigen::Vector3d& p : antennas) {
    // The antenna's distance from the ground plane (through the site origin) is its height.
    EXPECT_NEAR(site.GroundNormalEnu().dot(p), 2.5, 1e-6);
    lowest_m = std::min(lowest_m, p.z());
    highest_m = std::max(highest_m, p.z());
  }
  EXPECT_GT(highest_m - lowest_m, 0.1);  // the stations are at different heights

  // With noise: the height recovered within the vertical noise, 2 × the horizontal (bias and
  // white); the horizontal positions are the level twin's.
  const SimulationConfig noisy = GradedYard(DefaultConfig());
  const Collected noisy_run = RunSim(noisy, CheapPreset(), 5);
  const Collected level_run = RunSim(DefaultConfig(), CheapPreset(), 5);
  ASSERT_EQ(noisy_run.session.fixes.size(), level_run.session.fixes.size());
  const double sigma_up_m = 2.0 * std::hypot(noisy.gnss_bias_sigma_m, noisy.gnss_white_sigma_m);
  double sum_m = 0.0;
  int fixed = 0;
  const std::vector<Eigen::Vector3d> noisy_enu = FixesEnu(noisy, noisy_run.session.fixes);
  const std::vector<Eigen::Vector3d> level_enu = FixesEnu(noisy, level_run.session.fixes);
  for (size_t i = 0; i < noisy_enu.size(); ++i) {
    EXPECT_NEAR(noisy_enu[i].x(), level_enu[i].x(), 1e-6);
    EXPECT_NEAR(noisy_enu[i].y(), level_enu[i].y(), 1e-6);
    if (noisy_run.session.fixes[i].quality != 4) continue;  // float: scaled-up noise
    const double h_m = site.GroundNormalEnu().dot(noisy_enu[i]);
    EXPECT_NEAR(h_m, 2.5, 6.0 * sigma_up_m);
    sum_m += h_m;
    ++fixed;
  }
  ASSERT_GT(fixed, 100);
  EXPECT_NEAR(sum_m / fixed, 2.5, 4.0 * sigma_up_m);
}

TEST(Simulator3dTest, AttitudeSamplesAreTheTruthWithinTheirNoise) {
  SimulationConfig config = GradedYard(NoiseFreeConfig());
  config.attitude_rate_hz = 10.0;
  config.attitude_white_sigma_rad = 0.1 * kDegToRad;
  config.heading_latency_s = 0.05;
  const Collected run = RunSim(config, CheapPreset(), 9);
  const std::vector<io::AttitudeSample>& samples = run.session.attitudes;
  ASSERT_GT(samples.size(), 400u);
  // Sample j is taken at j / rate and stamped as a heading is (heading_latency_s later).
  std::vector<double> t_s;
  for (size_t j = 0; j < samples.size(); ++j) {
    t_s.push_back(static_cast<double>(j) / config.attitude_rate_hz);
    EXPECT_NEAR(samples[j].stamp_s, config.start_time_s + t_s[j] + config.heading_latency_s,
                1e-6);
  }
  const std::vector<SimTruthPose> truth = TruePosesAt(config, t_s);
  const double sigma = config.attitude_white_sigma_rad;
  double sum_roll = 0.0, sum_pitch = 0.0, sq_roll = 0.0, sq_pitch = 0.0;
  double max_pitch_rad = 0.0, max_roll_rad = 0.0;
  for (size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(samples[i].roll_sigma_rad, sigma);
    EXPECT_EQ(samples[i].pitch_sigma_rad, sigma);
    const double roll_error = samples[i].roll_rad - truth[i].roll_rad;
    const double pitch_error = samples[i].pitch_rad - truth[i].pitch_rad;
    EXPECT_LT(std::abs(roll_error), 5.5 * sigma);
    EXPECT_LT(std::abs(pitch_error), 5.5 * sigma);
    sum_roll += roll_error;
    sum_pitch += pitch_error;
    sq_roll += roll_error * roll_error;
    sq_pitch += pitch_error * pitch_error;
    max_pitch_rad = std::max(max_pitch_rad, std::abs(truth[i].pitch_rad));
    max_roll_rad = std::max(max_roll_rad, std::abs(truth[i].roll_rad));
  }
  const double n = static_cast<double>(samples.size());
  EXPECT_NEAR(sum_roll / n, 0.0, 4.0 * sigma / std::sqrt(n));
  EXPECT_NEAR(sum_pitch / n, 0.0, 4.0 * sigma / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sq_roll / n), sigma, 0.15 * sigma);
  EXPECT_NEAR(std::sqrt(sq_pitch / n), sigma, 0.15 * sigma);
  // The truth itself is the ground's: up to atan(4 %) as the vehicle turns.
  EXPECT_GT(max_pitch_rad + max_roll_rad, 0.5 * std::atan(0.04));
  EXPECT_LE(max_pitch_rad, std::atan(0.04) + 1e-12);
  const Site site = SiteOf(config);
  for (const SimTruthPose& pose : truth) {
    const VehicleAttitude a = site.AttitudeAt(pose.yaw_enu_rad);
    EXPECT_EQ(pose.roll_rad, a.roll_rad);
    EXPECT_EQ(pose.pitch_rad, a.pitch_rad);
  }

  config.attitude_rate_hz = 0.0;
  EXPECT_TRUE(RunSim(config, CheapPreset(), 9).session.attitudes.empty());
}

TEST(Simulator3dTest, ALeaningWallsSurveyedPointsLieOnItsPlane) {
  SimulationConfig config = GradedYard(NoiseFreeConfig());
  config.yard_grade_dir_rad = 0.0;  // rising towards the wall
  const double lean_rad = 1.5 * kDegToRad;
  config.walls[0].lean_rad = lean_rad;
  config.walls[0].survey_heights_m = {0.3, 1.5, 2.7};
  const SimWall& wall = config.walls[0];
  const Site site = SiteOf(config);
  const Collected run = RunSim(config, CheapPreset(), 3);
  const Eigen::Vector2d p0(wall.x0_m, wall.y0_m), p1(wall.x1_m, wall.y1_m);
  const Eigen::Vector2d along = (p1 - p0).normalized();
  const Eigen::Vector2d left(-along.y(), along.x());
  const double c = std::cos(config.survey_rotation_rad), s = std::sin(config.survey_rotation_rad);
  std::multiset<double> heights_seen;
  int on_wall = 0;
  for (const io::SurveyPoint& point : run.session.survey) {
    const Eigen::Vector2d q(config.survey_origin_x_m + c * point.x_m - s * point.y_m,
                            config.survey_origin_y_m + s * point.x_m + c * point.y_m);
    if (point.code == "CTRL") {
      EXPECT_NEAR(point.z_m, site.GroundUpM(q), 1e-9);  // on the graded ground
      continue;
    }
    // Its foot on the base line, its height above it, its offset towards the wall's left.
    const Eigen::Vector2d foot = p0 + (q - p0).dot(along) * along;
    const double above_m = point.z_m - site.GroundUpM(foot);
    EXPECT_NEAR((q - foot).dot(left), std::tan(lean_rad) * above_m, 1e-9);
    heights_seen.insert(std::round(above_m * 1e6) / 1e6);
    ++on_wall;
  }
  ASSERT_EQ(on_wall % 3, 0);
  EXPECT_EQ(heights_seen.count(0.3), static_cast<size_t>(on_wall / 3));
  EXPECT_EQ(heights_seen.count(1.5), static_cast<size_t>(on_wall / 3));
  EXPECT_EQ(heights_seen.count(2.7), static_cast<size_t>(on_wall / 3));
}

TEST(Simulator3dTest, OnlyTheThreeDimensionalScenariosAreThreeDimensional) {
  const std::set<std::string> three_d = {
      "bench_lms291_yard2",   "bench_lms291_yard2_attitude", "bench_lms291_yard5",
      "bench_lms291_yard5_attitude", "bench_lms291_pitched", "bench_lms291_lean"};
  int scenarios = 0;
  for (const fs::directory_entry& entry :
       fs::directory_iterator(fs::path(WALLCAL_SOURCE_DIR) / "configs" / "simulate")) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string name = entry.path().stem().string();
    const SimulationConfig config = ReadSimulationConfig(entry.path().string());
    EXPECT_EQ(config.IsThreeDSite(), three_d.count(name) == 1) << name;
    if (three_d.count(name) == 0) {
      EXPECT_EQ(config.attitude_rate_hz, 0.0) << name;
    }
    ++scenarios;
  }
  EXPECT_GT(scenarios, 30);
  const SimulationConfig sample = ReadTruthYaml(std::string(WALLCAL_SOURCE_DIR) +
                                                "/samples/lms291-sapporo/truth.yaml");
  EXPECT_FALSE(sample.IsThreeDSite());
  EXPECT_FALSE(DefaultConfig().IsThreeDSite());
}

TEST(Simulator3dTest, TheThreeDimensionalScenariosSayWhatTheirNamesSay) {
  using testing_support::ShippedScenarioPath;
  const SimulationConfig yard2 = ReadSimulationConfig(ShippedScenarioPath("bench_lms291_yard2"));
  EXPECT_EQ(yard2.yard_grade_pct, 2.0);
  EXPECT_EQ(yard2.AntennaHeightM(), 3.0);
  EXPECT_EQ(yard2.mount_z_m, -2.5);
  EXPECT_EQ(yard2.attitude_rate_hz, 0.0);
  const SimulationConfig yard5 =
      ReadSimulationConfig(ShippedScenarioPath("bench_lms291_yard5_attitude"));
  EXPECT_EQ(yard5.yard_grade_pct, 5.0);
  EXPECT_GE(yard5.attitude_rate_hz, 10.0);
  EXPECT_LE(yard5.attitude_rate_hz, 20.0);
  EXPECT_GE(yard5.attitude_white_sigma_rad, 0.05 * kDegToRad - 1e-12);
  EXPECT_LE(yard5.attitude_white_sigma_rad, 0.1 * kDegToRad + 1e-12);
  const SimulationConfig pitched =
      ReadSimulationConfig(ShippedScenarioPath("bench_lms291_pitched"));
  EXPECT_EQ(pitched.yard_grade_pct, 0.0);
  EXPECT_NEAR(pitched.scanner_pitch_rad, -3.0 * kDegToRad, 1e-15);
  EXPECT_TRUE(pitched.write_tilt);
  EXPECT_FALSE(std::isnan(pitched.mount_z_m));
  const SimulationConfig lean = ReadSimulationConfig(ShippedScenarioPath("bench_lms291_lean"));
  EXPECT_EQ(lean.yard_grade_pct, 0.0);
  ASSERT_EQ(lean.walls.size(), 1u);
  EXPECT_NEAR(lean.walls[0].LeanRad(), 1.0 * kDegToRad, 1e-15);
  EXPECT_GE(lean.walls[0].survey_heights_m.size(), 2u);
}

TEST(Simulator3dTest, TruthYamlRoundTripsTheThreeDimensionalKeys) {
  SimulationConfig config = DefaultConfig();
  config.yard_grade_pct = 3.5;
  config.yard_grade_dir_rad = -20.0 * kDegToRad;
  config.antenna_height_m = 2.8;
  config.gnss_vertical_factor = 1.5;
  config.mount_z_m = -2.3;
  config.scanner_pitch_rad = -2.0 * kDegToRad;
  config.scanner_roll_rad = 0.5 * kDegToRad;
  config.write_z_m = false;
  config.write_tilt = true;
  config.attitude_rate_hz = 20.0;
  config.attitude_white_sigma_rad = 0.05 * kDegToRad;
  config.attitude_sentence = "avr";
  config.walls[0].lean_rad = -1.25 * kDegToRad;
  config.walls[0].survey_heights_m = {0.25, 1.5};
  SimScanner second;
  second.id = "rear";
  second.mount_x_m = -1.0;
  second.z_m = -1.8;
  second.pitch_rad = 1.0 * kDegToRad;
  config.scanners = {second};
  const std::string text = FormatTruthYaml(config, 7);
  ExpectContains(text, {"  z: -2.3", "  pitch_deg: -2", "  roll_deg: 0.5", "yard_grade_pct: 3.5",
                        "lean_deg: -1.25", "survey_heights_m: [0.25, 1.5]", "write_tilt: true",
                        "attitude_sentence: avr"});
  const SimulationConfig read =
      ReadTruthYaml(testing_support::WriteScratchFile("truth_3d.yaml", text));
  EXPECT_EQ(read.yard_grade_pct, 3.5);
  EXPECT_NEAR(read.yard_grade_dir_rad, config.yard_grade_dir_rad, 1e-15);
  EXPECT_EQ(read.antenna_height_m, 2.8);
  EXPECT_EQ(read.gnss_vertical_factor, 1.5);
  EXPECT_EQ(read.mount_z_m, -2.3);
  EXPECT_NEAR(read.scanner_pitch_rad, config.scanner_pitch_rad, 1e-15);
  EXPECT_NEAR(read.scanner_roll_rad, config.scanner_roll_rad, 1e-15);
  EXPECT_FALSE(read.write_z_m);
  EXPECT_TRUE(read.write_tilt);
  EXPECT_EQ(read.attitude_rate_hz, 20.0);
  EXPECT_NEAR(read.attitude_white_sigma_rad, config.attitude_white_sigma_rad, 1e-15);
  EXPECT_EQ(read.attitude_sentence, "avr");
  ASSERT_EQ(read.walls.size(), config.walls.size());
  EXPECT_NEAR(read.walls[0].lean_rad, config.walls[0].lean_rad, 1e-15);
  EXPECT_EQ(read.walls[0].survey_heights_m, config.walls[0].survey_heights_m);
  ASSERT_EQ(read.scanners.size(), 1u);
  EXPECT_EQ(read.scanners[0].z_m, -1.8);
  EXPECT_NEAR(read.scanners[0].pitch_rad, second.pitch_rad, 1e-15);
  EXPECT_TRUE(std::isnan(read.scanners[0].roll_rad));
  EXPECT_TRUE(read.IsThreeDSite());

  // A 2-D scenario's truth.yaml names none of them.
  ExpectLacks(FormatTruthYaml(DefaultConfig(), 7),
              {"yard_", "antenna_height_m", "gnss_vertical_factor", "mount_z_m", "pitch_deg",
               "roll_deg", "lean_deg", "survey_heights_m", "write_z_m", "write_tilt", "attitude_",
               "  z:"});
}

TEST(Simulator3dTest, SessionYamlCarriesTheScannersHeightAndTiltAsTheCrewWritesThem) {
  SimulationConfig config = GradedYard(NoiseFreeConfig());
  config.num_stations = 3;
  config.mount_z_m = -2.0;
  config.scanner_pitch_rad = -3.0 / kRadToDeg;  // as read from scanner_pitch_deg: -3
  const fs::path dir = testing_support::FreshScratchDir("session_3d");
  WriteSimulatedSession(config, 1, dir.string());
  const std::string session = testing_support::ReadFile((dir / "session.yaml").string());
  ExpectContains(session, {"  z_m: -2\n"});
  ExpectLacks(session, {"pitch_deg", "roll_deg"});  // the crew does not know the tilt

  config.write_z_m = false;
  config.write_tilt = true;
  const fs::path tilted = testing_support::FreshScratchDir("session_3d_tilt");
  WriteSimulatedSession(config, 1, tilted.string());
  const std::string with_tilt = testing_support::ReadFile((tilted / "session.yaml").string());
  ExpectContains(with_tilt, {"  pitch_deg: -3\n", "  roll_deg: 0\n"});
  ExpectLacks(with_tilt, {"z_m"});
}

}  // namespace
}  // namespace wallcal::sim
