// SPDX-License-Identifier: Apache-2.0
#pragma once
// GNSS positions and yaw samples of a vehicle driving on a circle of 10 m radius with known
// white noise, for the tests of the white-noise measures (calib/white_noise.h,
// calib/drive_white_noise.h) and of the choice between them. The vehicle either drives without
// stopping (its speed varying smoothly) or stops and goes (each drive with the cosine speed
// profile s(τ) = (1 − cos πτ)/2, as the simulator's: its acceleration steps at both ends).
// Its yaw is the circle's tangent, so that it passes through ±π.

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "calib/time_alignment.h"
#include "common/angles.h"

namespace wallcal::testing_support {

struct SyntheticPoseLog {
  std::vector<calib::PositionSample> positions;
  std::vector<calib::YawSample> yaws;
  std::vector<calib::Dwell> dwells;  // the stops, when listed as dwells
};

struct SyntheticDrivePlan {
  // Stop and go when num_stops > 0: num_stops stops of stop_s, each followed by a drive of
  // drive_s turning the vehicle by drive_arc_rad along the circle. Else one smooth drive of
  // duration_s: the arc angle φ(t) = ω t + (A / Ω) sin(Ω t), ω = 0.08 rad/s, Ω = 2π / 7 s, so
  // that the speed is 0.8 ± 10 m × A (0.4..1.2 m/s by default).
  int num_stops = 0;
  double stop_s = 4.0;
  double drive_s = 8.0;
  double drive_arc_rad = 0.5;  // 5 m at 10 m radius: 0.98 m/s at the drive's middle
  double wobble_rad_per_s = 0.04;  // A
  bool stops_are_dwells = true;
  double duration_s = 300.0;
  double gnss_rate_hz = 10.0;
  double heading_rate_hz = 20.0;
  double gnss_white_sigma_m = 0.003;      // per axis
  double heading_sigma_rad = 0.05 * kDegToRad;
  // Each fix stamped up to this late, uniformly, while its position is at the true time.
  double gnss_jitter_s = 0.0;
};

inline constexpr double kSyntheticCircleRadiusM = 10.0;

// The arc angle at true time t_s, rad.
inline double SyntheticArcAngle(const SyntheticDrivePlan& plan, double t_s) {
  if (plan.num_stops == 0) {
    const double omega_rad_per_s = 0.08, wobble_rad_per_s = kTwoPi / 7.0;
    return omega_rad_per_s * t_s +
           plan.wobble_rad_per_s / wobble_rad_per_s * std::sin(wobble_rad_per_s * t_s);
  }
  const double cycle_s = plan.stop_s + plan.drive_s;
  const int k = static_cast<int>(std::floor(t_s / cycle_s));
  const double in_cycle_s = t_s - k * cycle_s;
  double s = 0.0;
  if (in_cycle_s > plan.stop_s) {
    s = 0.5 * (1.0 - std::cos(kPi * (in_cycle_s - plan.stop_s) / plan.drive_s));
  }
  return plan.drive_arc_rad * (k + s);
}

inline double SyntheticDuration(const SyntheticDrivePlan& plan) {
  return plan.num_stops > 0 ? plan.num_stops * (plan.stop_s + plan.drive_s) : plan.duration_s;
}

inline SyntheticPoseLog MakeSyntheticPoseLog(const SyntheticDrivePlan& plan, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> standard(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  SyntheticPoseLog log;
  const double duration_s = SyntheticDuration(plan);
  const auto position = [&](double t_s) {
    const double phi = SyntheticArcAngle(plan, t_s);
    return Eigen::Vector2d(kSyntheticCircleRadiusM * std::cos(phi),
                           kSyntheticCircleRadiusM * std::sin(phi));
  };
  for (int j = 0; j / plan.gnss_rate_hz < duration_s; ++j) {
    const double t_s = j / plan.gnss_rate_hz;
    const Eigen::Vector2d white(plan.gnss_white_sigma_m * standard(rng),
                                plan.gnss_white_sigma_m * standard(rng));
    const double stamp_s = t_s + plan.gnss_jitter_s * uniform(rng);
    log.positions.push_back({stamp_s, position(t_s) + white, plan.gnss_white_sigma_m});
  }
  for (int j = 0; j / plan.heading_rate_hz < duration_s; ++j) {
    const double t_s = j / plan.heading_rate_hz;
    const double yaw_rad = SyntheticArcAngle(plan, t_s) + 0.5 * kPi;  // counter-clockwise
    log.yaws.push_back({t_s, WrapAngle(yaw_rad + plan.heading_sigma_rad * standard(rng))});
  }
  if (plan.stops_are_dwells) {
    for (int k = 0; k < plan.num_stops; ++k) {
      // A dwell spans its first to last GNSS sample, as PoseInterpolator finds them.
      const double start_s = k * (plan.stop_s + plan.drive_s);
      calib::Dwell dwell;
      dwell.start_s = start_s;
      dwell.end_s = start_s + std::floor(plan.stop_s * plan.gnss_rate_hz - 1e-9) /
                                  plan.gnss_rate_hz;
      dwell.mean_p_local_m = position(start_s);
      dwell.mean_yaw_rad = WrapAngle(SyntheticArcAngle(plan, start_s) + 0.5 * kPi);
      log.dwells.push_back(dwell);
    }
  }
  return log;
}

}  // namespace wallcal::testing_support
