// SPDX-License-Identifier: Apache-2.0
#include "pipeline/calibrate_options.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "common/angles.h"
#include "io/types.h"
#include "test/support/scratch_files.h"

namespace wallcal::pipeline {
namespace {

namespace fs = std::filesystem;
using io::InputError;

using testing_support::WriteFile;

// A folder in this process's scratch folder, removed when the process ends.
std::string Dir(const std::string& name) {
  return testing_support::ScratchFolder("calibrate_options_test_", name);
}

TEST(CalibrateOptionsTest, ReadsCalibrateOptionsInDegrees) {
  const std::string path = WriteFile(Dir("options") + "/calibrate.yaml", R"(
detector:
  min_inliers: 20
  wide_angle_gate_deg: 15
alignment:
  stationary_yaw_rate_deg_per_s: 0.5
  use_moving_scans: true
solver:
  heading_sigma_deg: 0.2
  min_heading_spread_deg: 30
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
}

TEST(CalibrateOptionsTest, RejectsBadCalibrateOptions) {
  const std::string dir = Dir("bad_options");
  auto error = [&dir](const std::string& yaml) {
    try {
      ReadCalibrateOptions(WriteFile(dir + "/calibrate.yaml", yaml));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("detector:\n  min_inliers: 20\n  wide_angle_gate_rad: 0.3\n")
                .find("calibrate.yaml:3: unknown key 'detector.wide_angle_gate_rad'"),
            std::string::npos);
  EXPECT_NE(
      error("solvers:\n  max_iterations: 3\n").find("calibrate.yaml:1: unknown key 'solvers'"),
      std::string::npos);
  EXPECT_NE(error("detector:\n  min_inliers: 0\n")
                .find("calibrate.yaml:2: detector.min_inliers must be >= 3, got 0"),
            std::string::npos);
  EXPECT_NE(
      error("detector:\n  min_inliers: many\n").find("calibrate.yaml:2: detector.min_inliers"),
      std::string::npos);
  EXPECT_NE(error("alignment:\n  use_moving_scans: maybe\n").find("true or false"),
            std::string::npos);
  EXPECT_NE(error("detector: 3\n").find("detector must be a map"), std::string::npos);
}

}  // namespace
}  // namespace wallcal::pipeline
