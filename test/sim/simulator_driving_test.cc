// SPDX-License-Identifier: Apache-2.0
// The simulator's driving between and through the stations: continuous sweeps with a weave
// (sideways or a car's arc), car-like reversing drives, and the truth helpers that follow them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/angles.h"
#include "sim/simulator.h"
#include "test/support/sim_fixtures.h"

namespace wallcal::sim {
namespace {
using namespace testing_fixtures;  // NOLINT: the shared fixtures

TEST(SimulatorTest, ContinuousDrivingNeverStopsAndSweepsTheStationPoses) {
  sim::SimulationConfig stop_and_go = DefaultConfig();
  stop_and_go.drive_speed_mps = 0.6;
  sim::SimulationConfig config = stop_and_go;
  config.continuous = true;
  config.weave_amplitude_m = 1.0;
  const Collected run = RunSim(config, CheapPreset(), 1);
  const auto& poses = run.session.truth_poses;
  ASSERT_GT(poses.size(), 100u);

  // As long as the stop-and-go run of the same config.
  EXPECT_NEAR(poses.back().stamp_s - poses.front().stamp_s, RunDurationS(stop_and_go), 0.1 + 1e-6);
  EXPECT_NEAR(RunDurationS(config), RunDurationS(stop_and_go), 1e-9);

  double min_yaw = 1e9, max_yaw = -1e9, min_speed = 1e9, path_m = 0.0;
  double min_x = 1e9, max_x = -1e9;
  for (size_t k = 0; k < poses.size(); ++k) {
    EXPECT_FALSE(poses[k].stationary) << "pose " << k;
    min_yaw = std::min(min_yaw, poses[k].yaw_enu_rad);
    max_yaw = std::max(max_yaw, poses[k].yaw_enu_rad);
    min_x = std::min(min_x, poses[k].antenna_enu_m.x());
    max_x = std::max(max_x, poses[k].antenna_enu_m.x());
    // The default wall is y = 12 m: the weave stays within ±A of the stations' distance.
    const double distance_m = 12.0 - poses[k].antenna_enu_m.y();
    EXPECT_GE(distance_m, config.station_distance_m - config.weave_amplitude_m - 1e-9);
    EXPECT_LE(distance_m, config.station_distance_m + config.weave_amplitude_m + 1e-9);
    if (k > 0) {
      const double step_m = (poses[k].antenna_enu_m - poses[k - 1].antenna_enu_m).norm();
      path_m += step_m;
      min_speed = std::min(min_speed, step_m / 0.1);
    }
  }
  // The stations' headings (centred on facing the wall) and lateral positions, passed once.
  EXPECT_NEAR(max_yaw - min_yaw, config.heading_spread_rad, 1e-9);
  EXPECT_NEAR(0.5 * (max_yaw + min_yaw), kPi / 2.0, 1e-9);
  EXPECT_NEAR(max_x - min_x, config.lateral_spread_m, 1e-6);
  // Never stopped (every 0.1 s step moves), and the mean speed is about drive_speed_mps: the
  // weave's 4A per period plus a little from the sweep.
  EXPECT_GT(min_speed, 0.01);
  const double mean_speed = path_m / (poses.back().stamp_s - poses.front().stamp_s);
  EXPECT_GT(mean_speed, 0.9 * config.drive_speed_mps);
  EXPECT_LT(mean_speed, 1.3 * config.drive_speed_mps);
}

// A car's weave (weave_turn_deg): forward and back along the vehicle's own axis on an arc, so
// the velocity has no sideways part beyond the sweep's slow drift, the heading turns by
// weave_turn_deg at ±weave_amplitude_m, and the turn rate peaks at κ times the weave's peak
// speed π/2·v (8°/m × 1.26 m/s = 10°/s), plus the sweep's. Checked on TruePosesAt every 5 ms
// by central differences.
TEST(SimulatorTest, CarLikeWeaveDrivesAlongTheAxisOnAnArc) {
  sim::SimulationConfig config = DefaultConfig();
  config.continuous = true;
  config.drive_speed_mps = 0.8;
  config.weave_amplitude_m = 1.0;
  config.weave_turn_rad = 8.0 * kDegToRad;
  sim::SimulationConfig sideways = config;
  sideways.weave_turn_rad = 0.0;
  constexpr double kStepS = 0.005;
  std::vector<double> times;
  for (double t = 0.0; t <= RunDurationS(config); t += kStepS) times.push_back(t);
  const std::vector<SimTruthPose> poses = TruePosesAt(config, times);
  const std::vector<SimTruthPose> plain = TruePosesAt(sideways, times);
  // The sweep's cosine profile peaks at π/(2D) of its span per second: the lateral spread, and
  // the weave's arc (up to A long) swung by the sweep's heading. The weave itself adds nothing.
  const double sweep_rate_per_s = 0.5 * kPi / RunDurationS(config);
  const double sweep_mps =
      sweep_rate_per_s *
      (config.lateral_spread_m + config.weave_amplitude_m * config.heading_spread_rad);
  double max_sideways_mps = 0.0, max_rate_rps = 0.0, max_turn_rad = 0.0;
  double plain_sideways_mps = 0.0;
  for (size_t k = 1; k + 1 < poses.size(); ++k) {
    auto sideways_speed = [&](const std::vector<SimTruthPose>& p) {
      const Eigen::Vector2d v = (p[k + 1].antenna_enu_m - p[k - 1].antenna_enu_m) / (2 * kStepS);
      const double yaw = p[k].yaw_enu_rad;
      return std::abs(Eigen::Vector2d(-std::sin(yaw), std::cos(yaw)).dot(v));
    };
    max_sideways_mps = std::max(max_sideways_mps, sideways_speed(poses));
    plain_sideways_mps = std::max(plain_sideways_mps, sideways_speed(plain));
    max_rate_rps = std::max(
        max_rate_rps, std::abs(poses[k + 1].yaw_enu_rad - poses[k - 1].yaw_enu_rad) / (2 * kStepS));
    max_turn_rad = std::max(max_turn_rad, std::abs(poses[k].yaw_enu_rad - plain[k].yaw_enu_rad));
  }
  EXPECT_LT(max_sideways_mps, sweep_mps + 1e-3);
  // The old weave, with the vehicle turned up to ±heading_spread/2 from the wall normal, moves
  // it sideways at up to v·sin(spread/2): the new one does not.
  EXPECT_GT(plain_sideways_mps,
            0.5 * config.drive_speed_mps * std::sin(0.5 * config.heading_spread_rad));
  // Heading off the sweep's by κ·r: at most the configured turn, reached at the weave's ends.
  EXPECT_NEAR(max_turn_rad, config.weave_turn_rad, 1e-3);
  // Peak weave speed is π/2 · 4A/T = π/2 · v; the turn rate κ times that, plus the sweep's.
  const double weave_rate =
      config.weave_turn_rad / config.weave_amplitude_m * 0.5 * kPi * config.drive_speed_mps;
  EXPECT_GT(max_rate_rps, weave_rate);
  EXPECT_LT(max_rate_rps, weave_rate + config.heading_spread_rad * sweep_rate_per_s + 1e-4);
  // The same distance from the wall as the sideways weave at the sweep's ends.
  EXPECT_NEAR(poses.front().antenna_enu_m.y(), plain.front().antenna_enu_m.y(), 1e-9);
}

// A car-like vehicle between stops (drive_reverse_m): it backs out and drives in, its velocity
// along its own axis throughout (no sideways motion), at rest at each station and at the cusp,
// and it arrives at every station's pose. Checked on TruePosesAt every 5 ms by differences.
TEST(SimulatorTest, ReversingDrivesMoveAlongTheVehicleAxisOnly) {
  sim::SimulationConfig config = DefaultConfig();
  config.drive_reverse_m = 4.0;
  sim::SimulationConfig sideways = config;
  sideways.drive_reverse_m = 0.0;
  const double duration_s = RunDurationS(config);
  EXPECT_GT(duration_s, RunDurationS(sideways) + 9 * 8.0 / config.drive_speed_mps * 0.9);
  constexpr double kStepS = 0.005;
  std::vector<double> times;
  for (double t = 0.0; t <= duration_s; t += kStepS) times.push_back(t);
  const std::vector<SimTruthPose> poses = TruePosesAt(config, times);
  double max_sideways_mps = 0.0, max_speed_mps = 0.0, max_rate_rps = 0.0, farthest_m = 0.0;
  int stations = 0;
  for (size_t k = 1; k + 1 < poses.size(); ++k) {
    const Eigen::Vector2d v =
        (poses[k + 1].antenna_enu_m - poses[k - 1].antenna_enu_m) / (2.0 * kStepS);
    const double yaw = poses[k].yaw_enu_rad;
    const Eigen::Vector2d left(-std::sin(yaw), std::cos(yaw));
    max_sideways_mps = std::max(max_sideways_mps, std::abs(left.dot(v)));
    max_speed_mps = std::max(max_speed_mps, v.norm());
    max_rate_rps =
        std::max(max_rate_rps,
                 std::abs(poses[k + 1].yaw_enu_rad - poses[k - 1].yaw_enu_rad) / (2.0 * kStepS));
    farthest_m = std::max(farthest_m, 12.0 - poses[k].antenna_enu_m.y());  // the wall: y = 12 m
    if (poses[k].stationary && !poses[k - 1].stationary) ++stations;
  }
  // Sideways speed: only what the 5 ms differences make of the curvature (O(step²)).
  EXPECT_LT(max_sideways_mps, 1e-3) << "speed " << max_speed_mps;
  EXPECT_GT(max_speed_mps, config.drive_speed_mps);
  EXPECT_LT(max_speed_mps, 2.0 * config.drive_speed_mps);
  // A tractor's turn rates (the sessions turn at up to 12°/s).
  EXPECT_LT(max_rate_rps, 15.0 * kPi / 180.0);
  // Backs out to about drive_reverse_m behind the stations' line (8 m from the wall).
  EXPECT_NEAR(farthest_m, config.station_distance_m + config.drive_reverse_m, 0.5);
  EXPECT_EQ(stations, config.num_stations - 1);  // the first station starts the run
  // Every station is reached at rest, facing as planned: the sideways plan's poses there.
  for (size_t k = 0; k < poses.size(); ++k) {
    if (!poses[k].stationary) continue;
    const double t = times[k];
    bool matched = false;
    for (double s = 0.0; s <= RunDurationS(sideways); s += 0.05) {
      const SimTruthPose p = TruePosesAt(sideways, {s}).front();
      if (p.stationary && (p.antenna_enu_m - poses[k].antenna_enu_m).norm() < 1e-9 &&
          std::abs(p.yaw_enu_rad - poses[k].yaw_enu_rad) < 1e-9) {
        matched = true;
        break;
      }
    }
    ASSERT_TRUE(matched) << "stationary pose at t = " << t << " is not a station";
    k += 50;  // one check per 0.25 s of a dwell is plenty
  }
}

TEST(SimulatorTest, ContinuousDurationAndTruthHelpersFollowTheConfig) {
  sim::SimulationConfig config = DefaultConfig();
  config.continuous = true;
  config.continuous_duration_s = 30.0;
  const Collected run = RunSim(config, CheapPreset(), 2);
  EXPECT_NEAR(run.session.truth_poses.back().stamp_s - config.start_time_s, 30.0, 1e-9);
  EXPECT_NEAR(RunDurationS(config), 30.0, 1e-12);
  // TruePosesAt reproduces the truth record exactly.
  std::vector<double> times;
  for (size_t k = 0; k < run.session.truth_poses.size(); k += 37) times.push_back(k / 10.0);
  const std::vector<SimTruthPose> poses = TruePosesAt(config, times);
  ASSERT_EQ(poses.size(), times.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    const SimTruthPose& expected = run.session.truth_poses[i * 37];
    EXPECT_DOUBLE_EQ(poses[i].stamp_s, expected.stamp_s);
    EXPECT_EQ(poses[i].antenna_enu_m, expected.antenna_enu_m);
    EXPECT_EQ(poses[i].yaw_enu_rad, expected.yaw_enu_rad);
  }
}

TEST(SimulatorTest, ContinuousScansSeeTheWallFromTheMovingPose) {
  sim::SimulationConfig config = NoiseFreeConfig();
  config.continuous = true;
  const io::ScannerPreset preset = PerfectPreset();
  const Collected run = RunSim(config, preset, 4);
  ASSERT_GT(run.scans.size(), 100u);
  int checked = 0;
  for (size_t si = 0; si < run.scans.size(); si += 50) {
    const io::ScanRecord& scan = run.scans[si];
    const SimTruthPose truth = TruePosesAt(config, {scan.stamp_s - config.start_time_s}).front();
    const std::vector<SimBeamHit> hits = TrueBeamHits(config, preset, truth);
    ASSERT_EQ(hits.size(), scan.ranges_m.size());
    for (size_t i = 0; i < hits.size(); ++i) {
      if (!hits[i].returned) continue;
      EXPECT_EQ(hits[i].wall_index, 0);  // the only wall
      EXPECT_NEAR(scan.ranges_m[i], hits[i].range_m, 2e-7 * hits[i].range_m + 1e-6);
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(SimulatorTest, RejectsAWeaveThatReachesTheWall) {
  sim::SimulationConfig config = DefaultConfig();
  config.continuous = true;
  config.weave_amplitude_m = config.station_distance_m - 2.0;  // scanner 2.57 m ahead
  EXPECT_THROW(RunSim(config, CheapPreset(), 1), io::InputError);
  EXPECT_THROW(RunDurationS(config), io::InputError);
  config.weave_amplitude_m = -1.0;
  EXPECT_THROW(RunSim(config, CheapPreset(), 1), io::InputError);
  config.weave_amplitude_m = 1.0;
  config.weave_turn_rad = 100.0 * kDegToRad;  // a turn past square to the wall
  EXPECT_THROW(RunSim(config, CheapPreset(), 1), io::InputError);
  config.weave_turn_rad = -1.0 * kDegToRad;
  EXPECT_THROW(RunSim(config, CheapPreset(), 1), io::InputError);
  config.weave_turn_rad = 8.0 * kDegToRad;
  config.continuous_duration_s = -5.0;
  EXPECT_THROW(RunSim(config, CheapPreset(), 1), io::InputError);
  config.continuous = false;  // the weave settings only matter when driving continuously
  EXPECT_NO_THROW(RunSim(config, CheapPreset(), 1));
}

}  // namespace
}  // namespace wallcal::sim
