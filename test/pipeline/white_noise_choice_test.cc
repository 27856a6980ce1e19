// SPDX-License-Identifier: Apache-2.0
// Where the white noise the solve takes comes from: the stops when they hold enough samples,
// else the drives, else the configured figures; on synthetic logs and on simulated sessions.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>

#include "calib/drive_white_noise.h"
#include "calib/white_noise.h"
#include "common/angles.h"
#include "common/format.h"
#include "outputs/summary.h"
#include "pipeline/calibration.h"
#include "pipeline/step_results.h"
#include "solvers/solver_options.h"
#include "test/support/simulated_sessions.h"
#include "test/support/synthetic_pose_logs.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;
using pipeline::NoiseSource;
using testing_support::MakeSyntheticPoseLog;
using testing_support::SyntheticDrivePlan;
using testing_support::SyntheticPoseLog;

struct Measured {
  calib::MeasuredWhiteNoise at_stops;
  calib::DriveWhiteNoise on_drives;
  pipeline::WhiteNoiseInUse in_use;
};

Measured MeasureAndChoose(const SyntheticPoseLog& log, const solvers::SolverOptions& configured) {
  Measured m;
  m.at_stops = calib::MeasureWhiteNoise(log.positions, log.yaws, log.dwells);
  m.on_drives = calib::MeasureDriveWhiteNoise(log.positions, log.yaws, log.dwells);
  m.in_use = pipeline::ChooseWhiteNoise(configured, m.at_stops, m.on_drives);
  return m;
}

TEST(WhiteNoiseChoiceTest, StopsThatHoldEnoughKeepTheirFigures) {
  // Ten stops of 4 s (760 GNSS and 790 heading degrees of freedom) and drives between them:
  // both measure, the stops' figures are taken.
  SyntheticDrivePlan plan;
  plan.num_stops = 10;
  const Measured m = MeasureAndChoose(MakeSyntheticPoseLog(plan, 11), solvers::SolverOptions());
  ASSERT_GT(m.at_stops.gnss_white_sigma_m, 0.0);
  ASSERT_GT(m.on_drives.gnss_white_sigma_m, 0.0);
  ASSERT_NE(m.at_stops.gnss_white_sigma_m, m.on_drives.gnss_white_sigma_m);
  EXPECT_EQ(m.in_use.gnss_source, NoiseSource::kMeasuredAtStops);
  EXPECT_EQ(m.in_use.gnss_white_sigma_m, m.at_stops.gnss_white_sigma_m);
  EXPECT_EQ(m.in_use.heading_source, NoiseSource::kMeasuredAtStops);
  EXPECT_EQ(m.in_use.heading_sigma_rad, m.at_stops.heading_sigma_rad);
}

TEST(WhiteNoiseChoiceTest, StopsTooShortLeaveItToTheDrives) {
  // Stops of 0.3 s: too short to be dwells, the drives measure.
  SyntheticDrivePlan plan;
  plan.num_stops = 20;
  plan.stop_s = 0.3;
  plan.stops_are_dwells = false;
  const Measured m = MeasureAndChoose(MakeSyntheticPoseLog(plan, 12), solvers::SolverOptions());
  EXPECT_EQ(m.at_stops.gnss_white_sigma_m, 0.0);
  EXPECT_EQ(m.in_use.gnss_source, NoiseSource::kMeasuredOnDrives);
  EXPECT_EQ(m.in_use.gnss_white_sigma_m, m.on_drives.gnss_white_sigma_m);
  EXPECT_NEAR(m.in_use.gnss_white_sigma_m / plan.gnss_white_sigma_m, 1.0,
              4.0 / std::sqrt(2.0 * m.on_drives.gnss_degrees_of_freedom));
  EXPECT_EQ(m.in_use.heading_source, NoiseSource::kMeasuredOnDrives);
  EXPECT_NEAR(m.in_use.heading_sigma_rad / plan.heading_sigma_rad, 1.0,
              4.0 / std::sqrt(2.0 * m.on_drives.heading_degrees_of_freedom));
}

