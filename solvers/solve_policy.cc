// SPDX-License-Identifier: Apache-2.0
#include "solvers/solve_policy.h"

#include <algorithm>
#include <cmath>

#include "calib/detection_pass.h"
#include "common/angles.h"
#include "solvers/mount_problem.h"
#include "solvers/time_block.h"

namespace wallcal::solvers {
namespace {

// At most this many re-interpolations of the poses at the estimated scan times, stopping when
// the offset left over is below the tolerance or below a quarter of its own σ. A round moves
// the poses by speed × offset, which the solve already models to first order (the clock
// offset's Jacobian is the velocity); what a round adds is the curvature of the path over the
// offset, and the offset along the poorly determined split between clock offset and heading
// delay, where the solve stops early because the cost hardly changes. A change below σ/4 adds
// less than 6 % to the offset's variance: not worth a whole solve (2 s on an hour session).
constexpr int kClockOffsetRounds = 3;
constexpr double kClockOffsetToleranceS = 2e-4;
constexpr double kClockOffsetSigmaFraction = 0.25;

// How far moving the headings by shift_s would move the estimate of dt + δh (s), without a
// solve: the moving scans' headings interpolated at the shifted times, less the linear model's
// ψ + ω·shift_s, regressed on ω (the model's own regressor, each scan's heading noise alike).
// A yaw rate smoothed over ±0.5 s, as while driving on, overstates the shift it multiplies
// (by a fifth on short-stop sessions with car-like drives); a rate over ±one sample period on a drive between stops hardly
// does, and there a round would only repeat the solve.
double HeadingRoundChange(const calib::PoseInterpolator& poses,
                          const std::vector<calib::WallObservation>& observations,
                          double shift_s) {
  double sum_wd = 0.0, sum_ww = 0.0;
  for (const calib::WallObservation& o : observations) {
    if (UsesDwellHeading(o) || o.pose.yaw_rate_rps == 0.0) continue;
    calib::VehiclePose moved;
    if (poses.At(o.pose.stamp_s, o.pose.heading_shift_s + shift_s, &moved) !=
        calib::PoseStatus::kOk) {
      continue;
    }
    const double w = o.pose.yaw_rate_rps;
    const double discrepancy = WrapAngle(moved.yaw_rad - o.pose.yaw_rad - w * shift_s);
    sum_wd += w * discrepancy;
    sum_ww += w * w;
  }
  return sum_ww > 0.0 ? sum_wd / sum_ww : 0.0;
}

}  // namespace

const char* MethodName(Method method) {
  return method == Method::kBarawid ? "barawid" : "ceres";
}

PolicyOutcome SolveWithPolicy(Method method, std::vector<calib::WallObservation>* observations,
                              const std::vector<calib::WallGeometry>& walls,
                              const solvers::SolverOptions& options, const Mount& initial, bool force,
                              const calib::PoseInterpolator& poses,
                              const std::function<void(double shift_s)>& on_round,
                              double observation_weight) {
  PolicyOutcome outcome;
  if (method == Method::kBarawid) {
    outcome.estimate = SolveMountBarawid(*observations, walls, options, force);
    return outcome;
  }
  // Each round starts where the last one ended (warm), and is not checked before its solve
  // again: the geometry is the one the first solve checked.
  WarmStart warm;
  outcome.estimate = SolveMountCeres(*observations, walls, options, initial, force, nullptr, &warm,
                                     observation_weight);
  if (!outcome.estimate.usable || !outcome.estimate.time_offset_estimated) return outcome;
  // A round moves the positions by the clock offset dt and the headings by what turns need,
  // dt + δh (the headings are stamped on the same clock, δh after the positions): each only when
  // the data determine it and what is left of it is beyond the tolerance and a quarter of its σ.
  // On drives along one wall only the sum is in the data: the headings move by it while dt, which
  // only its prior holds, stays linear (moving it would start the next round's prior from
  // there, and the rounds would creep along the split).
  const auto worth_moving = [](double value_s, double sigma_s) {
    return std::abs(value_s) >
           std::max(kClockOffsetToleranceS, kClockOffsetSigmaFraction * sigma_s);
  };
  const double clock_prior_s = options.time_offset_sigma_s;
  double shifted_s = 0.0, heading_shifted_s = 0.0;
  while (outcome.clock_rounds < kClockOffsetRounds && outcome.estimate.usable) {
    const MountEstimate& e = outcome.estimate;
    const Eigen::Matrix2d& c = e.time_covariance;  // [dt, δh], s²
    const double heading_prior_s = e.heading_delay_estimated ? e.heading_delay_prior_sigma_s : 0.0;
    const double turn_s = e.time_offset_s + (e.heading_delay_estimated ? e.heading_delay_s : 0.0);
    const double turn_sigma_s =
        e.heading_delay_estimated ? std::sqrt(std::max(0.0, c(0, 0) + 2.0 * c(0, 1) + c(1, 1)))
                                  : e.time_offset_sigma_s;
    const double turn_prior_s = std::hypot(clock_prior_s, heading_prior_s);
    const bool clock_determined = DelayDetermined(c, clock_prior_s, heading_prior_s, 0);
    const bool turn_determined = ShrinksPriorByHalf(turn_sigma_s, turn_prior_s);
    const double position_move_s =
        clock_determined && worth_moving(e.time_offset_s, e.time_offset_sigma_s) ? e.time_offset_s
                                                                                 : 0.0;
    // The headings move by the sum when that changes its estimate by more than the threshold
    // (HeadingRoundChange; with the positions moved, the headings move with them anyway).
    const bool move_turn =
        turn_determined && worth_moving(turn_s, turn_sigma_s) &&
        (position_move_s != 0.0 ||
         worth_moving(HeadingRoundChange(poses, *observations, turn_s), turn_sigma_s));
    const double heading_move_s = move_turn ? turn_s : position_move_s;
    if (position_move_s == 0.0 && heading_move_s == 0.0) break;
    // The headings' shift beyond the positions' is the heading delay moved into the poses.
    const double delay_move_s = heading_move_s - position_move_s;
    ++outcome.clock_rounds;
    shifted_s += position_move_s;
    heading_shifted_s += delay_move_s;
    if (on_round) on_round(shifted_s);
    outcome.dropped_at_shifted_time +=
        calib::ShiftObservations(poses, position_move_s, delay_move_s, observations);
    WarmStart from = warm;
    from.checked = !e.forced;
    from.time_offset_s -= position_move_s;  // what is left of each once the poses carry it
    from.heading_delay_s -= delay_move_s;
    const Mount start = e.mount;           // e is overwritten below
    outcome.estimate = SolveMountCeres(*observations, walls, options, start, force, &from, &warm,
                                       observation_weight);
  }
  outcome.estimate.time_offset_s += shifted_s;
  outcome.estimate.heading_delay_s += heading_shifted_s;
  return outcome;
}

}  // namespace wallcal::solvers
