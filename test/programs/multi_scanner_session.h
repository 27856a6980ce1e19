// SPDX-License-Identifier: Apache-2.0
#pragma once
// The two-scanner sessions the multi-scanner tests share (test/programs/multi_scanner_*_test.cc):
// configs/simulate/two_corner_scanners.yaml on a short stop-and-go run, simulated by the
// program into a scratch folder of the test binary's own, and the calls that calibrate them.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "io/config/config_writer.h"
#include "pipeline/multi_scanner.h"
#include "sim/simulation_config.h"
#include "test/support/program_runner.h"
#include "test/support/scratch_dir.h"
#include "test/support/shipped_presets.h"

namespace wallcal::multi_scanner_testing {

namespace fs = std::filesystem;

inline fs::path FreshDir(const std::string& name) {
  static const testing_support::ScratchDir scratch("wallcal_multi_");
  const fs::path dir = scratch.path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The two corner scanners of configs/simulate/two_corner_scanners.yaml, on a short stop-and-go
// run (8 stations of 3 s).
inline sim::SimulationConfig TwoScanners() {
  sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/two_corner_scanners.yaml");
  config.num_stations = 8;
  config.dwell_s = 3.0;
  return config;
}

inline std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// TwoScanners() as a file for `wallcal simulate --config`: the shipped config with the short
// run's two keys replaced.
inline const fs::path& ShortConfig() {
  static const fs::path file = [] {
    const fs::path f = FreshDir("config") / "two_scanners_short.yaml";
    std::string text = ReadText(fs::path(WALLCAL_SOURCE_DIR) /
                                "configs/simulate/two_corner_scanners.yaml");
    for (const auto& [from, to] : {std::pair<std::string, std::string>{"\nnum_stations: 10\n",
                                                                       "\nnum_stations: 8\n"},
                                   {"\ndwell_s: 4.0\n", "\ndwell_s: 3.0\n"}}) {
      const size_t at = text.find(from);
      EXPECT_NE(at, std::string::npos) << from;
      if (at != std::string::npos) text.replace(at, from.size(), to);
    }
    std::ofstream(f) << text;
    return f;
  }();
  return file;
}

// `wallcal simulate --seed 7 --format FORMAT` of ShortConfig() into the folder `name`.
inline fs::path Simulate(const std::string& format, const std::string& name) {
  const fs::path dir = FreshDir(name);
  const testing_support::ProgramRun run = testing_support::RunWallcal(
      {"simulate", "--config", ShortConfig().string(), "--seed", "7", "--format", format,
       "--output", dir.string()});
  EXPECT_EQ(run.exit_code, 0) << format << ": " << run.err;
  return dir;
}

inline const fs::path& TextSession() {
  static const fs::path dir = Simulate("text", "text");
  return dir;
}

// The same session as a recording of `format`, in the folder `name` (default: the format's).
inline fs::path SessionAs(const std::string& format, const std::string& name = "") {
  return Simulate(format, name.empty() ? format : name);
}

// Each scanner of the session at `dir` names a preset of its own in the session's scanners/
// folder: the family's, with its unit's range model known to offset_sigma_m and scale_sigma
// (0 and 0: taken as exact).
inline void OwnUnitPresets(const fs::path& dir, double offset_sigma_m, double scale_sigma) {
  io::ScannerPreset preset = testing_support::ShippedPreset("sick_lms291");
  preset.range_offset_sigma_m = offset_sigma_m;
  preset.range_scale_sigma = scale_sigma;
  fs::create_directories(dir / "scanners");
  std::string session = ReadText(dir / "session.yaml");
  for (const std::string id : {"front_left", "front_right"}) {
    preset.name = "lms291_" + id;
    std::ofstream(dir / "scanners" / (preset.name + ".yaml")) << io::FormatScannerPreset(preset, {});
    const size_t entry = session.find("  - id: " + id + "\n");
    const size_t model = session.find("model: sick_lms291", entry);
    ASSERT_NE(entry, std::string::npos) << session;
    ASSERT_NE(model, std::string::npos) << session;
    session.replace(model, std::string("model: sick_lms291").size(), "model: " + preset.name);
  }
  std::ofstream(dir / "session.yaml", std::ios::trunc) << session;
}

// The session's units characterised: the σ a characterised unit has (0.5 mm, 2e-5).
inline void CharacteriseUnits(const fs::path& dir) { OwnUnitPresets(dir, 0.0005, 2e-5); }

inline pipeline::SeveralScannersResult Calibrate(const fs::path& dir, bool allow_partial = false,
                                          bool collect_report_data = false) {
  pipeline::CalibrateRequest request;
  request.session_path = dir.string();
  request.collect_report_data = collect_report_data;
  return pipeline::RunSeveralScanners(request, allow_partial);
}

// stdout only, so that --emit's text can be parsed.
inline testing_support::ProgramRun RunCalibrate(const fs::path& dir, std::vector<std::string> options) {
  options.insert(options.begin(), {"calibrate", dir.string()});
  return testing_support::RunWallcal(options);
}

}  // namespace wallcal::multi_scanner_testing
