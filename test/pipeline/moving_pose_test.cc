// SPDX-License-Identifier: Apache-2.0
// Scans taken while driving: their pose uncertainty in the observation covariance
// (solvers/mount_problem.h MovingPoseCovariance, MovingScansPerGnssFix), and their use by
// stop-and-go sessions (alignment.moving_scans_in_stop_and_go) when the scanner clock offset is
// determined, σ honest against the simulator's truth.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/angles.h"
#include "calib/observation.h"
#include "solvers/solver_options.h"
#include "sim/simulation_config.h"
#include "io/config/session_reader.h"
#include "outputs/summary.h"
#include "pipeline/calibration.h"
#include "sim/simulated_session.h"
#include "sim/simulator.h"
#include "solvers/mount_problem.h"
#include "test/support/scratch_dir.h"
#include "test/support/simulated_sessions.h"
#include "test/support/synthetic_fixtures.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

// A wall along y = 10 (normal +y) seen by a vehicle near the origin heading north.
using testing_support::NorthWall;

calib::WallObservation At(bool standing, const Eigen::Vector2d& velocity, double yaw_rate) {
  calib::WallObservation o;
  o.rho_m = 7.5;
  o.theta_rad = 0.0;
  o.sigma_rho_m = 0.002;
  o.sigma_theta_rad = 0.0005;
  o.pose.stamp_s = 100.0;
  o.pose.yaw_rad = 0.5 * kPi;
  o.pose.stationary = standing;
  o.pose.segment = standing ? 0 : 7;
  o.pose.gnss_segment = 3;
  o.pose.velocity_local_mps = velocity;
  o.pose.yaw_rate_rps = yaw_rate;
  o.pose.gnss_period_s = 0.1;
  return o;
}

solvers::SolverOptions Options() {
  solvers::SolverOptions options;
  options.gnss_white_sigma_m = 0.003;
  options.heading_sigma_rad = 0.0009;
  options.moving_timing_sigma_s = 0.002;
  return options;
}

TEST(MovingPoseTest, StandingScanGetsNoPoseTerm) {
  const calib::WallObservation o = At(true, Eigen::Vector2d(1.0, 1.0), 0.2);
  EXPECT_EQ(solvers::MovingPoseCovariance(o, Eigen::Vector2d(0.0, 1.0), 0.5, Options()),
            Eigen::Matrix2d::Zero());
}

TEST(MovingPoseTest, TimingMovesRhoBySpeedAlongTheNormal) {
  const solvers::SolverOptions options = Options();
  // 1 m/s towards the wall, no turn: rho variance (1 m/s × 2 ms)² = 4e-6 m², theta untouched.
  const Eigen::Matrix2d towards = solvers::MovingPoseCovariance(
      At(false, Eigen::Vector2d(0.0, 1.0), 0.0), Eigen::Vector2d(0.0, 1.0), 0.0, options);
  EXPECT_NEAR(towards(0, 0), 4e-6, 1e-12);
  EXPECT_NEAR(towards(1, 1), 0.0, 1e-15);
  // 1 m/s along the wall: nothing in rho from the timing (and no curve: no interpolation).
  const Eigen::Matrix2d along = solvers::MovingPoseCovariance(
      At(false, Eigen::Vector2d(1.0, 0.0), 0.0), Eigen::Vector2d(0.0, 1.0), 0.0, options);
  EXPECT_NEAR(along(0, 0), 0.0, 1e-15);
  // Turning at 0.2 rad/s with a 2.5 m along-wall lever: theta (0.2 × 2 ms)², rho ℓ² times that,
  // plus the interpolation on the curve (|v||ω| T² / (2√30))² at 1 m/s, T = 0.1 s.
  const Eigen::Matrix2d turning = solvers::MovingPoseCovariance(
      At(false, Eigen::Vector2d(1.0, 0.0), 0.2), Eigen::Vector2d(0.0, 1.0), 2.5, options);
  const double heading_var = std::pow(0.2 * 0.002, 2);
  const double interp_m = 0.2 * 0.01 / (2.0 * std::sqrt(30.0));
  EXPECT_NEAR(turning(1, 1), heading_var, 1e-15);
  EXPECT_NEAR(turning(0, 1), 2.5 * heading_var, 1e-15);
  EXPECT_NEAR(turning(0, 0), 2.5 * 2.5 * heading_var + interp_m * interp_m, 1e-15);
}

