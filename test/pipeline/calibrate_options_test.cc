// SPDX-License-Identifier: Apache-2.0
#include "pipeline/calibrate_options.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "common/angles.h"
#include "io/types.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"

namespace wallcal::pipeline {
namespace {

namespace fs = std::filesystem;
using testing_support::ScratchFolder;
using io::InputError;

using testing_support::WriteFile;

TEST(CalibrateOptionsTest, ReadsCalibrateOptionsInDegrees) {
  const std::string path = WriteFile(ScratchFolder("options") + "/calibrate.yaml", R"(
detector:
  min_inliers: 20
  wide_angle_gate_deg: 15
alignment:
  stationary_yaw_rate_deg_per_s: 0.5
  use_moving_scans: true
solver:
  heading_sigma_deg: 0.2
  min_heading_spread_deg: 30
acceptance:
  relative_max_sigma_yaw_deg: 0.02
  relative_max_change_xy_m: 0.004
first_pass_max_scans: 500
)");
  const CalibrateOptions options = ReadCalibrateOptions(path);
  EXPECT_EQ(options.detector.min_inliers, 20);
  EXPECT_NEAR(options.detector.wide_angle_gate_rad, 15.0 * kDegToRad, 1e-15);
  EXPECT_DOUBLE_EQ(options.detector.inlier_band_m, calib::DetectorOptions().inlier_band_m);  // default
  EXPECT_NEAR(options.alignment.stationary_yaw_rate_rps, 0.5 * kDegToRad, 1e-15);
  EXPECT_TRUE(options.alignment.use_moving_scans);
  EXPECT_NEAR(options.solver.heading_sigma_rad, 0.2 * kDegToRad, 1e-15);
  EXPECT_NEAR(options.solver.min_heading_spread_rad, 30.0 * kDegToRad, 1e-15);
  EXPECT_EQ(options.first_pass_max_scans, 500);
  EXPECT_NEAR(options.acceptance.relative_max_sigma_yaw_rad, 0.02 * kDegToRad, 1e-15);
  EXPECT_DOUBLE_EQ(options.acceptance.relative_max_change_xy_m, 0.004);
  EXPECT_DOUBLE_EQ(options.acceptance.relative_max_sigma_xy_m,
                   AcceptanceOptions().relative_max_sigma_xy_m);  // default
}

TEST(CalibrateOptionsTest, RejectsBadCalibrateOptions) {
  const std::string dir = ScratchFolder("bad_options");
  // Each file and what its message says (file:line first where the key has a line).
  const std::pair<const char*, const char*> kBad[] = {
      {"detector:\n  min_inliers: 20\n  wide_angle_gate_rad: 0.3\n",
       "calibrate.yaml:3: unknown key 'detector.wide_angle_gate_rad'"},
      {"solvers:\n  max_iterations: 3\n", "calibrate.yaml:1: unknown key 'solvers'"},
      {"detector:\n  min_inliers: 0\n", "calibrate.yaml:2: detector.min_inliers must be >= 3, got 0"},
      {"detector:\n  min_inliers: many\n", "calibrate.yaml:2: detector.min_inliers"},
      {"alignment:\n  use_moving_scans: maybe\n", "true or false"},
      {"detector: 3\n", "detector must be a map"},
      // Each key's check, named by its key with the value as the file spells it.
      {"solver:\n  max_sigma_yaw_deg: 0\n",
       "calibrate.yaml:2: solver.max_sigma_yaw_deg must be in (0, 180], got 0"},
      {"solver:\n  heading_drift_sigma_deg_per_h: -2\n",
       "calibrate.yaml:2: solver.heading_drift_sigma_deg_per_h must be >= 0, got -2"},
      {"detector:\n  hough_rho_step_m: 2\n",
       "calibrate.yaml:2: detector.hough_rho_step_m must be in [0.0001, 1], got 2"},
      {"acceptance:\n  max_change_sigmas: -3\n",
       "calibrate.yaml:2: acceptance.max_change_sigmas must be > 0, got -3"},
      {"alignment:\n  min_dwell_s: -1\n", "calibrate.yaml:2: alignment.min_dwell_s must be >= 0"},
      {"first_pass_max_scans: 0\n", "calibrate.yaml:1: first_pass_max_scans must be >= 1, got 0"},
      // A check across keys: the accumulator the steps ask for.
      {"detector:\n  hough_rho_step_m: 0.0001\n  hough_theta_step_deg: 0.01\n",
       "calibrate.yaml:2: detector.hough_rho_step_m must be large enough"},
      {"acceptance:\n  relative_max_sigma_xy_m: 0\n",
       "calibrate.yaml:2: acceptance.relative_max_sigma_xy_m must be > 0, got 0"},
  };
  testing_support::ExpectEachThrows<InputError>(kBad, [&dir](const char* yaml) {
    ReadCalibrateOptions(WriteFile(dir + "/calibrate.yaml", yaml));
  });
}

}  // namespace
}  // namespace wallcal::pipeline
