// Per-stream delays on a simulated session (issue 16): the logger stamps the GNSS sentences
// 35 ms + U(0, 10 ms) after their epochs, the heading 4 ms and the scans 13 ms after they were
// taken (configs/simulate/bench_lms291_delays_continuous.yaml: continuous driving, weaving
// towards and away from the wall, so that the velocity along the wall normal tells dt and the
// turns tell dt + δh). calibrate must map the GNSS epochs onto the logger clock and find the scanner
// clock offset and the heading's delay beside the mount, each with an honest σ.
//
// Truth on the logger clock (bench/accuracy_bench.cc TrueDelays): the epochs land at the mean
// GNSS delay L = 35 + 5 = 40 ms (L̂ as fitted: the fixes are placed there); the scanner offset is
// dt = L̂ − 13 ms ≈ +27 ms (true scan time = stamp + dt); the heading delay after the GNSS epochs
// is δh = 4 ms − L̂ ≈ −36 ms.
// Tolerances from the noise: the jitter's σ is 10/√12 = 2.9 ms, so the mean of ≥ 300 fixes is
// good to 0.17 ms (1 ms allowed: 6 σ). dt and δh: within 4 of their reported σ (a 1-in-16 000
// miss for a Gaussian error with an honest σ), and their σ small enough that the check means
// something: the scanner's within the 1 ms target; the heading's below 5 ms (a tenth of
// its 50 ms prior; on this session's turns it is 2.7 ms: heading noise 0.05° at 20 Hz over
// turn rates of a few °/s tells the delay no better). The mount: within 4 σ on each axis.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "common/angles.h"
#include "io/session_reader.h"
#include "pipeline/calibration.h"
#include "sim/simulated_session.h"
#include "sim/simulator.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

TEST(DelaysTest, RecoversGnssLatencyScannerOffsetAndHeadingDelayWithHonestSigma) {
  const io::SimulationConfig config = sim::WithDefaultWalls(io::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/bench_lms291_delays_continuous.yaml"));
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("wallcal_delays_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  sim::WriteSimulatedSession(config, 7, dir.string());
  pipeline::CalibrateRequest request;
  request.session_path = dir.string();
  request.config_path = std::string(WALLCAL_SOURCE_DIR) + "/bench/calibrate_matched_moving.yaml";
  const pipeline::CalibrationResult result = pipeline::RunCalibration(request, nullptr);
  fs::remove_all(dir);
  ASSERT_TRUE(result.estimate.usable) << result.estimate.message;

  const double gnss_s = config.gnss_latency_s + 0.5 * config.gnss_jitter_s;
  ASSERT_EQ(result.gnss_epochs.status, calib::EpochMappingStatus::kMapped);
  EXPECT_NEAR(result.gnss_epochs.offset_s, gnss_s, 1e-3);
  // Robust σ of U(0, 10 ms) is 3.7 ms.
  EXPECT_NEAR(result.gnss_epochs.jitter_s, 0.0037, 1e-3);

  const double mapped_s = result.gnss_epochs.offset_s;  // where the epochs were placed
  const double dt_truth_s = mapped_s - config.scanner_latency_s + config.scanner_time_offset_s;
  ASSERT_EQ(result.scanner_offset.status, pipeline::DelayStatus::kDetermined);
  EXPECT_LT(result.scanner_offset.sigma_s, 1e-3);
  EXPECT_LT(std::abs(result.scanner_offset.value_s - dt_truth_s), 4.0 * result.scanner_offset.sigma_s)
      << "dt " << result.scanner_offset.value_s << " ± " << result.scanner_offset.sigma_s;

  const double heading_truth_s = config.heading_latency_s - mapped_s;
  ASSERT_EQ(result.heading_delay.status, pipeline::DelayStatus::kDetermined);
  EXPECT_LT(result.heading_delay.sigma_s, 5e-3);
  EXPECT_LT(std::abs(result.heading_delay.value_s - heading_truth_s),
            4.0 * result.heading_delay.sigma_s)
      << "δh " << result.heading_delay.value_s << " ± " << result.heading_delay.sigma_s;

  const solvers::MountEstimate& e = result.estimate;
  const double error[3] = {e.mount.x_m - config.mount_x_m, e.mount.y_m - config.mount_y_m,
                           WrapAngle(e.mount.yaw_rad - config.mount_yaw_rad)};
  for (int a = 0; a < 3; ++a) {
    EXPECT_LT(std::abs(error[a]), 4.0 * std::sqrt(e.covariance(a, a))) << "axis " << a;
  }
}

TEST(DelaysTest, StationaryOnlySessionSaysTheHeadingDelayIsNotEstimated) {
  io::SimulationConfig config = sim::WithDefaultWalls(io::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/bench_lms291_delays_stopgo.yaml"));
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("wallcal_delays_still_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  sim::WriteSimulatedSession(config, 3, dir.string());
  pipeline::CalibrateRequest request;
  request.session_path = dir.string();
  request.config_path = std::string(WALLCAL_SOURCE_DIR) + "/bench/calibrate_matched_standing.yaml";
  const pipeline::CalibrationResult result = pipeline::RunCalibration(request, nullptr);
  fs::remove_all(dir);
  ASSERT_TRUE(result.estimate.usable) << result.estimate.message;
  EXPECT_EQ(result.gnss_epochs.status, calib::EpochMappingStatus::kMapped);
  EXPECT_EQ(result.heading_delay.status, pipeline::DelayStatus::kNotEstimated);
  EXPECT_EQ(result.scanner_offset.status, pipeline::DelayStatus::kNotEstimated);
}

}  // namespace
}  // namespace wallcal