TEST(WhiteNoiseChoiceTest, OneShortStopAndAShortDriveFallBackToTheConfigured) {
  // One stop of 4 s (76 GNSS degrees of freedom) and 6 s of drive (70): neither is enough.
  SyntheticDrivePlan plan;
  plan.num_stops = 1;
  plan.drive_s = 6.0;
  solvers::SolverOptions configured;
  configured.gnss_white_sigma_m = 0.007;
  configured.heading_sigma_rad = 0.2 * kDegToRad;
  const Measured m = MeasureAndChoose(MakeSyntheticPoseLog(plan, 13), configured);
  EXPECT_LT(m.at_stops.gnss_degrees_of_freedom, calib::kMinWhiteNoiseDegreesOfFreedom);
  EXPECT_LT(m.on_drives.gnss_degrees_of_freedom, calib::kMinWhiteNoiseDegreesOfFreedom);
  EXPECT_LT(m.on_drives.heading_degrees_of_freedom, calib::kMinWhiteNoiseDegreesOfFreedom);
  EXPECT_EQ(m.in_use.gnss_source, NoiseSource::kConfigured);
  EXPECT_EQ(m.in_use.gnss_white_sigma_m, 0.007);
  EXPECT_EQ(m.in_use.heading_source, NoiseSource::kConfigured);
  EXPECT_EQ(m.in_use.heading_sigma_rad, 0.2 * kDegToRad);
}

TEST(WhiteNoiseChoiceTest, EachFigureFromItsOwnSource) {
  // Headings at the stops but fixes only on the drives: each figure says where it came from.
  calib::MeasuredWhiteNoise at_stops;
  at_stops.heading_sigma_rad = 0.001;
  calib::DriveWhiteNoise on_drives;
  on_drives.gnss_white_sigma_m = 0.004;
  on_drives.heading_sigma_rad = 0.002;
  const pipeline::WhiteNoiseInUse in_use =
      pipeline::ChooseWhiteNoise(solvers::SolverOptions(), at_stops, on_drives);
  EXPECT_EQ(in_use.gnss_source, NoiseSource::kMeasuredOnDrives);
  EXPECT_EQ(in_use.gnss_white_sigma_m, 0.004);
  EXPECT_EQ(in_use.heading_source, NoiseSource::kMeasuredAtStops);
  EXPECT_EQ(in_use.heading_sigma_rad, 0.001);
}

TEST(WhiteNoiseChoiceTest, TurnedOffTakesTheConfigured) {
  SyntheticDrivePlan plan;
  plan.num_stops = 20;
  plan.stop_s = 0.3;
  solvers::SolverOptions configured;
  configured.use_measured_white_noise = false;
  const Measured m = MeasureAndChoose(MakeSyntheticPoseLog(plan, 14), configured);
  ASSERT_GT(m.on_drives.gnss_white_sigma_m, 0.0);
  EXPECT_EQ(m.in_use.gnss_source, NoiseSource::kConfigured);
  EXPECT_EQ(m.in_use.gnss_white_sigma_m, configured.gnss_white_sigma_m);
  EXPECT_EQ(m.in_use.heading_source, NoiseSource::kConfigured);
}

TEST(WhiteNoiseChoiceTest, SourcesHaveDistinctNames) {
  const std::set<std::string> names = {pipeline::NoiseSourceName(NoiseSource::kConfigured),
                                       pipeline::NoiseSourceName(NoiseSource::kMeasuredAtStops),
                                       pipeline::NoiseSourceName(NoiseSource::kMeasuredOnDrives)};
  EXPECT_EQ(names.size(), 3u);
  EXPECT_EQ(std::string(pipeline::NoiseSourceName(NoiseSource::kMeasuredOnDrives)),
            "measured on the drives");
}

