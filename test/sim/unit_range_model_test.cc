// SPDX-License-Identifier: Apache-2.0
// Each scanner unit's own range model (range_scale_error, range_offset_error_m,
// draw_unit_range_models) and the scan stamps' jitter (scanner_jitter_s): the errors move the
// logged ranges by what the keys say, drawn errors are reproducible, differ between the
// scanners of a session, leave every other draw alone and come back from truth.yaml; jittered
// stamps lie within [0, jitter] of the unjittered ones.
//
// Tolerances: two runs with the same seed draw the same range noise ξ per beam, so a range
// moves by the error alone, up to one quantum where the rounding of n·y + c + ξ falls the other
// way (and the float the scan stores: 1e-5 m at 80 m).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sim/simulated_session.h"
#include "sim/simulator.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"
#include "test/support/sim_fixtures.h"

namespace wallcal::sim {
namespace {
using namespace testing_fixtures;  // NOLINT: the shared fixtures

namespace fs = std::filesystem;

constexpr double kFloatM = 1e-5;  // a range stored as float, up to 80 m

// A short run facing the default wall head on (no heading spread): three stops of 1 s.
SimulationConfig HeadOn() {
  SimulationConfig config = DefaultConfig();
  config.num_stations = 3;
  config.dwell_s = 1.0;
  config.heading_spread_rad = 0.0;
  config.lateral_spread_m = 2.0;
  config.log_every_n = 5;
  config.lost_scan_fraction = 0.0;
  return config;
}

// The range of a beam that returned (not the SICK's no-return maximum).
bool Returned(const io::ScanRecord& scan, size_t beam) {
  return scan.ranges_m[beam] > 0.0f && scan.ranges_m[beam] < scan.max_range_m;
}

// For each beam that returned in both runs: `check(base range, range)`. Returns their count.
template <class Check>
int ForEachBeam(const Collected& base, const Collected& moved, Check check) {
  EXPECT_EQ(base.scans.size(), moved.scans.size());
  int beams = 0;
  for (size_t s = 0; s < std::min(base.scans.size(), moved.scans.size()); ++s) {
    EXPECT_EQ(base.scans[s].stamp_s, moved.scans[s].stamp_s);
    for (size_t i = 0; i < base.scans[s].ranges_m.size(); ++i) {
      if (!Returned(base.scans[s], i) || !Returned(moved.scans[s], i)) continue;
      check(static_cast<double>(base.scans[s].ranges_m[i]),
            static_cast<double>(moved.scans[s].ranges_m[i]));
      ++beams;
    }
  }
  return beams;
}

TEST(UnitRangeModelTest, OffsetErrorMovesEveryRangeByIt) {
  const io::ScannerPreset preset = SickLms291();  // 1 cm quanta, 1 cm noise
  const double quantum_m = preset.range_resolution_m;
  SimulationConfig config = HeadOn();
  config.mixed_pixel_probability = 0.0;  // a head-on wall has no depth jump anyway
  const Collected base = RunSim(config, preset, 11);
  config.range_offset_error_m = 0.03;
  const Collected moved = RunSim(config, preset, 11);
  double sum_m = 0.0;
  const int beams = ForEachBeam(base, moved, [&](double z0_m, double z1_m) {
    EXPECT_NEAR(z1_m - z0_m, 0.03, quantum_m + kFloatM);
    sum_m += z1_m - z0_m;
  });
  ASSERT_GT(beams, 1000);
  EXPECT_NEAR(sum_m / beams, 0.03, 1e-4);
  // The GNSS and heading draws are the same.
  ASSERT_EQ(base.session.fixes.size(), moved.session.fixes.size());
  for (size_t i = 0; i < base.session.fixes.size(); ++i) {
    EXPECT_EQ(base.session.fixes[i].lat_deg, moved.session.fixes[i].lat_deg);
  }
}

TEST(UnitRangeModelTest, ScaleErrorScalesEveryRange) {
  const io::ScannerPreset preset = SickLms291();
  const double quantum_m = preset.range_resolution_m;
  SimulationConfig config = HeadOn();
  config.heading_spread_rad = 60.0 * kDegToRad;  // ranges from 5 m to past 15 m
  config.mixed_pixel_probability = 0.0;
  const Collected base = RunSim(config, preset, 12);
  config.range_scale_error = 0.01;
  const Collected scaled = RunSim(config, preset, 12);
  // z1 − z0 = 0.01·n·y, y = z0 − ξ within half a quantum: 0.01·(5 σ + q/2) of slack.
  const double slack_m = 0.01 * (5.0 * preset.range_sigma_m + 0.5 * quantum_m);
  double sxy = 0.0, sxx = 0.0, min_m = 1e9, max_m = 0.0;
  const int beams = ForEachBeam(base, scaled, [&](double z0_m, double z1_m) {
    EXPECT_NEAR(z1_m - z0_m, 0.01 * z0_m, quantum_m + slack_m + kFloatM) << z0_m;
    sxy += z0_m * (z1_m - z0_m);
    sxx += z0_m * z0_m;
    min_m = std::min(min_m, z0_m);
    max_m = std::max(max_m, z0_m);
  });
  ASSERT_GT(beams, 1000);
  EXPECT_LT(min_m, 7.0);
  EXPECT_GT(max_m, 12.0);
  EXPECT_NEAR(sxy / sxx, 0.01, 2e-4);  // the slope through the origin
}

TEST(UnitRangeModelTest, ErrorsAreOffTheToolsCorrectionAndOnTopOfTheTruthOverrides) {
  io::ScannerPreset preset = SickLms291();
  preset.range_scale_k = 1.25;
  preset.range_offset_b_m = 0.02;
  SimulationConfig config;
  config.truth_scale_n = 0.8;
  config.truth_offset_c_m = -0.016;
  config.range_scale_error = 0.002;
  config.range_offset_error_m = 0.03;
  const io::ScannerPreset truth = TrueScannerPreset(config, preset);
  EXPECT_DOUBLE_EQ(truth.sim_scale_n, 0.8 * 1.002);
  EXPECT_DOUBLE_EQ(truth.sim_offset_c_m, -0.016 + 0.03 / 1.25);
  // The tool's corrected range k·z + b of a true range y is off by e_k·k·n·y + e_b.
  const double y_m = 10.0;
  const auto corrected = [&preset](const io::ScannerPreset& p, double y) {
    return preset.range_scale_k * (p.sim_scale_n * y + p.sim_offset_c_m) + preset.range_offset_b_m;
  };
  SimulationConfig exact = config;
  exact.range_scale_error = kNaN;
  exact.range_offset_error_m = kNaN;
  const io::ScannerPreset unit_free = TrueScannerPreset(exact, preset);
  EXPECT_NEAR(corrected(truth, y_m) - corrected(unit_free, y_m), 0.002 * 1.25 * 0.8 * y_m + 0.03,
              1e-12);
  // Unset: the truth overrides alone; without the switch nothing is drawn.
  EXPECT_EQ(unit_free.sim_scale_n, 0.8);
  EXPECT_EQ(unit_free.sim_offset_c_m, -0.016);
  EXPECT_TRUE(std::isnan(UnitRangeErrors(exact, preset, 5).range_scale_error));
  EXPECT_TRUE(std::isnan(UnitRangeErrors(exact, preset, 5).range_offset_error_m));
}

TEST(UnitRangeModelTest, DrawnErrorsFollowThePresetsSigmaPerScannerAndSeed) {
  const io::ScannerPreset preset = SickLms291();  // σ_k 5e-4, σ_b 10 mm
  SimulationConfig config = DefaultConfig();
  config.draw_unit_range_models = true;
  SimulationConfig second = config;
  second.scanner_noise_stream = 1;
  const int kSeeds = 400;
  double skk = 0.0, sbb = 0.0, skk2 = 0.0, sk12 = 0.0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const SimulationConfig a = UnitRangeErrors(config, preset, seed);
    const SimulationConfig b = UnitRangeErrors(second, preset, seed);
    const SimulationConfig again = UnitRangeErrors(config, preset, seed);
    EXPECT_EQ(a.range_scale_error, again.range_scale_error);
    EXPECT_EQ(a.range_offset_error_m, again.range_offset_error_m);
    EXPECT_NE(a.range_scale_error, b.range_scale_error);
    EXPECT_NE(a.range_offset_error_m, b.range_offset_error_m);
    skk += a.range_scale_error * a.range_scale_error;
    sbb += a.range_offset_error_m * a.range_offset_error_m;
    skk2 += b.range_scale_error * b.range_scale_error;
    sk12 += a.range_scale_error * b.range_scale_error;
  }
  // σ from 400 draws: within 15 % (4 standard errors of 3.5 %).
  EXPECT_NEAR(std::sqrt(skk / kSeeds), preset.range_scale_sigma, 0.15 * preset.range_scale_sigma);
  EXPECT_NEAR(std::sqrt(sbb / kSeeds), preset.range_offset_sigma_m,
              0.15 * preset.range_offset_sigma_m);
  EXPECT_NEAR(std::sqrt(skk2 / kSeeds), preset.range_scale_sigma, 0.15 * preset.range_scale_sigma);
  EXPECT_LT(std::abs(sk12 / std::sqrt(skk * skk2)), 0.2);  // the scanners' draws independent

