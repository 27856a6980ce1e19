// SPDX-License-Identifier: Apache-2.0
// The files shipped in configs/ load, validate, and say what the code's defaults say.

#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "pipeline/calibrate_options.h"
#include "sim/simulation_config.h"
#include "io/config/session_reader.h"

namespace wallcal::io {
using pipeline::CalibrateOptions;
using pipeline::ReadCalibrateOptions;
using sim::ReadSimulationConfig;
using sim::SimulationConfig;
namespace {

namespace fs = std::filesystem;
const fs::path kConfigs = fs::path(WALLCAL_SOURCE_DIR) / "configs";

// Every key of an option struct with its value in the struct's own units, in the order its
// Visit...Options function lists them (one list per struct: the keys cannot drift apart).
struct KeyValues {
  std::vector<std::pair<std::string, double>> values;
  std::string section;
  void Number(const std::string& key, double& value, const io::Check& = {}) {
    values.push_back({section + key, value});
  }
  void Scaled(const std::string& key, double& value, double, const io::Check& = {}) {
    Number(key, value);
  }
  void Integer(const std::string& key, int& value, const io::Check& = {}) {
    values.push_back({section + key, value});
  }
  void Boolean(const std::string& key, bool& value) { values.push_back({section + key, value}); }
};

KeyValues ValuesOf(CalibrateOptions options) {
  KeyValues v;
  v.section = "detector.";
  calib::VisitDetectorOptions(v, options.detector);
  v.section = "alignment.";
  calib::VisitAlignmentOptions(v, options.alignment);
  v.section = "solver.";
  solvers::VisitSolverOptions(v, options.solver);
  v.section = "acceptance.";
  pipeline::VisitAcceptanceOptions(v, options.acceptance);
  v.section = "";
  v.Integer("first_pass_max_scans", options.first_pass_max_scans);
  return v;
}

// configs/calibrate.yaml documents the defaults: every key of it must equal the built-in
// default: to 1e-6 (the file rounds some angles, written in degrees), and to 1e-12 where the
// value itself is too small for that to say anything (a drift rate in rad/s).
TEST(ShippedConfigTest, CalibrateYamlEqualsBuiltInDefaults) {
  const KeyValues file = ValuesOf(ReadCalibrateOptions((kConfigs / "calibrate.yaml").string()));
  const KeyValues built_in = ValuesOf(CalibrateOptions());
  ASSERT_EQ(file.values.size(), built_in.values.size());
  ASSERT_GE(file.values.size(), 48u);  // at least the keys the file has always had
  for (size_t i = 0; i < file.values.size(); ++i) {
    const auto& [key, value] = file.values[i];
    const double d = built_in.values[i].second;
    EXPECT_NEAR(value, d, std::abs(d) < 1e-4 ? 1e-12 : 1e-6) << key;
  }
}

TEST(ShippedConfigTest, EverySimulationScenarioLoadsAndNamesAPreset) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(kConfigs / "simulate")) {
    if (entry.path().extension() != ".yaml") continue;
    const SimulationConfig config = ReadSimulationConfig(entry.path().string());
    EXPECT_NO_THROW(LoadScannerPreset(config.scanner_model, {(kConfigs / "scanners").string()}))
        << entry.path();
    ++count;
  }
  EXPECT_GE(count, 4);
}

}  // namespace
}  // namespace wallcal::io