pipeline::CalibrationResult CalibrateScenario(const std::string& scenario, uint64_t seed) {
  const fs::path dir = testing_support::SimulatedSession(
      testing_support::ShippedScenario(scenario), seed, scenario + std::to_string(seed));
  pipeline::CalibrateRequest request;
  request.session_path = dir.string();
  return pipeline::RunCalibration(request);
}

// The simulator's receiver: 3 mm white per axis on an RTK error that wanders 0.9 mm per fix,
// which the cubic over 1 s leaves at 2 % of σ (calib/drive_white_noise.h); heading 0.05°.
void ExpectTheSimulatedNoise(const pipeline::CalibrationResult& result, double gnss_m,
                             double heading_deg) {
  const pipeline::WhiteNoiseInUse& in_use = result.poses.white_noise;
  const calib::DriveWhiteNoise& drives = result.poses.drive_noise;
  EXPECT_EQ(in_use.gnss_source, NoiseSource::kMeasuredOnDrives);
  EXPECT_EQ(in_use.heading_source, NoiseSource::kMeasuredOnDrives);
  EXPECT_NEAR(in_use.gnss_white_sigma_m / gnss_m, 1.02,
              4.0 / std::sqrt(2.0 * drives.gnss_degrees_of_freedom));
  EXPECT_NEAR(in_use.heading_sigma_rad * kRadToDeg / heading_deg, 1.0,
              4.0 / std::sqrt(2.0 * drives.heading_degrees_of_freedom));
  const std::string summary = outputs::FormatSummary(result);
  EXPECT_NE(summary.find("measured on the drives ("), std::string::npos) << summary;
}

TEST(WhiteNoiseChoiceTest, ShortStopsSessionTakesTheDrivesMeasure) {
  // 0.3 s stops (no dwell), the logger's per-stream delays: before, the configured 5 mm.
  const pipeline::CalibrationResult result =
      CalibrateScenario("bench_lms291_delays_short_stops", 3);
  ASSERT_TRUE(result.solve.estimate.usable) << result.solve.estimate.message;
  EXPECT_EQ(result.poses.num_dwells, 0);
  ExpectTheSimulatedNoise(result, 0.003, 0.05);
}

TEST(WhiteNoiseChoiceTest, ContinuousSessionTakesTheDrivesMeasure) {
  const pipeline::CalibrationResult result = CalibrateScenario("bench_lms291_continuous", 3);
  ASSERT_TRUE(result.solve.estimate.usable) << result.solve.estimate.message;
  ExpectTheSimulatedNoise(result, 0.003, 0.05);
}

TEST(WhiteNoiseChoiceTest, StopAndGoSessionKeepsTheStopsMeasure) {
  // Stops of 4 s and drives of several seconds between them: both measure, the stops are taken.
  const pipeline::CalibrationResult result = CalibrateScenario("bench_lms291_delays_stopgo", 3);
  const pipeline::PoseResult& poses = result.poses;
  ASSERT_GT(poses.drive_noise.gnss_white_sigma_m, 0.0);  // the drives measure too
  EXPECT_EQ(poses.white_noise.gnss_source, NoiseSource::kMeasuredAtStops);
  EXPECT_EQ(poses.white_noise.gnss_white_sigma_m, poses.measured_noise.gnss_white_sigma_m);
  EXPECT_EQ(poses.white_noise.heading_source, NoiseSource::kMeasuredAtStops);
  EXPECT_EQ(poses.white_noise.heading_sigma_rad, poses.measured_noise.heading_sigma_rad);
  const std::string summary = outputs::FormatSummary(result);
  EXPECT_NE(summary.find("GNSS " + Format("%.4f", poses.measured_noise.gnss_white_sigma_m) +
                         " m measured at the stops ("),
            std::string::npos)
      << summary;
}

}  // namespace
}  // namespace wallcal