  // A value given stays; the other is drawn as it would be without it.
  SimulationConfig given = config;
  given.range_scale_error = 0.004;
  const SimulationConfig drawn = UnitRangeErrors(config, preset, 9);
  const SimulationConfig kept = UnitRangeErrors(given, preset, 9);
  EXPECT_EQ(kept.range_scale_error, 0.004);
  EXPECT_EQ(kept.range_offset_error_m, drawn.range_offset_error_m);
}

// A scan log's lines: the stamp (the logger's, the last field) and the ranges of each.
struct LoggedScan {
  std::string stamp;
  std::vector<double> ranges_m;
};
std::vector<LoggedScan> ReadClf(const std::string& path) {
  std::vector<LoggedScan> scans;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("RAWLASER1 ", 0) != 0) continue;
    std::istringstream fields(line);
    std::vector<std::string> f;
    for (std::string word; fields >> word;) f.push_back(word);
    LoggedScan scan;
    scan.stamp = f.back();
    const int count = std::stoi(f.at(8));
    for (int i = 0; i < count; ++i) scan.ranges_m.push_back(std::stod(f.at(9 + i)));
    scans.push_back(scan);
  }
  return scans;
}

std::string Bytes(const fs::path& path) { return testing_support::ReadFile(path.string()); }

// The held-out two-unit scenario, cut short.
SimulationConfig TwoUnits() {
  SimulationConfig config = ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/bench_two_scanners_units_site3.yaml");
  config.num_stations = 3;
  config.dwell_s = 2.0;
  return config;
}