TEST(MovingPoseTest, MovingScanWeighsLessThanStandingOne) {
  const solvers::SolverOptions options = Options();
  const calib::WallGeometry wall = NorthWall();
  const solvers::Mount lever{2.5, 0.0, 0.0};
  // Heading east along the wall: the 2.5 m forward lever lies along it (ℓ = 2.5 m).
  calib::WallObservation standing = At(true, Eigen::Vector2d::Zero(), 0.0);
  calib::WallObservation moving = At(false, Eigen::Vector2d(0.6, 0.8), 0.1);
  standing.pose.yaw_rad = moving.pose.yaw_rad = 0.0;
  const Eigen::Matrix2d c_standing =
      solvers::ObservationCovariance(standing, wall, options, lever, 0.015, 1.5);
  const Eigen::Matrix2d c_moving =
      solvers::ObservationCovariance(moving, wall, options, lever, 0.015, 1.5);
  // Standing: line fit + GNSS white only (the dwell heading is a parameter, not noise here).
  EXPECT_NEAR(c_standing(0, 0), 0.002 * 0.002 + 0.003 * 0.003, 1e-12);
  // Moving: GNSS white × 1.5 scans per fix, its own heading's white noise through the lever
  // (ℓ² σ_h²), and the pose terms.
  const Eigen::Matrix2d pose = solvers::MovingPoseCovariance(
      moving, Eigen::Vector2d(0.0, 1.0), 2.5, options);
  EXPECT_GT(pose(0, 0), std::pow(0.8 * 0.002, 2));  // at least the speed towards the wall
  EXPECT_NEAR(c_moving(0, 0),
              0.002 * 0.002 + 1.5 * 0.003 * 0.003 + 2.5 * 2.5 * 0.0009 * 0.0009 + pose(0, 0),
              1e-10);
  EXPECT_NEAR(c_moving(1, 1), 0.0005 * 0.0005 + 0.0009 * 0.0009 + pose(1, 1), 1e-12);
  EXPECT_NEAR(c_moving(0, 1), 2.5 * 0.0009 * 0.0009 + pose(0, 1), 1e-12);
  // Its information in rho is about half the standing scan's here.
  EXPECT_LT(1.0 / c_moving(0, 0), 0.6 / c_standing(0, 0));
}

TEST(MovingPoseTest, ScansPerFixFromTheMovingScansSpacing) {
  std::vector<calib::WallObservation> obs;
  for (int k = 0; k < 30; ++k) {  // 15 Hz moving scans, 10 Hz GNSS: 1.5 scans per fix
    calib::WallObservation o = At(false, Eigen::Vector2d(0.0, 1.0), 0.0);
    o.pose.stamp_s = 100.0 + k / 15.0;
    obs.push_back(o);
  }
  for (int k = 0; k < 30; ++k) {  // standing scans at 75 Hz do not count
    calib::WallObservation o = At(true, Eigen::Vector2d::Zero(), 0.0);
    o.pose.stamp_s = 50.0 + k / 75.0;
    obs.push_back(o);
  }
  EXPECT_NEAR(solvers::MovingScansPerGnssFix(obs), 1.5, 1e-9);
  obs.resize(0);
  EXPECT_EQ(solvers::MovingScansPerGnssFix(obs), 1.0);
}

// A stop-and-go session calibrated with the drives (the solver's noise σ set to the
// simulator's, as bench/calibrate_matched.yaml): the drives between the stops are used, the
// scanner clock offset is estimated, σ shrinks against the standing scans alone, and the
// errors stay within 3.5 σ (with an honest σ, |error| > 3.5 σ has probability 5e-4 per axis:
// 3 axes × 3 seeds, a false failure about once in 700 runs of this test).
// The heading stream's delay is held at 0 (the simulation has none): with it free, the drives of
// a one-wall stop-and-go session, which run along the wall, cannot tell it from the scanner clock
// offset (docs/time-alignment.md), the offset is not determined and the drives are dropped.
constexpr char kMatched[] =
    "solver:\n  gnss_white_sigma_m: 0.003\n  heading_sigma_deg: 0.05\n"
    "  control_sigma_m: 0.015\n  total_station_sigma_m: 0.003\n  heading_delay_sigma_s: 0\n";

constexpr char kDrives[] = "alignment:\n  moving_scans_in_stop_and_go: true\n";

