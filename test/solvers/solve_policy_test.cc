// SPDX-License-Identifier: Apache-2.0
// Tests of the solve policy (solvers/solve_policy.h): which solver runs, and the clock rounds
// that move the poses to the estimated scan times and solve again. Observations come from the
// shared synthetic fixture (sim/synthetic_observations.h); the poses the rounds re-interpolate
// come from a pose interpolator over the same noise-free track.

#include "solvers/solve_policy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "common/angles.h"
#include "sim/synthetic_observations.h"
#include "test/support/synthetic_fixtures.h"

namespace wallcal::solvers {
namespace {

using sim::SimData;
using sim::SimSettings;
using testing_support::OptionsFor;

// The recorded track of each station (the noise-free fixture's poses: position and heading
// linear in time), sampled every 0.1 s from 1 s before a station's first scan to 1 s after its
// last, so that a shift of the poses by the clock offset stays inside the logs.
calib::PoseInterpolator TrackOf(SimSettings settings) {
  settings.noise = false;
  std::mt19937 rng(1);
  const SimData exact = sim::SimulateObservations(settings, rng);
  std::map<int, std::vector<const calib::WallObservation*>> by_station;
  for (const calib::WallObservation& o : exact.observations)
    by_station[o.pose.segment].push_back(&o);
  std::vector<calib::PositionSample> positions;
  std::vector<calib::YawSample> yaws;
  for (const auto& [station, scans] : by_station) {
    const calib::VehiclePose& first = scans.front()->pose;
    const double last_s = scans.back()->pose.stamp_s;
    for (int i = -10; first.stamp_s + 0.1 * i <= last_s + 1.0 + 1e-9; ++i) {
      const double dt = 0.1 * i;
      positions.push_back({first.stamp_s + dt,
                           first.antenna_local_m + dt * first.velocity_local_mps,
                           settings.gnss_white_sigma_m});
      yaws.push_back({first.stamp_s + dt, first.yaw_rad + dt * first.yaw_rate_rps});
    }
  }
  return calib::PoseInterpolator(positions, yaws, calib::AlignmentOptions());
}

TEST(SolveWithPolicyTest, MovesThePosesToTheEstimatedScanTimesAndReportsTheWholeOffset) {
  const SimSettings settings = testing_support::MovingStations();
  const calib::PoseInterpolator poses = TrackOf(settings);
  std::mt19937 rng(9);
  SimData data = sim::SimulateObservations(settings, rng);
  const size_t observed = data.observations.size();
  std::vector<double> shifts_s;
  const ClockRoundRule rule;
  const PolicyOutcome outcome = SolveWithPolicy(
      Method::kCeres, &data.observations, data.walls, OptionsFor(settings), settings.truth,
      /*force=*/false, poses, [&shifts_s](double shift_s) { shifts_s.push_back(shift_s); }, 1.0,
      rule);
  const MountEstimate& e = outcome.estimate;
  ASSERT_TRUE(e.usable) << e.message;
  ASSERT_TRUE(e.time_offset_estimated);
  // The first estimate (80 ms, σ of a few ms) is all left for the linear model: one round at
  // least, each told beforehand with the shift the poses carry after it.
  EXPECT_GE(outcome.clock_rounds, 1);
  EXPECT_LE(outcome.clock_rounds, rule.max_rounds);
  ASSERT_EQ(shifts_s.size(), static_cast<size_t>(outcome.clock_rounds));
  EXPECT_EQ(outcome.dropped_at_shifted_time, 0);
  ASSERT_EQ(data.observations.size(), observed);
  const double sigma_s = e.time_offset_sigma_s;
  ASSERT_GT(sigma_s, 0.0);
  // The poses now sit at the scans' true times: the shift carries the offset, to its σ ...
  EXPECT_NEAR(shifts_s.back(), settings.time_offset_s, 4.0 * sigma_s);
  for (const calib::WallObservation& o : data.observations) {
    EXPECT_DOUBLE_EQ(o.pose.clock_shift_s, shifts_s.back());
  }
  // ... and the reported offset is the whole of it (the shift plus what the last solve found).
  EXPECT_NEAR(e.time_offset_s, settings.time_offset_s, 4.0 * sigma_s);
  if (e.heading_delay_estimated) {
    EXPECT_NEAR(e.heading_delay_s, 0.0, 4.0 * e.heading_delay_sigma_s);
  }
  const Eigen::Vector3d sigma = e.covariance.diagonal().cwiseSqrt();
  EXPECT_NEAR(e.mount.x_m, settings.truth.x_m, 4.0 * sigma.x());
  EXPECT_NEAR(e.mount.y_m, settings.truth.y_m, 4.0 * sigma.y());
  EXPECT_NEAR(WrapAngle(e.mount.yaw_rad - settings.truth.yaw_rad), 0.0, 4.0 * sigma.z());
}

TEST(SolveWithPolicyTest, WithoutRoundsItIsTheCeresSolveAlone) {
  const SimSettings settings = testing_support::MovingStations();
  const calib::PoseInterpolator poses = TrackOf(settings);
  std::mt19937 rng(9);
  SimData data = sim::SimulateObservations(settings, rng);
  const std::vector<calib::WallObservation> before = data.observations;
  ClockRoundRule none;
  none.max_rounds = 0;
  int told = 0;
  const PolicyOutcome outcome = SolveWithPolicy(
      Method::kCeres, &data.observations, data.walls, OptionsFor(settings), settings.truth, false,
      poses, [&told](double) { ++told; }, 1.0, none);
  const MountEstimate alone =
      SolveMountCeres(before, data.walls, OptionsFor(settings), settings.truth);
  ASSERT_TRUE(outcome.estimate.usable) << outcome.estimate.message;
  EXPECT_EQ(outcome.clock_rounds, 0);
  EXPECT_EQ(told, 0);
  EXPECT_EQ(outcome.estimate.mount.x_m, alone.mount.x_m);
  EXPECT_EQ(outcome.estimate.mount.yaw_rad, alone.mount.yaw_rad);
  EXPECT_EQ(outcome.estimate.time_offset_s, alone.time_offset_s);
  ASSERT_EQ(data.observations.size(), before.size());
  EXPECT_EQ(data.observations.front().pose.stamp_s, before.front().pose.stamp_s);
}

TEST(SolveWithPolicyTest, StandingScansEstimateNoOffsetAndGetNoRound) {
  const SimSettings still;
  const calib::PoseInterpolator poses = TrackOf(testing_support::MovingStations());
  for (const Method method : {Method::kCeres, Method::kBarawid}) {
    std::mt19937 rng(3);
    SimData data = sim::SimulateObservations(still, rng);
    const std::vector<calib::WallObservation> before = data.observations;
    int told = 0;
    const PolicyOutcome outcome =
        SolveWithPolicy(method, &data.observations, data.walls, OptionsFor(still), still.truth,
                        false, poses, [&told](double) { ++told; });
    const MountEstimate alone =
        method == Method::kBarawid
            ? SolveMountBarawid(before, data.walls, OptionsFor(still))
            : SolveMountCeres(before, data.walls, OptionsFor(still), still.truth);
    SCOPED_TRACE(MethodName(method));
    ASSERT_TRUE(outcome.estimate.usable) << outcome.estimate.message;
    EXPECT_FALSE(outcome.estimate.time_offset_estimated);
    EXPECT_EQ(outcome.clock_rounds, 0);
    EXPECT_EQ(told, 0);
    EXPECT_EQ(outcome.estimate.mount.x_m, alone.mount.x_m);
    EXPECT_EQ(outcome.estimate.mount.y_m, alone.mount.y_m);
    EXPECT_EQ(outcome.estimate.mount.yaw_rad, alone.mount.yaw_rad);
    // Both solvers recover the mount to their σ.
    const Eigen::Vector3d sigma = outcome.estimate.covariance.diagonal().cwiseSqrt();
    ASSERT_GT(sigma.minCoeff(), 0.0);
    EXPECT_NEAR(outcome.estimate.mount.x_m, still.truth.x_m, 4.0 * sigma.x());
    EXPECT_NEAR(WrapAngle(outcome.estimate.mount.yaw_rad - still.truth.yaw_rad), 0.0,
                4.0 * sigma.z());
  }
}

}  // namespace
}  // namespace wallcal::solvers