TEST(UnitRangeModelTest, DrawnUnitsChangeOnlyTheirRangesAndComeBackFromTruthYaml) {
  SimulationConfig config = TwoUnits();
  ASSERT_TRUE(config.draw_unit_range_models);
  ASSERT_EQ(config.scanners.size(), 2u);
  const fs::path on = testing_support::FreshScratchDir("units_on");
  const fs::path again = testing_support::FreshScratchDir("units_again");
  const fs::path off = testing_support::FreshScratchDir("units_off");
  WriteSimulatedSession(config, 1, on.string());
  WriteSimulatedSession(config, 1, again.string());
  config.draw_unit_range_models = false;
  WriteSimulatedSession(config, 1, off.string());

  // Reproducible: the same seed writes the same files.
  for (const char* file : {"truth.yaml", "scans_front.clf", "scans_front_left_corner.clf"}) {
    EXPECT_EQ(Bytes(on / file), Bytes(again / file)) << file;
  }
  // Every other draw as without the switch: the logs, the survey and session.yaml.
  for (const char* file : {"gnss.nmea", "heading.nmea", "survey.csv", "session.yaml"}) {
    EXPECT_EQ(Bytes(on / file), Bytes(off / file)) << file;
  }

  // truth.yaml names each unit's errors; the scanners differ; without the switch: none.
  const SimulationConfig truth = ReadTruthYaml((on / "truth.yaml").string());
  EXPECT_TRUE(truth.draw_unit_range_models);
  ASSERT_EQ(truth.scanners.size(), 2u);
  const io::ScannerPreset preset = SickLms291();
  for (const SimScanner& unit : truth.scanners) {
    EXPECT_LT(std::abs(unit.range_scale_error), 5.0 * preset.range_scale_sigma) << unit.id;
    EXPECT_LT(std::abs(unit.range_offset_error_m), 5.0 * preset.range_offset_sigma_m) << unit.id;
  }
  EXPECT_NE(truth.scanners[0].range_scale_error, truth.scanners[1].range_scale_error);
  EXPECT_NE(truth.scanners[0].range_offset_error_m, truth.scanners[1].range_offset_error_m);
  EXPECT_TRUE(std::isnan(truth.range_scale_error));
  const std::string off_truth = Bytes(off / "truth.yaml");
  testing_support::ExpectLacks(
      off_truth, {"range_scale_error", "range_offset_error_m", "draw_unit_range_models"});

  // Each log: the same scans at the same stamps, every range moved by its unit's errors.
  for (size_t k = 0; k < 2; ++k) {
    const std::string file = "scans_" + truth.scanners[k].id + ".clf";
    const std::vector<LoggedScan> a = ReadClf((off / file).string());
    const std::vector<LoggedScan> b = ReadClf((on / file).string());
    ASSERT_EQ(a.size(), b.size()) << file;
    ASSERT_GT(a.size(), 50u);
    const double e_k = truth.scanners[k].range_scale_error;
    const double e_b = truth.scanners[k].range_offset_error_m;
    int beams = 0;
    double offset_sum_m = 0.0;
    for (size_t s = 0; s < a.size(); ++s) {
      EXPECT_EQ(a[s].stamp, b[s].stamp);
      ASSERT_EQ(a[s].ranges_m.size(), b[s].ranges_m.size());
      for (size_t i = 0; i < a[s].ranges_m.size(); ++i) {
        const double z0 = a[s].ranges_m[i], z1 = b[s].ranges_m[i];
        if (z0 >= preset.max_range_m || z1 >= preset.max_range_m) continue;
        // A mixed pixel moves by the same errors (its range is the model's too).
        EXPECT_NEAR(z1 - z0, e_k * z0 + e_b, preset.range_resolution_m + 1e-3) << file;
        offset_sum_m += z1 - z0 - e_k * z0;
        ++beams;
      }
    }
    ASSERT_GT(beams, 1000) << file;
    // Over the beams the rounding averages out: the offset itself (this seed's are 3 mm and
    // more, so that a unit left as it was would fail).
    EXPECT_GT(std::abs(e_b), 0.003) << file;
    EXPECT_NEAR(offset_sum_m / beams, e_b, 5e-4) << file;
  }

  // The errors truth.yaml gives simulate the same session again.
  const fs::path replay = testing_support::FreshScratchDir("units_replay");
  WriteSimulatedSession(truth, 1, replay.string());
  for (const char* file : {"truth.yaml", "scans_front.clf", "scans_front_left_corner.clf",
                           "gnss.nmea", "session.yaml"}) {
    EXPECT_EQ(Bytes(on / file), Bytes(replay / file)) << file;
  }
}

