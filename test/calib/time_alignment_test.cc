// SPDX-License-Identifier: Apache-2.0
#include "calib/time_alignment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "calib/geodesy.h"
#include "common/angles.h"

namespace wallcal::calib {
namespace {
std::vector<PositionSample> Positions(double t0, double t1, double rate_hz,
                                      Eigen::Vector2d (*at)(double)) {
  std::vector<PositionSample> out;
  const int n = static_cast<int>(std::round((t1 - t0) * rate_hz));
  for (int i = 0; i <= n; ++i) {
    const double t = t0 + i / rate_hz;
    out.push_back(PositionSample{t, at(t), 0.01 + 0.001 * t});
  }
  return out;
}

std::vector<YawSample> Yaws(double t0, double t1, double rate_hz, double (*at)(double)) {
  std::vector<YawSample> out;
  const int n = static_cast<int>(std::round((t1 - t0) * rate_hz));
  for (int i = 0; i <= n; ++i) {
    const double t = t0 + i / rate_hz;
    out.push_back(YawSample{t, at(t)});
  }
  return out;
}

Eigen::Vector2d Line(double t) { return Eigen::Vector2d(1.0 + 2.0 * t, -3.0 + 0.5 * t); }
double SlowTurn(double t) { return 0.1 + 0.01 * t; }

TEST(TimeAlignmentTest, InterpolationIsExactForLinearMotion) {
  const PoseInterpolator poses(Positions(100.0, 110.0, 10.0, Line),
                               Yaws(100.05, 110.0, 20.0, SlowTurn), calib::AlignmentOptions{});
  EXPECT_NEAR(poses.gnss_period_s(), 0.1, 1e-9);
  EXPECT_NEAR(poses.heading_period_s(), 0.05, 1e-9);
  EXPECT_DOUBLE_EQ(poses.start_s(), 100.05);  // the overlap starts with the later stream
  EXPECT_DOUBLE_EQ(poses.end_s(), 110.0);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> when(100.05, 110.0);
  for (int i = 0; i < 200; ++i) {
    const double t = when(rng);
    VehiclePose pose;
    ASSERT_EQ(poses.At(t, &pose), PoseStatus::kOk) << t;
    EXPECT_DOUBLE_EQ(pose.stamp_s, t);
    EXPECT_NEAR((pose.antenna_local_m - Line(t)).norm(), 0.0, 1e-9);
    EXPECT_NEAR(pose.yaw_rad, SlowTurn(t), 1e-9);
    EXPECT_NEAR(pose.gnss_sigma_m, 0.01 + 0.001 * t, 1e-9);
    EXPECT_FALSE(pose.stationary);
  }
  VehiclePose pose;
  EXPECT_EQ(poses.At(110.0, &pose), PoseStatus::kOk);  // the last instant is inside
  EXPECT_NEAR((pose.antenna_local_m - Line(110.0)).norm(), 0.0, 1e-9);
}

Eigen::Vector2d SpeedingUp(double t) {  // 3 m/s² from rest at t = 100 s, along (0.6, 0.8)
  const double s = 1.5 * (t - 100.0) * (t - 100.0);
  return Eigen::Vector2d(1.0 + 0.6 * s, -3.0 + 0.8 * s);
}
double TurningFaster(double t) { return 0.2 + 0.3 * (t - 100.0) * (t - 100.0); }  // 0.6 rad/s²

TEST(TimeAlignmentTest, MovingPoseIsExactForAnAcceleratingVehicle) {
  // Between two 10 Hz fixes a straight chord misplaces a vehicle speeding up at 3 m/s² by up to
  // a·T²/8 = 3.75 mm (same sign over the whole acceleration); the moving pose is a cubic through
  // two samples each side, exact for this quadratic motion (and the yaw's).
  const PoseInterpolator poses(Positions(100.0, 102.0, 10.0, SpeedingUp),
                               Yaws(100.0, 102.0, 20.0, TurningFaster), calib::AlignmentOptions{});
  double worst_chord_m = 0.0;
  for (double t = 100.13; t < 101.85; t += 0.01) {
    VehiclePose pose;
    ASSERT_EQ(poses.At(t, &pose), PoseStatus::kOk) << t;
    ASSERT_FALSE(pose.stationary);
    EXPECT_NEAR((pose.antenna_local_m - SpeedingUp(t)).norm(), 0.0, 1e-9) << t;
    EXPECT_NEAR(pose.yaw_rad, TurningFaster(t), 1e-9) << t;
    const double lo = std::floor(10.0 * (t - 100.0)) / 10.0 + 100.0;
    const double f = (t - lo) / 0.1;
    const Eigen::Vector2d chord = SpeedingUp(lo) + f * (SpeedingUp(lo + 0.1) - SpeedingUp(lo));
    worst_chord_m = std::max(worst_chord_m, (chord - SpeedingUp(t)).norm());
  }
  EXPECT_NEAR(worst_chord_m, 3.75e-3, 0.1e-3);  // what the straight chord would have made of it
  // Next to the ends (no second sample beyond): the straight chord, still a pose.
  VehiclePose pose;
  ASSERT_EQ(poses.At(100.05, &pose), PoseStatus::kOk);
  EXPECT_GT((pose.antenna_local_m - SpeedingUp(100.05)).norm(), 1e-3);
}

// The weights a pose gave its samples (VehiclePose::gnss_fix_weights, heading_sample_weights)
// are the ones it was interpolated with: the samples weighted by them give the pose back,
// the cubic's four while driving, the straight chord's two next to the ends. Several
// scanners share the samples' white noise through them (solvers/epoch_noise_cost.h): linear
// weights on a cubic pose would misplace that noise by a tenth of its σ per scan.
TEST(TimeAlignmentTest, PoseCarriesTheWeightsOfItsSamples) {
  const std::vector<PositionSample> positions = Positions(100.0, 102.0, 10.0, SpeedingUp);
  const std::vector<YawSample> yaws = Yaws(100.0, 102.0, 20.0, TurningFaster);
  const PoseInterpolator poses(positions, yaws, calib::AlignmentOptions{});
  const auto weighted = [](const auto& samples, int k, const std::array<double, 4>& w,
                           const auto& value) {
    decltype(value(samples[0])) sum = value(samples[k]) * 0.0;
    for (int j = 0; j < 4; ++j) {
      if (w[j] != 0.0) sum += w[j] * value(samples[k - 1 + j]);
    }
    return sum;
  };
  const auto position = [](const PositionSample& p) { return Eigen::Vector2d(p.p_local_m); };
  const auto yaw = [](const YawSample& y) { return y.yaw_rad; };
  int cubic = 0;
  for (double t = 100.13; t < 101.85; t += 0.017) {
    VehiclePose pose;
    ASSERT_EQ(poses.At(t, 0.012, &pose), PoseStatus::kOk) << t;
    ASSERT_FALSE(pose.stationary);
    const std::array<double, 4>& u = pose.gnss_fix_weights;
    const std::array<double, 4>& v = pose.heading_sample_weights;
    EXPECT_NEAR(u[0] + u[1] + u[2] + u[3], 1.0, 1e-12);
    EXPECT_NEAR(v[0] + v[1] + v[2] + v[3], 1.0, 1e-12);
    EXPECT_NEAR((weighted(positions, pose.gnss_fix, u, position) - pose.antenna_local_m).norm(),
                0.0, 1e-9)
        << t;
    EXPECT_NEAR(weighted(yaws, pose.heading_sample, v, yaw), pose.yaw_rad, 1e-9) << t;
    if (u[0] != 0.0 && u[3] != 0.0) ++cubic;
  }
  EXPECT_GT(cubic, 90);  // the cubic's outer samples carry weight while driving
  VehiclePose pose;
  ASSERT_EQ(poses.At(100.05, &pose), PoseStatus::kOk);  // no second fix before: the chord
  EXPECT_EQ(pose.gnss_fix, 0);
  EXPECT_DOUBLE_EQ(pose.gnss_fix_weights[0], 0.0);
  EXPECT_NEAR(pose.gnss_fix_weights[1], 0.5, 1e-9);
  EXPECT_NEAR(pose.gnss_fix_weights[2], 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(pose.gnss_fix_weights[3], 0.0);
}

// The heading delay moved into the poses (solvers/solve_policy.h): the position at the stamp,
// the heading and its rate at the stamp plus the shift, each exact for this quadratic motion;
// a shift that takes the heading past the streams' end is no pose.
TEST(TimeAlignmentTest, HeadingShiftTakesTheHeadingLaterThanThePosition) {
  const PoseInterpolator poses(Positions(100.0, 102.0, 10.0, SpeedingUp),
                               Yaws(100.0, 102.0, 20.0, TurningFaster), calib::AlignmentOptions{});
  for (const double shift_s : {-0.036, 0.027}) {
    for (double t = 100.3; t < 101.6; t += 0.013) {
      VehiclePose pose, plain, later;
      ASSERT_EQ(poses.At(t, shift_s, &pose), PoseStatus::kOk) << t;
      ASSERT_EQ(poses.At(t, &plain), PoseStatus::kOk);
      ASSERT_EQ(poses.At(t + shift_s, &later), PoseStatus::kOk);
      EXPECT_DOUBLE_EQ(pose.stamp_s, t);
      EXPECT_DOUBLE_EQ(pose.heading_shift_s, shift_s);
      EXPECT_NEAR((pose.antenna_local_m - SpeedingUp(t)).norm(), 0.0, 1e-9) << t;
      EXPECT_EQ(pose.velocity_local_mps, plain.velocity_local_mps);
      EXPECT_NEAR(pose.yaw_rad, TurningFaster(t + shift_s), 1e-9) << t;
      EXPECT_EQ(pose.yaw_rate_rps, later.yaw_rate_rps);
      EXPECT_EQ(pose.gnss_segment, plain.gnss_segment);
    }
  }
  VehiclePose pose;
  EXPECT_EQ(poses.At(101.99, 0.02, &pose), PoseStatus::kAfterEnd);
  EXPECT_EQ(poses.At(100.01, -0.02, &pose), PoseStatus::kBeforeStart);
  EXPECT_EQ(poses.At(101.99, &pose), PoseStatus::kOk);
  EXPECT_DOUBLE_EQ(pose.heading_shift_s, 0.0);
}

TEST(TimeAlignmentTest, YawTakesShortArcAcrossPi) {
  const std::vector<PositionSample> positions = {{0.0, Eigen::Vector2d::Zero(), 0.0},
                                                 {1.0, Eigen::Vector2d::Zero(), 0.0}};
  // 3.1 rad then −3.1 rad: 0.083 rad apart through ±π, not 6.2 rad back through zero.
  const std::vector<YawSample> yaws = {{0.0, 3.1}, {1.0, -3.1}};
  const PoseInterpolator poses(positions, yaws, calib::AlignmentOptions{});
  const double step = 2 * kPi - 6.2;
  VehiclePose pose;
  ASSERT_EQ(poses.At(0.25, &pose), PoseStatus::kOk);
  EXPECT_NEAR(pose.yaw_rad, 3.1 + 0.25 * step, 1e-12);
  ASSERT_EQ(poses.At(0.5, &pose), PoseStatus::kOk);
  EXPECT_NEAR(std::abs(pose.yaw_rad), kPi, 1e-12);
  ASSERT_EQ(poses.At(0.75, &pose), PoseStatus::kOk);
  EXPECT_NEAR(pose.yaw_rad, -3.1 - 0.25 * step, 1e-12);
  EXPECT_GT(pose.yaw_rad, -kPi);
}

TEST(TimeAlignmentTest, GapsAndEndsGiveNoPose) {
  // 10 Hz GNSS with 2 s missing between 105.0 and 107.0; 20 Hz headings with 1 s missing
  // between 108.0 and 109.0.
  std::vector<PositionSample> positions;
  for (const PositionSample& p : Positions(100.0, 112.0, 10.0, Line)) {
    if (p.stamp_s > 105.01 && p.stamp_s < 106.99) continue;
    positions.push_back(p);
  }
  std::vector<YawSample> yaws;
  for (const YawSample& y : Yaws(99.0, 111.0, 20.0, SlowTurn)) {
    if (y.stamp_s > 108.01 && y.stamp_s < 108.99) continue;
    yaws.push_back(y);
  }
  const PoseInterpolator poses(positions, yaws, calib::AlignmentOptions{});
  EXPECT_DOUBLE_EQ(poses.start_s(), 100.0);
  EXPECT_DOUBLE_EQ(poses.end_s(), 111.0);
  VehiclePose pose;
  pose.segment = -7;
  EXPECT_EQ(poses.At(99.99, &pose), PoseStatus::kBeforeStart);  // headings yes, GNSS not yet
  EXPECT_EQ(poses.At(111.01, &pose), PoseStatus::kAfterEnd);    // GNSS yes, headings over
  EXPECT_EQ(pose.segment, -7);                                  // untouched
  EXPECT_EQ(poses.At(100.0, &pose), PoseStatus::kOk);
  EXPECT_EQ(poses.At(104.99, &pose), PoseStatus::kOk);
  EXPECT_EQ(poses.At(105.01, &pose), PoseStatus::kGnssGap);
  EXPECT_EQ(poses.At(106.0, &pose), PoseStatus::kGnssGap);
  EXPECT_EQ(poses.At(106.99, &pose), PoseStatus::kGnssGap);
  EXPECT_EQ(poses.At(107.01, &pose), PoseStatus::kOk);
  EXPECT_EQ(poses.At(108.5, &pose), PoseStatus::kHeadingGap);
  EXPECT_EQ(poses.At(109.01, &pose), PoseStatus::kOk);
  EXPECT_STREQ(PoseStatusName(PoseStatus::kGnssGap), "in a GNSS gap");
  EXPECT_STREQ(PoseStatusName(PoseStatus::kBeforeStart), "before the GNSS/heading logs");

  // A gap of just under max_gap_periods × period is bridged.
  calib::AlignmentOptions options;
  options.max_gap_periods = 25.0;  // 2.5 s at 10 Hz
  const PoseInterpolator tolerant(positions, yaws, options);
  EXPECT_EQ(tolerant.At(106.0, &pose), PoseStatus::kOk);
  EXPECT_NEAR((pose.antenna_local_m - Line(106.0)).norm(), 0.0, 1e-9);
}

TEST(TimeAlignmentTest, RejectsUnsortedOrTooFewSamples) {
  const std::vector<YawSample> yaws = {{0.0, 0.0}, {1.0, 0.0}};
  EXPECT_THROW(PoseInterpolator({{0.0, Eigen::Vector2d::Zero(), 0.0}}, yaws, {}),
               std::invalid_argument);
  EXPECT_THROW(
      PoseInterpolator({{0.0, Eigen::Vector2d::Zero(), 0.0}, {0.0, Eigen::Vector2d::Zero(), 0.0}},
                       yaws, {}),
      std::invalid_argument);
  EXPECT_THROW(
      PoseInterpolator({{0.0, Eigen::Vector2d::Zero(), 0.0}, {1.0, Eigen::Vector2d::Zero(), 0.0}},
                       {{1.0, 0.0}, {0.5, 0.0}}, {}),
      std::invalid_argument);
}

// A stop-and-go drive: phases of constant speed and yaw rate, with abrupt changes (the hardest
// case for a windowed speed test), sampled at 10 Hz GNSS / 20 Hz heading with noise.
struct Phase {
  double duration_s, speed_mps, yaw_rate_rps;
};

struct Drive {
  std::vector<PositionSample> positions;
  std::vector<YawSample> yaws;
  struct Stop {
    double start_s, end_s;
    Eigen::Vector2d p;
    double yaw;
  };
  std::vector<Stop> stops;  // phases with zero speed and yaw rate
};

Drive MakeDrive(const std::vector<Phase>& phases, double sigma_p_m, double sigma_yaw_rad,
                unsigned seed) {
  const double dt = 0.001, t0 = 1000.0;
  std::vector<double> ts;
  std::vector<Eigen::Vector2d> ps;
  std::vector<double> ys;
  Drive drive;
  double t = 0.0, yaw = 2.9;  // near +π so the turns cross the wrap
  Eigen::Vector2d p(5.0, -2.0);
  for (const Phase& phase : phases) {
    const int steps = static_cast<int>(std::round(phase.duration_s / dt));
    if (phase.speed_mps == 0.0 && phase.yaw_rate_rps == 0.0) {
      drive.stops.push_back({t0 + t, t0 + t + phase.duration_s, p, WrapAngle(yaw)});
    }
    for (int i = 0; i < steps; ++i) {
      ts.push_back(t);
      ps.push_back(p);
      ys.push_back(yaw);
      p += phase.speed_mps * dt * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
      yaw += phase.yaw_rate_rps * dt;
      t += dt;
    }
  }
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (size_t i = 0; i < ts.size(); i += 100) {  // 10 Hz
    drive.positions.push_back(
        {t0 + ts[i], ps[i] + sigma_p_m * Eigen::Vector2d(normal(rng), normal(rng)), sigma_p_m});
  }
  for (size_t i = 0; i < ts.size(); i += 50) {  // 20 Hz
    drive.yaws.push_back({t0 + ts[i], WrapAngle(ys[i] + sigma_yaw_rad * normal(rng))});
  }
  return drive;
}

const std::vector<Phase> kStopAndGo = {
    {5.0, 1.0, 0.0},  {4.0, 0.0, 0.0},                   // stop 1
    {6.0, 1.0, 0.15}, {5.0, 0.0, 0.0},                   // turn, stop 2
    {3.0, 0.0, 0.3},                                     // turn on the spot: not a stop
    {4.0, 1.2, 0.0},  {6.0, 0.0, 0.0},                   // stop 3
    {1.0, 0.0, 0.0},  {2.0, 0.8, -0.2}, {1.5, 0.0, 0.0}  // too short to be a station
};

TEST(TimeAlignmentTest, FindsStopsOfStopAndGoDrive) {
  // Noise at the solver's defaults: 5 mm GNSS, 0.1° heading (single noisy windows must not
  // split a stop).
  for (unsigned seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE(seed);
    const Drive drive = MakeDrive(kStopAndGo, 0.005, 0.0017, seed);
    const PoseInterpolator poses(drive.positions, drive.yaws, calib::AlignmentOptions{});
    // The phase list also has a 1 s pause after stop 3 (merged into it: 7 s) and a 1.5 s stop
    // at the end (too short).
    ASSERT_EQ(poses.dwells().size(), 3u);
    const double expected_end[3] = {drive.stops[0].end_s, drive.stops[1].end_s,
                                    drive.stops[3].end_s};
    for (int i = 0; i < 3; ++i) {
      SCOPED_TRACE(i);
      const Dwell& dwell = poses.dwells()[i];
      // Each end cut by the guard (default 0.2 s).
      const double guard_s = calib::AlignmentOptions{}.dwell_guard_s;
      EXPECT_NEAR(dwell.start_s, drive.stops[i].start_s + guard_s, 0.3);
      EXPECT_NEAR(dwell.end_s, expected_end[i] - guard_s, 0.3);
      EXPECT_NEAR((dwell.mean_p_local_m - drive.stops[i].p).norm(), 0.0, 0.005);
      EXPECT_NEAR(WrapAngle(dwell.mean_yaw_rad - drive.stops[i].yaw), 0.0, 0.002);
    }
  }
}

TEST(TimeAlignmentTest, DwellLeavesOutTheEndOfASlowTurn) {
  // The vehicle finishes a turn on the spot slowly (2.3°/s) before it stops, and starts the
  // next one as slowly: the samples 0.1 s from the stop are 0.23° off its heading, inside the
  // edge test's tolerance (the stationary yaw rate times the window, 0.29°). Without a guard
  // they enter the dwell and pull its mean heading; with the default guard they do not.
  const std::vector<Phase> phases = {
      {5.0, 1.0, 0.0}, {1.0, 0.0, 0.04}, {4.0, 0.0, 0.0}, {1.0, 0.0, -0.04}, {5.0, 1.0, 0.0}};
  const Drive drive = MakeDrive(phases, 0.0, 0.0, 1);
  ASSERT_EQ(drive.stops.size(), 1u);
  const Drive::Stop& stop = drive.stops[0];
  calib::AlignmentOptions options;
  const PoseInterpolator guarded(drive.positions, drive.yaws, options);
  ASSERT_EQ(guarded.dwells().size(), 1u);
  EXPECT_GE(guarded.dwells()[0].start_s, stop.start_s - 1e-9);
  EXPECT_LE(guarded.dwells()[0].end_s, stop.end_s + 1e-9);
  EXPECT_NEAR(WrapAngle(guarded.dwells()[0].mean_yaw_rad - stop.yaw), 0.0, 1e-9);
  // The contrast: the same drive without the guard takes turning samples.
  options.dwell_guard_s = 0.0;
  const PoseInterpolator unguarded(drive.positions, drive.yaws, options);
  ASSERT_EQ(unguarded.dwells().size(), 1u);
  EXPECT_LT(unguarded.dwells()[0].start_s, stop.start_s - 0.05);
}

TEST(TimeAlignmentTest, NoiseFreeDwellsLieInsideTheStopsAtTheirPose) {
  // Without noise a dwell must not take a sample of the approach or departure: every sample in
  // it is at the stop's pose, so its mean heading is the stop's heading exactly (a scan from the
  // end of a turn solved with that heading biased the mount, docs/results.md). The guard costs
  // at most itself plus one GNSS period (0.1 s) at each end.
  const Drive drive = MakeDrive(kStopAndGo, 0.0, 0.0, 1);
  const calib::AlignmentOptions options;
  const PoseInterpolator poses(drive.positions, drive.yaws, options);
  ASSERT_EQ(poses.dwells().size(), 3u);
  for (int i = 0; i < 2; ++i) {
    SCOPED_TRACE(i);
    const Dwell& dwell = poses.dwells()[i];
    const Drive::Stop& stop = drive.stops[i];
    EXPECT_GE(dwell.start_s, stop.start_s - 1e-9);
    EXPECT_LE(dwell.end_s, stop.end_s + 1e-9);
    EXPECT_LE(dwell.start_s, stop.start_s + options.dwell_guard_s + 0.1001);
    EXPECT_GE(dwell.end_s, stop.end_s - options.dwell_guard_s - 0.1001);
    EXPECT_NEAR(WrapAngle(dwell.mean_yaw_rad - stop.yaw), 0.0, 1e-9);
    EXPECT_NEAR((dwell.mean_p_local_m - stop.p).norm(), 0.0, 1e-9);
  }
}

TEST(TimeAlignmentTest, SegmentsSeparateStationsAndTimeSlices) {
  const Drive drive = MakeDrive(kStopAndGo, 0.003, 0.0009, 9);
  calib::AlignmentOptions options;
  options.segment_max_s = 2.0;
  const PoseInterpolator poses(drive.positions, drive.yaws, options);
  ASSERT_EQ(poses.dwells().size(), 3u);
  const double start = poses.start_s();
  VehiclePose pose;
  // Inside each dwell: stationary, segment = dwell index; the GNSS slice is on the time grid.
  for (int i = 0; i < 3; ++i) {
    const Dwell& dwell = poses.dwells()[i];
    const double t = 0.5 * (dwell.start_s + dwell.end_s);
    ASSERT_EQ(poses.At(t, &pose), PoseStatus::kOk);
    EXPECT_TRUE(pose.stationary);
    EXPECT_EQ(pose.segment, i);
    EXPECT_EQ(pose.gnss_segment, static_cast<int>(std::floor((t - start) / 2.0)));
  }
  // Moving: station stretches of 5 s, 3 + floor((t − start) / 5), whatever segment_max_s;
  // GNSS slices of segment_max_s. Driving from 0–5 s and 9–15 s.
  ASSERT_EQ(poses.At(start + 1.0, &pose), PoseStatus::kOk);
  EXPECT_FALSE(pose.stationary);
  EXPECT_EQ(pose.segment, 3);
  EXPECT_EQ(pose.gnss_segment, 0);
  ASSERT_EQ(poses.At(start + 4.0, &pose), PoseStatus::kOk);
  EXPECT_EQ(pose.segment, 3);       // same stretch as t = 1 s
  EXPECT_EQ(pose.gnss_segment, 2);  // a later GNSS slice
  ASSERT_EQ(poses.At(start + 12.0, &pose), PoseStatus::kOk);
  EXPECT_FALSE(pose.stationary);
  EXPECT_EQ(pose.segment, 5);
  EXPECT_EQ(pose.gnss_segment, 6);
  // Turning on the spot (20–23 s) is not a station.
  ASSERT_EQ(poses.At(start + 21.5, &pose), PoseStatus::kOk);
  EXPECT_FALSE(pose.stationary);
  EXPECT_EQ(pose.segment, 7);
  EXPECT_EQ(pose.gnss_segment, 10);
}

TEST(TimeAlignmentTest, MovingPosesCarryVelocityAndYawRate) {
  // Phase 1 drives straight at 1 m/s from yaw 2.9 rad; phase 3 turns at 0.15 rad/s at 1 m/s
  // (9–15 s after the start, after a 4 s stop). The rates are what a clock offset multiplies.
  const Drive drive = MakeDrive(kStopAndGo, 0.003, 0.0009, 4);
  const PoseInterpolator poses(drive.positions, drive.yaws, calib::AlignmentOptions{});
  const double start = poses.start_s();
  VehiclePose pose;
  ASSERT_EQ(poses.At(start + 2.5, &pose), PoseStatus::kOk);
  EXPECT_FALSE(pose.stationary);
  EXPECT_NEAR(pose.velocity_local_mps.x(), std::cos(2.9), 0.03);
  EXPECT_NEAR(pose.velocity_local_mps.y(), std::sin(2.9), 0.03);
  EXPECT_NEAR(pose.yaw_rate_rps, 0.0, 0.01);
  ASSERT_EQ(poses.At(start + 12.0, &pose), PoseStatus::kOk);
  EXPECT_FALSE(pose.stationary);
  EXPECT_NEAR(pose.velocity_local_mps.norm(), 1.0, 0.03);
  EXPECT_NEAR(pose.yaw_rate_rps, 0.15, 0.01);
  // At a station both are (nearly) zero: only the noise of the samples.
  const Dwell& dwell = poses.dwells()[0];
  ASSERT_EQ(poses.At(0.5 * (dwell.start_s + dwell.end_s), &pose), PoseStatus::kOk);
  EXPECT_TRUE(pose.stationary);
  EXPECT_LT(pose.velocity_local_mps.norm(), 0.02);
  EXPECT_LT(std::abs(pose.yaw_rate_rps), 0.005);
}

}  // namespace
}  // namespace wallcal::calib
