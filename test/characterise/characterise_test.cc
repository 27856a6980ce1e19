// SPDX-License-Identifier: Apache-2.0
// characterise on simulated sessions whose scanner model is known (scanner_truth): the range
// model recovered within its reported σ, the warm-up drift, the preset fed back to calibrate,
// and the refusals.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "characterise/characterisation.h"
#include "common/angles.h"
#include "sim/simulation_config.h"
#include "io/config/session_reader.h"
#include "io/writers/writers.h"
#include "io/output_file.h"
#include "io/config/config_writer.h"
#include "pipeline/calibration.h"
#include "sim/simulated_session.h"
#include "test/support/expect_text.h"
#include "test/support/program_runner.h"
#include "test/support/scratch_files.h"

namespace wallcal::characterise {
namespace {

namespace fs = std::filesystem;
using testing_support::FreshScratchDir;

sim::SimulationConfig Scenario(const std::string& name) {
  return sim::ReadSimulationConfig(std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/" + name +
                                  ".yaml");
}

// A session folder simulated from `config` and options without the bootstrap (speed only: the
// characterisation does not use calibrate's repeatability).
CharacteriseRequest Simulated(const sim::SimulationConfig& config, uint64_t seed,
                              const fs::path& dir) {
  sim::WriteSimulatedSession(config, seed, (dir / "session").string());
  std::ofstream((dir / "fast.yaml").string()) << "solver:\n  bootstrap_samples: 0\n";
  CharacteriseRequest request;
  request.session_path = (dir / "session").string();
  request.config_path = (dir / "fast.yaml").string();
  request.threads = 1;
  return request;
}

// |estimate − truth| within 3 reported σ (a 0.3 % chance per value for an honest σ).
void ExpectWithin3Sigma(const Value& v, double truth, const char* what) {
  ASSERT_TRUE(v.known()) << what;
  EXPECT_LT(std::abs(v.value - truth), 3.0 * v.sigma)
      << what << " = " << v.value << " +- " << v.sigma << ", truth " << truth;
}

TEST(CharacteriseTest, RecoversAnLms291LikeScannerInCmMode) {
  const fs::path dir = FreshScratchDir("lms");
  sim::SimulationConfig config = Scenario("characterise_lms291");
  const Characterisation r = Characterise(Simulated(config, 3, dir));
  ASSERT_TRUE(r.ok()) << r.reason;
  // Truth: z = 0.9992·true + 6 mm + N(0, 8 mm), in cm -> k = 1/n, b = −c/n.
  ExpectWithin3Sigma(r.model.k, 1.0 / 0.9992, "k");
  ExpectWithin3Sigma(r.model.b_m, -0.006 / 0.9992, "b");
  ExpectWithin3Sigma(r.model.sigma_m, 0.008, "sigma");
  // The σ are those of a real determination: k to 0.1 %, b to 2 mm (ten stations).
  EXPECT_LT(r.model.k.sigma, 0.001);
  EXPECT_LT(r.model.b_m.sigma, 0.002);
  EXPECT_DOUBLE_EQ(r.stats.quantum_m, 0.01);
  // The preset's 75° limit, found from where returns stop (5° bins: σ 1.4°; 3σ plus the bin
  // edge effect of the interpolation).
  ASSERT_TRUE(r.stats.incidence_limit_reached);
  EXPECT_NEAR(r.stats.incidence_limit_rad.value * kRadToDeg, 75.0, 5.0);
  // The preset carries the measurement.
  EXPECT_EQ(r.preset.name, "sick_lms291_measured");
  EXPECT_DOUBLE_EQ(r.preset.range_scale_k, r.model.k.value);
  EXPECT_DOUBLE_EQ(r.preset.range_resolution_m, 0.01);
  // ... and how well it knows this unit, in place of the family's spread (10 mm, 5e-4).
  EXPECT_DOUBLE_EQ(r.preset.range_scale_sigma, r.model.k.sigma / r.model.k.value);
  EXPECT_DOUBLE_EQ(r.preset.range_offset_sigma_m, r.model.b_m.sigma);
  testing_support::ExpectContains(r.preset.source, {"measured", "characterise-lms291"});
  EXPECT_NE(Summary(r).find("k = "), std::string::npos);
  EXPECT_NE(Summary(r).find("the correction k*z + b is known to"), std::string::npos);
  EXPECT_EQ(Plots(r).size(), 3u);
}

TEST(CharacteriseTest, RecoversTheUrg04lxModelOfOkuboEtAl) {
  const fs::path dir = FreshScratchDir("urg");
  const Characterisation r = Characterise(Simulated(Scenario("characterise_urg04lx"), 5, dir));
  ASSERT_TRUE(r.ok()) << r.reason;
  // Okubo, Ye & Borenstein 2009: n = 0.9899, c = 7.0 mm, σ = 2.9 mm, mm mode.
  ExpectWithin3Sigma(r.model.k, 1.0 / 0.9899, "k");
  ExpectWithin3Sigma(r.model.b_m, -0.007 / 0.9899, "b");
  ExpectWithin3Sigma(r.model.sigma_m, 0.0029, "sigma");
  EXPECT_DOUBLE_EQ(r.stats.quantum_m, 0.001);
}

TEST(CharacteriseTest, MeasuresTheWarmUpDriftOfTheFirstHour) {
  const fs::path dir = FreshScratchDir("warmup");
  const Characterisation r =
      Characterise(Simulated(Scenario("characterise_lms291_warmup"), 2, dir));
  ASSERT_TRUE(r.ok()) << r.reason;
  ASSERT_TRUE(r.model.drift_fitted);
  EXPECT_NEAR(r.model.drift_span_s, 3600.0, 1e-6);
  // Truth: 8.4 mm · (1 − exp(−3600 s / 1200 s)) = 7.98 mm. σ ≈ 1.2 mm (the stations' shared
  // GNSS errors). Within 2σ: 1σ holds for 68 % of seeds only; 2σ for 95 %.
  const double truth_m = 0.0084 * (1.0 - std::exp(-3.0));
  ASSERT_TRUE(r.model.drift_first_hour_m.known());
  EXPECT_LT(std::abs(r.model.drift_first_hour_m.value - truth_m),
            2.0 * r.model.drift_first_hour_m.sigma)
      << r.model.drift_first_hour_m.value << " +- " << r.model.drift_first_hour_m.sigma;
  EXPECT_LT(r.model.drift_first_hour_m.sigma, 0.003);
}

// Writes `preset` where calibrate finds it for the session and points session.yaml at it.
void UsePreset(const fs::path& session_dir, const io::ScannerPreset& preset) {
  fs::create_directories(session_dir / "scanners");
  io::WriteFileAtomically((session_dir / "scanners" / (preset.name + ".yaml")).string(),
                          io::FormatScannerPreset(preset, {"test"}));
  io::SessionSpec spec = io::ReadSession((session_dir / "session.yaml").string());
  std::ifstream in((session_dir / "session.yaml").string());
  std::stringstream text;
  text << in.rdbuf();
  const std::string updated = std::regex_replace(
      text.str(), std::regex("model: " + spec.scanner_model), "model: " + preset.name);
  ASSERT_NE(updated, text.str());
  std::ofstream((session_dir / "session.yaml").string()) << updated;
}

pipeline::CalibrationResult Calibrate(const CharacteriseRequest& request) {
  pipeline::CalibrateRequest calibrate;
  calibrate.session_path = request.session_path;
  calibrate.config_path = request.config_path;
  calibrate.threads = 1;
  return pipeline::RunCalibration(calibrate);
}

TEST(CharacteriseTest, AMeasuredPresetMatchingTheShippedOneLeavesTheMountAlone) {
  const fs::path dir = FreshScratchDir("same");
  // The URG's truth is its shipped preset's model.
  const CharacteriseRequest request = Simulated(Scenario("characterise_urg04lx"), 7, dir);
  const pipeline::CalibrationResult before = Calibrate(request);
  ASSERT_TRUE(before.solve.estimate.usable) << before.solve.estimate.message;
  const Characterisation r = Characterise(request);
  ASSERT_TRUE(r.ok()) << r.reason;
  UsePreset(request.session_path, r.preset);
  const pipeline::CalibrationResult after = Calibrate(request);
  ASSERT_EQ(after.loaded.preset.name, "hokuyo_urg04lx_measured");
  ASSERT_TRUE(after.solve.estimate.usable) << after.solve.estimate.message;
  const Eigen::Matrix3d& cov = after.solve.estimate.covariance;
  EXPECT_LT(std::abs(after.solve.estimate.mount.x_m - before.solve.estimate.mount.x_m),
            std::sqrt(cov(0, 0)));
  EXPECT_LT(std::abs(after.solve.estimate.mount.y_m - before.solve.estimate.mount.y_m),
            std::sqrt(cov(1, 1)));
  EXPECT_LT(std::abs(after.solve.estimate.mount.yaw_rad - before.solve.estimate.mount.yaw_rad),
            std::sqrt(cov(2, 2)));
}

TEST(CharacteriseTest, AMeasuredPresetCorrectsTheMountWhenTheTrueOffsetDiffers) {
  // An LMS 291 whose true c is 1 cm while its shipped preset says 0, and the same session (same
  // seed: same GNSS, heading, survey and range noise) with c = 0 as the reference: what the
  // mount would be with the right range model. 30 stations, as docs/field-guide.md asks for a
  // preset that is to correct a mount: σ(k) ∝ 1/√stations, 0.00035 here (0.00058 with ten).
  sim::SimulationConfig config = Scenario("characterise_lms291");
  config.num_stations = 30;
  config.truth_scale_n = 1.0;
  config.truth_offset_c_m = 0.0;
  const pipeline::CalibrationResult reference =
      Calibrate(Simulated(config, 11, FreshScratchDir("offset_reference")));
  config.truth_offset_c_m = 0.010;
  const CharacteriseRequest request = Simulated(config, 11, FreshScratchDir("offset"));
  const pipeline::CalibrationResult before = Calibrate(request);
  ASSERT_TRUE(reference.solve.estimate.usable && before.solve.estimate.usable)
      << before.solve.estimate.message;
  const Characterisation r = Characterise(request);
  ASSERT_TRUE(r.ok()) << r.reason;
  ExpectWithin3Sigma(r.model.b_m, -0.010, "b");
  ExpectWithin3Sigma(r.model.k, 1.0, "k");
  UsePreset(request.session_path, r.preset);
  const pipeline::CalibrationResult after = Calibrate(request);
  ASSERT_TRUE(after.solve.estimate.usable) << after.solve.estimate.message;
  const double sigma_x = std::sqrt(after.solve.estimate.covariance(0, 0));
  const double sigma_y = std::sqrt(after.solve.estimate.covariance(1, 1));
  const double sigma_yaw = std::sqrt(after.solve.estimate.covariance(2, 2));
  // The uncorrected offset moves x by about its 1 cm (9.4 mm on this seed). What the measured
  // preset leaves is its own error at the stations' distances: σ(k)·d ⊕ σ(b) with d the middle
  // of the 3–15 m, 3.2 mm here. So x must come back to within 3 of that of the reference, and
  // closer than without the correction (9.4 mm is 2.9 of it: a 0.4 % chance of failing for an
  // honest σ); x, y and yaw within their own σ of the reference.
  const double d_mid_m = 0.5 * (r.distance_min_m + r.distance_max_m);
  const double sigma_correction = std::hypot(r.model.k.sigma * d_mid_m, r.model.b_m.sigma);
  const double dx_before = before.solve.estimate.mount.x_m - reference.solve.estimate.mount.x_m;
  const double dx_after = after.solve.estimate.mount.x_m - reference.solve.estimate.mount.x_m;
  EXPECT_GT(std::abs(dx_before), 0.007);  // the offset does move calibrate's x
  EXPECT_LT(std::abs(dx_after), std::abs(dx_before)) << dx_before << " " << dx_after;
  EXPECT_LT(std::abs(dx_after), 3.0 * sigma_correction) << sigma_correction;
  EXPECT_LT(std::abs(dx_after), sigma_x);
  EXPECT_LT(std::abs(after.solve.estimate.mount.y_m - reference.solve.estimate.mount.y_m), sigma_y);
  EXPECT_LT(std::abs(after.solve.estimate.mount.yaw_rad - reference.solve.estimate.mount.yaw_rad),
            sigma_yaw);
}

TEST(CharacteriseTest, RefusesASessionWithEveryStationAtOneDistance) {
  const fs::path dir = FreshScratchDir("narrow");
  sim::SimulationConfig config = Scenario("characterise_lms291");
  config.station_distance_m = 10.0;
  config.station_distance_far_m = 0.0;
  const Characterisation r = Characterise(Simulated(config, 1, dir));
  EXPECT_EQ(r.undetermined, Undetermined::kScaleK) << r.reason;
  EXPECT_NE(r.reason.find("stations from 3 m to 15 m"), std::string::npos) << r.reason;
}

TEST(CharacteriseTest, RefusesTooFewRanges) {
  const fs::path dir = FreshScratchDir("few");
  sim::SimulationConfig config = Scenario("characterise_urg04lx");
  config.log_every_n = 50;  // one scan in 5 s: a scan or two a station
  const Characterisation r = Characterise(Simulated(config, 1, dir));
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(r.undetermined == Undetermined::kTooFewRanges ||
              r.undetermined == Undetermined::kCalibrationFailed ||
              r.undetermined == Undetermined::kNoStations)
      << r.reason;
  EXPECT_FALSE(r.reason.empty());
}

TEST(CharacteriseTest, ABadMountFileIsBadInput) {
  const fs::path dir = FreshScratchDir("badmount");
  CharacteriseRequest request = Simulated(Scenario("characterise_urg04lx"), 1, dir);
  std::ofstream((dir / "offsets.yaml").string()) << "scanner_mount: {x: 1.0, y: oops}\n";
  request.mount_path = (dir / "offsets.yaml").string();
  EXPECT_THROW(Characterise(request), io::InputError);
  request.mount_path = (dir / "missing.yaml").string();
  EXPECT_THROW(Characterise(request), io::InputError);
}

TEST(CharacteriseTest, AGivenMountIsUsedWithItsSigma) {
  const fs::path dir = FreshScratchDir("mount");
  const sim::SimulationConfig config = Scenario("characterise_urg04lx");
  CharacteriseRequest request = Simulated(config, 4, dir);
  std::ofstream((dir / "offsets.yaml").string())
      << "scanner_mount: {x: 0.35, y: -0.06, yaw: " << -1.5 * kDegToRad
      << ", covariance: [1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 1e-6]}\n";
  request.mount_path = (dir / "offsets.yaml").string();
  const Characterisation r = Characterise(request);
  ASSERT_TRUE(r.ok()) << r.reason;
  EXPECT_TRUE(r.model.mount_given);
  EXPECT_TRUE(r.model.mount_sigma_given);
  ExpectWithin3Sigma(r.model.b_m, -0.007 / 0.9899, "b");
  EXPECT_LE(r.model.mount_x_m.sigma, 0.0101);  // the prior's 1 cm, or better
}

TEST(CharacteriseScenarioTest, ScannerTruthRoundTripsThroughTruthYamlOnlyWhenSet) {
  const fs::path dir = FreshScratchDir("truth");
  sim::SimulationConfig plain;
  EXPECT_EQ(sim::FormatTruthYaml(plain, 1).find("scanner_truth"), std::string::npos);
  EXPECT_EQ(sim::FormatTruthYaml(plain, 1).find("station_distance_far_m"), std::string::npos);
  sim::SimulationConfig config = Scenario("characterise_lms291_warmup");
  ASSERT_DOUBLE_EQ(config.truth_scale_n, 0.9992);
  ASSERT_DOUBLE_EQ(config.truth_drift_time_constant_s, 1200.0);
  config.truth_max_incidence_rad = 60.0 * kDegToRad;
  io::WriteFileAtomically((dir / "truth.yaml").string(), sim::FormatTruthYaml(config, 1));
  const sim::SimulationConfig back = sim::ReadTruthYaml((dir / "truth.yaml").string());
  EXPECT_DOUBLE_EQ(back.truth_scale_n, 0.9992);
  EXPECT_DOUBLE_EQ(back.truth_offset_c_m, 0.006);
  EXPECT_DOUBLE_EQ(back.truth_sigma_m, 0.008);
  EXPECT_DOUBLE_EQ(back.truth_resolution_m, 0.01);
  EXPECT_NEAR(back.truth_max_incidence_rad, 60.0 * kDegToRad, 1e-12);
  EXPECT_DOUBLE_EQ(back.truth_drift_amplitude_m, 0.0084);
  EXPECT_DOUBLE_EQ(back.station_distance_far_m, 17.6);
  // A bad value is refused with its key.
  std::ofstream((dir / "bad.yaml").string()) << "scanner_truth: {n: 3.0}\n";
  try {
    sim::ReadSimulationConfig((dir / "bad.yaml").string());
    FAIL() << "n = 3 accepted";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scanner_truth.n"), std::string::npos) << e.what();
  }
}

// The program: usage and exit codes.
// COMMAND is a shell command line (test/support/program_runner.h); the exit status.
int RunProgram(const std::string& command) { return testing_support::RunShell(command).exit_code; }

TEST(CharacteriseProgramTest, ExitCodes) {
  ASSERT_TRUE(fs::exists(testing_support::WallcalPath())) << "build the wallcal target first";
  const std::string program =
      testing_support::ShellQuote(testing_support::WallcalPath()) + " characterise";
  EXPECT_EQ(RunProgram(program + " --help"), 0);
  EXPECT_EQ(RunProgram(program + " --version"), 0);
  EXPECT_EQ(RunProgram(program), 2);
  EXPECT_EQ(RunProgram(program + " --bogus x"), 2);
  EXPECT_EQ(RunProgram(program + " /nonexistent/session"), 2);
  const fs::path dir = FreshScratchDir("program");
  const CharacteriseRequest request = Simulated(Scenario("characterise_urg04lx"), 2, dir);
  const std::string out = (dir / "preset.yaml").string();
  EXPECT_EQ(RunProgram(program + " " + request.session_path + " --config " + request.config_path +
                " --output " + out + " --report " + (dir / "plots").string()),
            0);
  const io::ScannerPreset preset = io::ReadScannerPreset(out);
  EXPECT_EQ(preset.name, "preset");
  EXPECT_NEAR(preset.range_scale_k, 1.0 / 0.9899, 0.01);
  // The written preset carries the unit's σ (the URG family's is 10 mm and 0.005).
  EXPECT_GT(preset.range_offset_sigma_m, 0.0);
  EXPECT_LT(preset.range_offset_sigma_m, 0.005);
  EXPECT_GT(preset.range_scale_sigma, 0.0);
  EXPECT_LT(preset.range_scale_sigma, 0.005);
  EXPECT_TRUE(fs::exists(dir / "plots" / "range_error_vs_range.svg"));
  // Never over an input.
  EXPECT_EQ(RunProgram(program + " " + request.session_path + " --config " + request.config_path +
                " --output " + request.config_path),
            2);
}

}  // namespace
}  // namespace wallcal::characterise
