// SPDX-License-Identifier: Apache-2.0
#include "calib/drive_white_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "calib/white_noise.h"
#include "common/angles.h"
#include "test/support/synthetic_pose_logs.h"

namespace wallcal::calib {
namespace {

using testing_support::MakeSyntheticPoseLog;
using testing_support::SyntheticDrivePlan;
using testing_support::SyntheticPoseLog;

// A pooled variance over `dof` degrees of freedom has a relative standard error of √(2/dof),
// its square root half that: 1/√(2·dof). The tests allow four of them.
double Tolerance(int dof) { return 4.0 / std::sqrt(2.0 * dof); }

constexpr int kGnssWindowDof = 2 * (kDriveWindowSamples - kDriveFitDegree - 1);
constexpr int kHeadingWindowDof = kDriveWindowSamples - kDriveFitDegree - 1;

TEST(DriveWhiteNoiseTest, RecoversTheWhiteNoiseOfASmoothCurvedDrive) {
  const SyntheticDrivePlan plan;  // 300 s on the circle, 0.4..1.2 m/s, yaw through ±π
  const SyntheticPoseLog log = MakeSyntheticPoseLog(plan, 1);
  const DriveWhiteNoise noise = MeasureDriveWhiteNoise(log.positions, log.yaws, log.dwells);
  // 3000 fixes: 272 windows of 11; 6000 headings: 545 windows.
  EXPECT_EQ(noise.gnss_windows_used + noise.gnss_windows_dropped, 272);
  EXPECT_EQ(noise.heading_windows_used + noise.heading_windows_dropped, 545);
  EXPECT_EQ(noise.gnss_degrees_of_freedom, noise.gnss_windows_used * kGnssWindowDof);
  EXPECT_EQ(noise.heading_degrees_of_freedom, noise.heading_windows_used * kHeadingWindowDof);
  // Of pure noise, a window is beyond 3× the median once in 4 000 (GNSS) or 120 (heading) times.
  EXPECT_LE(noise.gnss_windows_dropped, 2);
  EXPECT_LE(noise.heading_windows_dropped, 15);
  EXPECT_NEAR(noise.gnss_white_sigma_m / plan.gnss_white_sigma_m, 1.0,
              Tolerance(noise.gnss_degrees_of_freedom));
  EXPECT_NEAR(noise.heading_sigma_rad / plan.heading_sigma_rad, 1.0,
              Tolerance(noise.heading_degrees_of_freedom));
}

TEST(DriveWhiteNoiseTest, UnbiasedOverManyDrives) {
  // The cut at 3× the median takes the tail of pure noise too (for the headings' 7 degrees of
  // freedom a window, 1.7 % of the variance); the pooled variance is scaled back for it. Over
  // 400 drives of 60 s the mean variance ratio is known to √(2 / Σ dof): 0.26 % for the headings.
  SyntheticDrivePlan plan;
  plan.duration_s = 60.0;
  double gnss_sum = 0.0, heading_sum = 0.0;
  int gnss_dof = 0, heading_dof = 0;
  constexpr int kDrives = 400;
  for (uint32_t seed = 1; seed <= kDrives; ++seed) {
    const SyntheticPoseLog log = MakeSyntheticPoseLog(plan, 100 + seed);
    const DriveWhiteNoise noise = MeasureDriveWhiteNoise(log.positions, log.yaws, log.dwells);
    gnss_sum += std::pow(noise.gnss_white_sigma_m / plan.gnss_white_sigma_m, 2);
    heading_sum += std::pow(noise.heading_sigma_rad / plan.heading_sigma_rad, 2);
    gnss_dof += noise.gnss_degrees_of_freedom;
    heading_dof += noise.heading_degrees_of_freedom;
  }
  EXPECT_NEAR(gnss_sum / kDrives, 1.0, 4.0 * std::sqrt(2.0 / gnss_dof));
  EXPECT_NEAR(heading_sum / kDrives, 1.0, 4.0 * std::sqrt(2.0 / heading_dof));
}

TEST(DriveWhiteNoiseTest, HeadingsTurningThroughPlusMinusPi) {
  // Spinning at 180°/s for 30 s: through ±π every 2 s, in one window of four. No window is lost
  // to the wrap (a window of pure noise is beyond the cut once in 120).
  constexpr double kSigmaRad = 0.05 * kDegToRad;
  std::mt19937 rng(9);
  std::normal_distribution<double> noise_rad(0.0, kSigmaRad);
  std::vector<YawSample> yaws;
  for (int j = 0; j < 600; ++j) {
    const double t_s = j / 20.0;
    yaws.push_back({t_s, WrapAngle(kPi * t_s + noise_rad(rng))});
  }
  const DriveWhiteNoise noise = MeasureDriveWhiteNoise({}, yaws, {});
  EXPECT_EQ(noise.heading_windows_used + noise.heading_windows_dropped, 54);
  EXPECT_LE(noise.heading_windows_dropped, 3);
  EXPECT_NEAR(noise.heading_sigma_rad / kSigmaRad, 1.0,
              Tolerance(noise.heading_degrees_of_freedom));
}

TEST(DriveWhiteNoiseTest, LeavesTheDwellsOut) {
  // Stop and go: 20 stops of 4 s listed as dwells, whose samples carry ten times the noise. The
  // drives' measure sees none of them.
  SyntheticDrivePlan plan;
  plan.num_stops = 20;
  SyntheticPoseLog log = MakeSyntheticPoseLog(plan, 2);
  const SyntheticPoseLog loud = [&] {
    SyntheticDrivePlan p = plan;
    p.gnss_white_sigma_m *= 10.0;
    p.heading_sigma_rad *= 10.0;
    return MakeSyntheticPoseLog(p, 3);
  }();
  const auto in_dwell = [&](double t_s) {
    for (const Dwell& d : log.dwells)
      if (t_s >= d.start_s && t_s <= d.end_s) return true;
    return false;
  };
  for (size_t i = 0; i < log.positions.size(); ++i)
    if (in_dwell(log.positions[i].stamp_s)) log.positions[i] = loud.positions[i];
  for (size_t i = 0; i < log.yaws.size(); ++i)
    if (in_dwell(log.yaws[i].stamp_s)) log.yaws[i] = loud.yaws[i];
  const DriveWhiteNoise noise = MeasureDriveWhiteNoise(log.positions, log.yaws, log.dwells);
  // Each drive: 80 fixes (7 windows of 11) and 161 headings, from the one after the stop's last
  // fix (14 windows).
  EXPECT_EQ(noise.gnss_windows_used + noise.gnss_windows_dropped, 20 * 7);
  EXPECT_EQ(noise.heading_windows_used + noise.heading_windows_dropped, 20 * 14);
  EXPECT_NEAR(noise.gnss_white_sigma_m / plan.gnss_white_sigma_m, 1.0,
              Tolerance(noise.gnss_degrees_of_freedom));
  EXPECT_NEAR(noise.heading_sigma_rad / plan.heading_sigma_rad, 1.0,
              Tolerance(noise.heading_degrees_of_freedom));
  // The stops' own measure is theirs.
  const MeasuredWhiteNoise at_stops = MeasureWhiteNoise(log.positions, log.yaws, log.dwells);
  EXPECT_NEAR(at_stops.gnss_white_sigma_m / plan.gnss_white_sigma_m, 10.0, 1.0);
}

TEST(DriveWhiteNoiseTest, ShortStopsInsideTheWindowsAreNotNoise) {
  // Stops of 0.3 s, not dwells: each drive starts and ends with a step of its acceleration
  // (0.39 m/s² here) inside a window. A cubic over 1 s leaves the step's residuals at a few
  // tenths of a millimetre; the few windows far beyond the rest are left out.
  SyntheticDrivePlan plan;
  plan.num_stops = 30;
  plan.stop_s = 0.3;
  plan.stops_are_dwells = false;
  const SyntheticPoseLog log = MakeSyntheticPoseLog(plan, 4);
  const DriveWhiteNoise noise = MeasureDriveWhiteNoise(log.positions, log.yaws, log.dwells);
  EXPECT_NEAR(noise.gnss_white_sigma_m / plan.gnss_white_sigma_m, 1.0,
              Tolerance(noise.gnss_degrees_of_freedom));
  EXPECT_NEAR(noise.heading_sigma_rad / plan.heading_sigma_rad, 1.0,
              Tolerance(noise.heading_degrees_of_freedom));
}

TEST(DriveWhiteNoiseTest, DropsTheWindowsWhereTheMotionIsNotSmooth) {
  // Ten jolts: a fix 5 cm off the path (ten times the noise in its window's scatter). Each
  // window that holds one is left out, and the estimate is the white noise's.
  const SyntheticDrivePlan plan;
  SyntheticPoseLog log = MakeSyntheticPoseLog(plan, 5);
  for (size_t k = 0; k < 10; ++k) log.positions[150 + 275 * k].p_local_m.x() += 0.05;
  const DriveWhiteNoise noise = MeasureDriveWhiteNoise(log.positions, log.yaws, log.dwells);
  EXPECT_GE(noise.gnss_windows_dropped, 10);
  EXPECT_LE(noise.gnss_windows_dropped, 12);
  EXPECT_NEAR(noise.gnss_white_sigma_m / plan.gnss_white_sigma_m, 1.0,
              Tolerance(noise.gnss_degrees_of_freedom));
}

TEST(DriveWhiteNoiseTest, RunsEndAtGaps) {
  // 105 fixes, 3 s without any, 105 fixes: 9 windows on each side of the gap (a window across
  // it would make 19).
  SyntheticDrivePlan plan;
  plan.duration_s = 24.0;
  SyntheticPoseLog log = MakeSyntheticPoseLog(plan, 6);
  log.positions.erase(log.positions.begin() + 105, log.positions.begin() + 135);
  ASSERT_EQ(log.positions.size(), 210u);
  const DriveWhiteNoise noise = MeasureDriveWhiteNoise(log.positions, log.yaws, log.dwells);
  EXPECT_EQ(noise.gnss_windows_used + noise.gnss_windows_dropped, 18);
}

TEST(DriveWhiteNoiseTest, StampJitterCountsAsSpeedTimesJitter) {
  // Fixes stamped up to 40 ms late (uniform) at a steady 0.8 m/s: the position is off by the
  // speed times the stamp error, a white noise of variance v²·J²/12 per fix, half of it on each
  // axis on a circle. A moving scan's pose sees the same error: it is noise at the fixes.
  SyntheticDrivePlan plan;
  plan.wobble_rad_per_s = 0.0;
  plan.gnss_jitter_s = 0.04;
  const SyntheticPoseLog log = MakeSyntheticPoseLog(plan, 7);
  const double v_mps = 0.8;
  const double expected_m =
      std::sqrt(plan.gnss_white_sigma_m * plan.gnss_white_sigma_m +
                0.5 * v_mps * v_mps * plan.gnss_jitter_s * plan.gnss_jitter_s / 12.0);
  ASSERT_GT(expected_m, 2.0 * plan.gnss_white_sigma_m);  // √(3² + 6.5²) = 7.2 mm
  const DriveWhiteNoise noise = MeasureDriveWhiteNoise(log.positions, log.yaws, log.dwells);
  EXPECT_NEAR(noise.gnss_white_sigma_m / expected_m, 1.0,
              Tolerance(noise.gnss_degrees_of_freedom));
}

TEST(DriveWhiteNoiseTest, TooShortADriveGivesNoEstimate) {
  // 5 s: 4 windows of fixes (56 degrees of freedom), 9 of headings (63).
  SyntheticDrivePlan plan;
  plan.duration_s = 5.0;
  const SyntheticPoseLog log = MakeSyntheticPoseLog(plan, 8);
  const DriveWhiteNoise noise = MeasureDriveWhiteNoise(log.positions, log.yaws, log.dwells);
  EXPECT_EQ(noise.gnss_degrees_of_freedom, 4 * kGnssWindowDof);
  EXPECT_LT(noise.gnss_degrees_of_freedom, kMinWhiteNoiseDegreesOfFreedom);
  EXPECT_EQ(noise.gnss_white_sigma_m, 0.0);
  EXPECT_EQ(noise.heading_degrees_of_freedom, 9 * kHeadingWindowDof);
  EXPECT_EQ(noise.heading_sigma_rad, 0.0);
}

}  // namespace
}  // namespace wallcal::calib
