// SPDX-License-Identifier: Apache-2.0
#include "sim/simulation_config.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "common/angles.h"
#include "io/types.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"

namespace wallcal::sim {
namespace {

namespace fs = std::filesystem;
using testing_support::ScratchFolder;
using io::InputError;

using testing_support::WriteFile;

TEST(SimulationConfigTest, SimulationConfigDefaultsAndLists) {
  const std::string dir = ScratchFolder("simulation");
  const SimulationConfig defaults = ReadSimulationConfig(WriteFile(dir + "/empty.yaml", ""));
  const SimulationConfig expected;
  EXPECT_EQ(defaults.name, expected.name);
  EXPECT_EQ(defaults.scanner_model, expected.scanner_model);
  EXPECT_DOUBLE_EQ(defaults.mount_yaw_rad, expected.mount_yaw_rad);
  EXPECT_DOUBLE_EQ(defaults.heading_drift_rad_per_s, expected.heading_drift_rad_per_s);
  EXPECT_EQ(defaults.num_stations, expected.num_stations);
  EXPECT_TRUE(defaults.walls.empty());

  const SimulationConfig config = ReadSimulationConfig(WriteFile(dir + "/site.yaml", R"(
name: yard
mount_yaw_deg: -1.5
heading_drift_deg_per_h: 0.5
heading_spread_deg: 90
write_gst: false
walls:
  - {id: north, code: WALL1, x0_m: -10, y0_m: 20, x1_m: 10, y1_m: 20}
  - {id: shed, code: "", x0_m: 15, y0_m: 0, x1_m: 15, y1_m: 8, height_m: 2.5}
obstacles:
  - {x_m: 1, y_m: 5, radius_m: 0.3}
)"));
  EXPECT_EQ(config.name, "yard");
  EXPECT_NEAR(config.mount_yaw_rad, -1.5 * kDegToRad, 1e-15);
  EXPECT_NEAR(config.heading_drift_rad_per_s, 0.5 * kDegToRad / 3600.0, 1e-18);
  EXPECT_NEAR(config.heading_spread_rad, 90 * kDegToRad, 1e-15);
  EXPECT_FALSE(config.write_gst);
  ASSERT_EQ(config.walls.size(), 2u);
  EXPECT_EQ(config.walls[0].code, "WALL1");
  EXPECT_DOUBLE_EQ(config.walls[0].y1_m, 20.0);
  EXPECT_DOUBLE_EQ(config.walls[0].height_m, SimWall().height_m);
  EXPECT_EQ(config.walls[1].code, "");
  EXPECT_DOUBLE_EQ(config.walls[1].height_m, 2.5);
  ASSERT_EQ(config.obstacles.size(), 1u);
  EXPECT_DOUBLE_EQ(config.obstacles[0].radius_m, 0.3);

  // Each file and what its message says: an unknown key, or a key's check naming the key, its
  // line and the value (list items by their index; NaN defaults are not set and pass).
  const std::pair<const char*, const char*> kBad[] = {
      {"walls:\n  - {id: a, x0: 1}\n", "bad.yaml:2: unknown key 'walls[0].x0'"},
      {"num_stations: 0\n", "bad.yaml:1: simulation.num_stations must be >= 1, got 0"},
      {"name: x\nlost_scan_fraction: 1\n",
       "bad.yaml:2: simulation.lost_scan_fraction must be in [0, 1), got 1"},
      {"walls:\n  - {id: a, x0_m: 0, y0_m: 0, x1_m: 5, y1_m: 0}\n"
       "  - {id: b, x0_m: 0, y0_m: 0, x1_m: 5, y1_m: 0, height_m: -1}\n",
       "bad.yaml:3: simulation.walls[1].height_m must be > 0, got -1"},
      {"scanner_truth: {n: 2}\n", "simulation.scanner_truth.n must be in [0.5, 1.5], got 2"},
      {"scanner_model: \"\"\n", "simulation.scanner_model must be non-empty"},
      {"scanners:\n  - {id: a}\n  - {id: a}\n",
       "bad.yaml:3: simulation.scanners[1].id must be unique, got 'a' twice"},
      {"scanner_jitter_s: -1\n",
       "bad.yaml:1: simulation.scanner_jitter_s must be in [0, 1], got -1"},
      {"scanner_jitter_s: 2\n", "simulation.scanner_jitter_s must be in [0, 1], got 2"},
      {"range_scale_error: 0.6\n",
       "bad.yaml:1: simulation.range_scale_error must be in [-0.5, 0.5], got 0.6"},
      {"range_offset_error_m: -1.5\n",
       "simulation.range_offset_error_m must be in [-1, 1], got -1.5"},
      {"scanners:\n  - {id: a, range_offset_error_m: 2}\n",
       "bad.yaml:2: simulation.scanners[0].range_offset_error_m must be in [-1, 1], got 2"},
      {"range_scale_error: 0.001\nscanners:\n  - {id: a}\n",
       "bad.yaml:1: simulation.range_scale_error must be unset with scanners: (give it on each "
       "scanner's entry), got 0.001"},
      {"draw_unit_range_models: sometimes\n", "draw_unit_range_models"},
  };
  testing_support::ExpectEachThrows<InputError>(kBad, [&dir](const char* yaml) {
    ReadSimulationConfig(WriteFile(dir + "/bad.yaml", yaml));
  });
}

TEST(SimulationConfigTest, TruthYamlRoundTrips) {
  SimulationConfig config;
  config.name = "two walls";
  config.mount_x_m = 2.5703;
  config.mount_y_m = -0.0561;
  config.mount_yaw_rad = 0.0488692190558412;
  config.heading_drift_rad_per_s = 2.42e-6;
  config.write_gst = false;
  config.walls = {{"north", "WALL1", -10, 20, 10, 20, 3.0, 0.5, kNaN, {}},
                  {"shed", "", 15, 0, 15, 8, 2.5, 1.0, kNaN, {}}};
  config.obstacles = {{1.0, 5.0, 0.3}};
  const std::string path = WriteFile(ScratchFolder("truth") + "/truth.yaml", FormatTruthYaml(config, 42));

  const YAML::Node root = YAML::LoadFile(path);
  EXPECT_EQ(root["seed"].as<uint64_t>(), 42u);
  EXPECT_DOUBLE_EQ(root["truth"]["x"].as<double>(), 2.5703);
  EXPECT_NEAR(root["truth"]["yaw_deg"].as<double>(), 2.8, 1e-9);

  const SimulationConfig read = ReadTruthYaml(path);
  EXPECT_EQ(read.name, "two walls");
  EXPECT_DOUBLE_EQ(read.mount_x_m, config.mount_x_m);
  EXPECT_DOUBLE_EQ(read.mount_y_m, config.mount_y_m);
  EXPECT_DOUBLE_EQ(read.mount_yaw_rad, config.mount_yaw_rad);
  EXPECT_NEAR(read.heading_drift_rad_per_s, config.heading_drift_rad_per_s, 1e-18);
  EXPECT_NEAR(read.heading_spread_rad, config.heading_spread_rad, 1e-15);
  EXPECT_NEAR(read.survey_rotation_rad, config.survey_rotation_rad, 1e-15);
  EXPECT_DOUBLE_EQ(read.start_time_s, config.start_time_s);
  EXPECT_EQ(read.num_stations, config.num_stations);
  EXPECT_FALSE(read.write_gst);
  ASSERT_EQ(read.walls.size(), 2u);
  EXPECT_EQ(read.walls[1].id, "shed");
  EXPECT_EQ(read.walls[1].code, "");
  EXPECT_DOUBLE_EQ(read.walls[0].survey_spacing_m, 0.5);
  EXPECT_DOUBLE_EQ(read.walls[1].y1_m, 8.0);
  ASSERT_EQ(read.obstacles.size(), 1u);
  EXPECT_DOUBLE_EQ(read.obstacles[0].radius_m, 0.3);
}

TEST(SimulationConfigTest, TruthYamlRoundTripsTheUnitsRangeModelsAndScanJitter) {
  SimulationConfig one;
  one.range_scale_error = -3.0e-4;
  one.range_offset_error_m = 0.0123456789;
  one.draw_unit_range_models = true;
  one.scanner_jitter_s = 0.0005;
  const std::string one_text = FormatTruthYaml(one, 5);
  testing_support::ExpectContains(
      one_text, {"  range_scale_error: -3.0e-04\n", "  range_offset_error_m: 0.0123456789\n",
                 "  draw_unit_range_models: true\n", "  scanner_jitter_s: 5.0e-04\n"});
  const SimulationConfig one_read =
      ReadTruthYaml(WriteFile(ScratchFolder("truth_units") + "/one.yaml", one_text));
  EXPECT_EQ(one_read.range_scale_error, one.range_scale_error);
  EXPECT_EQ(one_read.range_offset_error_m, one.range_offset_error_m);
  EXPECT_TRUE(one_read.draw_unit_range_models);
  EXPECT_EQ(one_read.scanner_jitter_s, one.scanner_jitter_s);
  EXPECT_EQ(FormatTruthYaml(one_read, 5), one_text);

  // Several scanners: each entry carries its own; an entry without them stays unset.
  SimulationConfig two;
  two.scanners.resize(3);
  two.scanners[0].id = "left";
  two.scanners[0].range_scale_error = 0.000123;
  two.scanners[0].range_offset_error_m = -0.0042;
  two.scanners[1].id = "right";
  two.scanners[1].range_offset_error_m = 0.0;
  two.scanners[2].id = "rear";
  const std::string two_text = FormatTruthYaml(two, 5);
  testing_support::ExpectContains(
      two_text, {"{id: left, mount_x_m: 0, mount_y_m: 0, mount_yaw_deg: 0, "
                 "scanner_time_offset_s: 0, scanner_latency_s: 0, range_scale_error: 0.000123, "
                 "range_offset_error_m: -0.0042}",
                 "{id: right, mount_x_m: 0, mount_y_m: 0, mount_yaw_deg: 0, "
                 "scanner_time_offset_s: 0, scanner_latency_s: 0, range_offset_error_m: 0}",
                 "{id: rear, mount_x_m: 0, mount_y_m: 0, mount_yaw_deg: 0, "
                 "scanner_time_offset_s: 0, scanner_latency_s: 0}"});
  const SimulationConfig two_read =
      ReadTruthYaml(WriteFile(ScratchFolder("truth_units") + "/two.yaml", two_text));
  ASSERT_EQ(two_read.scanners.size(), 3u);
  EXPECT_EQ(two_read.scanners[0].range_scale_error, 0.000123);
  EXPECT_EQ(two_read.scanners[0].range_offset_error_m, -0.0042);
  EXPECT_TRUE(std::isnan(two_read.scanners[1].range_scale_error));
  EXPECT_EQ(two_read.scanners[1].range_offset_error_m, 0.0);
  EXPECT_TRUE(std::isnan(two_read.scanners[2].range_scale_error));
  EXPECT_TRUE(std::isnan(two_read.scanners[2].range_offset_error_m));
  EXPECT_FALSE(two_read.draw_unit_range_models);
  EXPECT_EQ(two_read.scanner_jitter_s, 0.0);
  // ForScanner carries each entry's errors onto its run.
  EXPECT_EQ(ForScanner(two_read, 0).range_scale_error, 0.000123);
  EXPECT_EQ(ForScanner(two_read, 0).range_offset_error_m, -0.0042);
  EXPECT_TRUE(std::isnan(ForScanner(two_read, 2).range_offset_error_m));

  // None set: none written.
  testing_support::ExpectLacks(
      FormatTruthYaml(SimulationConfig(), 5),
      {"range_scale_error", "range_offset_error_m", "draw_unit_range_models", "scanner_jitter_s"});
}

}  // namespace
}  // namespace wallcal::sim