pipeline::CalibrationResult Calibrate(const fs::path& dir, const std::string& extra,
                                      solvers::Method method = solvers::Method::kCeres) {
  pipeline::CalibrateRequest request;
  request.session_path = dir.string();
  request.config_path = (dir / "calibrate.yaml").string();
  std::ofstream(request.config_path) << kMatched << extra;
  request.method = method;
  return pipeline::RunCalibration(request);
}

TEST(MovingPoseTest, DrivesTimingIsWhatTheirPosesNeed) {
  // The clock offset dt and the heading delay δh each known to 40 ms but their sum to 1 ms
  // (correlation −0.9997: drives along one wall).
  const double s = 0.04, rho = -0.9997;
  Eigen::Matrix2d time_covariance;
  time_covariance << s * s, rho * s * s, rho * s * s, s * s;
  const double sum_sigma = std::sqrt(2.0 * s * s * (1.0 + rho));
  const solvers::Mount mount{2.57, 0.05, 0.05};
  const std::vector<calib::WallGeometry> walls = {NorthWall()};
  // Turning while driving along the wall: only dt + δh moves the pose.
  const std::vector<calib::WallObservation> turning = {At(false, {1.0, 0.0}, 0.1)};
  EXPECT_NEAR(solvers::DrivesTimingSigma(turning, walls, mount, time_covariance), sum_sigma,
              1e-9);
  // Driving straight at the wall: dt itself.
  const std::vector<calib::WallObservation> towards = {At(false, {0.0, 1.0}, 0.0)};
  EXPECT_NEAR(solvers::DrivesTimingSigma(towards, walls, mount, time_covariance), s, 1e-9);
  // Standing scans need no timing.
  const std::vector<calib::WallObservation> standing = {At(true, {0.0, 0.0}, 0.0)};
  EXPECT_EQ(solvers::DrivesTimingSigma(standing, walls, mount, time_covariance), 0.0);
}

TEST(MovingPoseTest, DrivesAtASecondWallLeaveNoBias) {
  // Two walls, the drives heading along the first and so straight at the second (whose lines
  // then see every acceleration of the drive), the simulator's pose and survey noise off: the
  // only errors left are the line fits'. With the drives' poses on straight chords between the
  // 10 Hz fixes (off by a·T²/8 = 4 mm, one sign over half a drive) x came out −20 mm here, the
  // same on every seed; their line fits alone scatter x by about 1 mm.
  const sim::SimulationConfig config = testing_support::TwoWallsWithOnlyLineFitErrors();
  const fs::path dir = testing_support::SimulatedSession(config, 5, "two_walls");
  // The solver's GNSS model left at an RTK receiver's (its slices free to follow a pattern),
  // its white noise the receiver's configured one.
  const std::string rtk = "  use_gst_sigma: false\n  gnss_bias_sigma_m: 0.03\n";
  const pipeline::CalibrationResult result =
      Calibrate(dir, rtk + "  use_measured_white_noise: false\n" + kDrives);
  ASSERT_TRUE(result.solve.estimate.usable) << result.solve.estimate.message;
  EXPECT_GT(result.finish.coverage.scans_used_moving, 100);
  EXPECT_LT(std::abs(result.solve.estimate.mount.x_m - config.mount_x_m), 0.004);
  EXPECT_LT(std::abs(result.solve.estimate.mount.y_m - config.mount_y_m), 0.004);
  // By default the white noise is the stops' measure, here the logs' number format alone (tens
  // of µm): the drives then count with their line fits' σ, and x scatters over seeds by about
  // its σ (8.9 mm; 2.3 mm with the configured noise, docs/notes.md). Still no bias beyond it.
  const pipeline::CalibrationResult measured = Calibrate(dir, rtk + kDrives);
  ASSERT_TRUE(measured.solve.estimate.usable) << measured.solve.estimate.message;
  EXPECT_EQ(measured.poses.white_noise.gnss_source, pipeline::NoiseSource::kMeasuredAtStops);
  EXPECT_LT(measured.poses.white_noise.gnss_white_sigma_m, 1e-4);
  EXPECT_GT(measured.finish.coverage.scans_used_moving, 100);
  const Eigen::Matrix3d& c = measured.solve.estimate.covariance;
  EXPECT_LT(std::abs(measured.solve.estimate.mount.x_m - config.mount_x_m),
            3.0 * std::sqrt(c(0, 0)));
  EXPECT_LT(std::abs(measured.solve.estimate.mount.y_m - config.mount_y_m),
            3.0 * std::sqrt(c(1, 1)));
}