TEST(UnitRangeModelTest, OneScannersErrorsInTruthYaml) {
  SimulationConfig config = HeadOn();
  config.range_offset_error_m = 0.03;
  config.draw_unit_range_models = true;  // the scale error drawn, the offset given
  const fs::path dir = testing_support::FreshScratchDir("one_unit");
  WriteSimulatedSession(config, 6, dir.string());
  const SimulationConfig truth = ReadTruthYaml((dir / "truth.yaml").string());
  EXPECT_EQ(truth.range_offset_error_m, 0.03);
  EXPECT_EQ(truth.range_scale_error, UnitRangeErrors(config, SickLms291(), 6).range_scale_error);
  EXPECT_FALSE(std::isnan(truth.range_scale_error));
}

TEST(UnitRangeModelTest, ScanStampsJitterWithinTheBoundOnTheirOwnStream) {
  const io::ScannerPreset preset = SickLms291();
  SimulationConfig config = HeadOn();
  config.log_every_n = 1;
  config.scanner_latency_s = 0.02;
  const Collected base = RunSim(config, preset, 21);
  // Unset: each stamp is the scan's time on the logging clock plus the latency.
  for (size_t k = 0; k < base.scans.size(); ++k) {
    EXPECT_EQ(base.scans[k].stamp_s, config.start_time_s + k / preset.rate_hz -
                                         config.scanner_time_offset_s + config.scanner_latency_s);
  }
  config.scanner_jitter_s = 0.004;
  const Collected jittered = RunSim(config, preset, 21);
  ASSERT_EQ(base.scans.size(), jittered.scans.size());
  ASSERT_GT(base.scans.size(), 200u);
  double sum_s = 0.0, max_s = 0.0;
  for (size_t k = 0; k < base.scans.size(); ++k) {
    const double late_s = jittered.scans[k].stamp_s - base.scans[k].stamp_s;
    EXPECT_GE(late_s, 0.0);
    EXPECT_LE(late_s, 0.004 + 1e-9);
    EXPECT_EQ(jittered.scans[k].ranges_m, base.scans[k].ranges_m);  // only the stamps move
    sum_s += late_s;
    max_s = std::max(max_s, late_s);
  }
  // Uniform on [0, 4 ms]: mean 2 ms (σ of the mean over n > 200 scans below 0.08 ms).
  EXPECT_NEAR(sum_s / base.scans.size(), 0.002, 0.0004);
  EXPECT_GT(max_s, 0.0035);
  for (size_t i = 0; i < base.session.headings.size(); ++i) {
    EXPECT_EQ(base.session.headings[i].stamp_s, jittered.session.headings[i].stamp_s);
  }

  // Each scanner of a session jitters on its own stream.
  SimulationConfig second = config;
  second.scanner_noise_stream = 1;
  const Collected other = RunSim(second, preset, 21);
  ASSERT_EQ(other.scans.size(), jittered.scans.size());
  int differ = 0;
  for (size_t k = 0; k < other.scans.size(); ++k) {
    differ += other.scans[k].stamp_s != jittered.scans[k].stamp_s;
  }
  EXPECT_GT(differ, static_cast<int>(other.scans.size()) * 9 / 10);
}

}  // namespace
}  // namespace wallcal::sim
