// SPDX-License-Identifier: Apache-2.0
// The joint adjustment's estimate of each unit's range scale is not pulled by the lines' own
// noise (solvers/unit_scale_reference.h). Two URG-04LX units whose ranges are exactly the
// preset's, in a session whose only noise is the scanners' range noise (no GNSS, heading or
// survey error): their scales are 0, and the relative transform is the truth's.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "pipeline/multi_scanner.h"
#include "sim/simulated_session.h"
#include "sim/simulation_config.h"
#include "solvers/joint_mounts.h"
#include "test/support/scratch_dir.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

TEST(JointUnitScaleTest, LinesNoiseDoesNotReadAsACommonScale) {
  const std::string source = WALLCAL_SOURCE_DIR;
  sim::SimulationConfig config =
      sim::ReadSimulationConfig(source + "/configs/simulate/bench_two_scanners_urg04lx.yaml");
  config.draw_unit_range_models = false;
  config.gnss_bias_sigma_m = 0.0;
  config.gnss_white_sigma_m = 0.0;
  config.heading_white_sigma_rad = 0.0;
  config.heading_drift_rad_per_s = 0.0;
  config.total_station_sigma_m = 0.0;
  config.control_sigma_m = 0.0;
  config.mixed_pixel_probability = 0.0;
  config.scanner_jitter_s = 0.0;
  config.lost_scan_fraction = 0.0;
  const testing_support::ScratchDir scratch("wallcal_unit_scale_");
  const fs::path dir = scratch.path() / "session";
  sim::WriteSimulatedSession(config, 1, dir.string());

  pipeline::CalibrateRequest request;
  request.session_path = dir.string();
  // The benchmark's options: the GNSS and heading noise its model assumes are the benchmark's.
  request.config_path = source + "/bench/calibrate_matched_scan_jitter.yaml";
  const pipeline::SeveralScannersResult result = pipeline::RunSeveralScanners(request, false);
  ASSERT_EQ(result.outcome, pipeline::SeveralOutcome::kAll) << result.message;
  // With the scan's measured rho as the scale's regressor both scales came back +0.005 (the
  // preset's 1σ) on every seed, spread ±0.0005, and the relative transform 0.5 % short (x, y
  // +0.7–1.2, +1.5–2.0 mm); with the references, within ±0.0005 and 0.35 mm.
  ASSERT_EQ(result.joint.unit_ranges.size(), 2u);
  for (const auto& unit : result.joint.unit_ranges) {
    ASSERT_TRUE(unit.estimated);
    EXPECT_LT(std::abs(unit.scale), 0.0015);
  }
  const auto mount_of = [&config](size_t k) {
    const sim::SimulationConfig one = sim::ForScanner(config, k);
    return solvers::Mount{one.mount_x_m, one.mount_y_m, one.mount_yaw_rad};
  };
  const solvers::Mount left = mount_of(0), right = mount_of(1);
  const solvers::Mount truth =
      solvers::RelativeMountOf(left, right, Eigen::Matrix<double, 6, 6>::Zero()).from_T_to;
  ASSERT_EQ(result.relative.size(), 1u);
  const solvers::Mount& estimate = result.relative.front().mount.from_T_to;
  EXPECT_NEAR(estimate.x_m, truth.x_m, 0.6e-3);
  EXPECT_NEAR(estimate.y_m, truth.y_m, 0.6e-3);
}

}  // namespace
}  // namespace wallcal