TEST(MovingPoseTest, StopAndGoUsesTheDrivesWithAnHonestSigma) {
  sim::SimulationConfig config = sim::WithDefaultWalls(sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/bench_lms291_stopgo.yaml"));
  config.scanner_time_offset_s = 0.04;  // the drives must find it
  const double truth[3] = {config.mount_x_m, config.mount_y_m, config.mount_yaw_rad};
  for (uint64_t seed : {11u, 12u, 13u}) {
    const testing_support::ScratchDir scratch("wallcal_moving_pose_");
    const fs::path dir = scratch.path() / ("seed" + std::to_string(seed));
    sim::WriteSimulatedSession(config, seed, dir.string());
    const pipeline::CalibrationResult with = Calibrate(dir, kDrives);
    ASSERT_TRUE(with.solve.estimate.usable) << with.solve.estimate.message;
    EXPECT_GT(with.finish.coverage.scans_used_moving, 50) << "seed " << seed;
    EXPECT_GT(with.finish.coverage.scans_used - with.finish.coverage.scans_used_moving, 300)
        << "seed " << seed;
    ASSERT_TRUE(with.solve.estimate.time_offset_estimated);
    // The offset: within 4 of its σ (about 1 ms) of the truth.
    EXPECT_NEAR(with.solve.scanner_offset.value_s, config.scanner_time_offset_s,
                4.0 * with.solve.scanner_offset.sigma_s);
    EXPECT_LT(with.solve.scanner_offset.sigma_s, 0.005);
    const double est[3] = {with.solve.estimate.mount.x_m, with.solve.estimate.mount.y_m,
                           with.solve.estimate.mount.yaw_rad};
    for (int a = 0; a < 3; ++a) {
      const double sigma = std::sqrt(with.solve.estimate.covariance(a, a));
      EXPECT_LT(std::abs(est[a] - truth[a]), 3.5 * sigma) << "seed " << seed << " axis " << a;
    }
    const std::string summary = outputs::FormatSummary(with);
    EXPECT_NE(summary.find(std::to_string(with.finish.coverage.scans_used_moving) + " moving"),
              std::string::npos)
        << summary;

    // Standing scans only: less information, so a larger σ in x and y (the all-data bound of
    // this scenario is 8 % / 16 % below the standing-scans one, docs/results.md).
    const pipeline::CalibrationResult without =
        Calibrate(dir, "alignment:\n  moving_scans_in_stop_and_go: false\n");
    ASSERT_TRUE(without.solve.estimate.usable) << without.solve.estimate.message;
    EXPECT_EQ(without.finish.coverage.scans_used_moving, 0);
    EXPECT_LT(with.solve.estimate.covariance(0, 0), without.solve.estimate.covariance(0, 0));
    EXPECT_LT(with.solve.estimate.covariance(1, 1), without.solve.estimate.covariance(1, 1));
  }
}

TEST(MovingPoseTest, DrivesAreDroppedWhenTheOffsetIsNotDetermined) {
  const fs::path dir = testing_support::SimulatedSession(
      testing_support::ShippedScenario("bench_lms291_stopgo"), 21, "drop");
  // No offset σ is this small: the drives go, with a warning, and the counts say so.
  const pipeline::CalibrationResult strict =
      Calibrate(dir, std::string(kDrives) + "  moving_max_time_offset_sigma_s: 0.000001\n");
  ASSERT_TRUE(strict.solve.estimate.usable) << strict.solve.estimate.message;
  EXPECT_EQ(strict.finish.coverage.scans_used_moving, 0);
  EXPECT_GT(strict.ScansSkipped().at(calib::ScanSkip::kVehicleMoving), 50);
  bool warned = false;
  for (const pipeline::Warning& w : strict.AllWarnings()) {
    warned = warned || w.kind == pipeline::WarningKind::kDrivesNotUsed;
  }
  EXPECT_TRUE(warned);
  // barawid estimates no clock offset: standing scans only.
  const pipeline::CalibrationResult barawid =
      Calibrate(dir, kDrives, solvers::Method::kBarawid);
  ASSERT_TRUE(barawid.solve.estimate.usable) << barawid.solve.estimate.message;
  EXPECT_EQ(barawid.finish.coverage.scans_used_moving, 0);
}

}  // namespace
}  // namespace wallcal
