// SPDX-License-Identifier: Apache-2.0
#include "solvers/solve_policy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "calib/detection_pass.h"
#include "common/angles.h"
#include "solvers/clock_rounds.h"
#include "solvers/mount_problem.h"
#include "solvers/time_block.h"

namespace wallcal::solvers {
namespace {

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
                              double observation_weight, const ClockRoundRule& rule) {
  PolicyOutcome outcome;
  if (method == Method::kBarawid) {
    outcome.estimate = SolveMountBarawid(*observations, walls, options, force);
    return outcome;
  }
  // Each round starts where the last one ended (warm) and takes ClockRoundStep's steps, with
  // the solve before's checks and σ's (the geometry is the one that solve checked); a round
  // that moves the poses by more than rule.max_step_shift_s solves in full.
  WarmStart warm;
  outcome.estimate = SolveMountCeres(*observations, walls, options, initial, force, nullptr, &warm,
                                     observation_weight);
  if (!outcome.estimate.usable || !outcome.estimate.time_offset_estimated) return outcome;
  // A round moves the positions by the clock offset dt and the headings by what turns need,
  // dt + δh (the headings are stamped on the same clock, δh after the positions): each only when
  // the data determine it and the change the round would make to it is beyond the tolerance and
  // a fraction of its σ (clock_rounds.h: the first round's is all of what is left, later ones'
  // are predicted from the round before). On drives along one wall only the sum is in the data:
  // the headings move by it while dt, which only its prior holds, stays linear (moving it would
  // start the next round's prior from there, and the rounds would creep along the split).
  const double clock_prior_s = options.time_offset_sigma_s;
  const double unmeasured = std::numeric_limits<double>::quiet_NaN();
  double shifted_s = 0.0, heading_shifted_s = 0.0;
  double clock_moved_s = unmeasured, turn_moved_s = unmeasured;  // by the round before
  while (outcome.clock_rounds < rule.max_rounds && outcome.estimate.usable) {
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
        clock_determined &&
                WorthARound(rule, PredictedRoundChange(e.time_offset_s, clock_moved_s),
                            e.time_offset_sigma_s)
            ? e.time_offset_s
            : 0.0;
    // The headings move by the sum when that changes its estimate by more than the threshold
    // (before any round, HeadingRoundChange says by how much without a solve), and whenever the
    // positions move: they are re-interpolated then anyway, and at the sum they leave the least
    // to the linear model (at dt alone, the heading delay's part of the sum would be left).
    const bool move_turn =
        turn_determined &&
        (position_move_s != 0.0 ||
         (WorthARound(rule, PredictedRoundChange(turn_s, turn_moved_s), turn_sigma_s) &&
          (std::isfinite(turn_moved_s) ||
           WorthARound(rule, HeadingRoundChange(poses, *observations, turn_s), turn_sigma_s))));
    const double heading_move_s = move_turn ? turn_s : position_move_s;
    if (position_move_s == 0.0 && heading_move_s == 0.0) break;
    clock_moved_s = position_move_s != 0.0 ? position_move_s : unmeasured;
    turn_moved_s = move_turn ? turn_s : unmeasured;
    // The headings' shift beyond the positions' is the heading delay moved into the poses.
    const double delay_move_s = heading_move_s - position_move_s;
    ++outcome.clock_rounds;
    shifted_s += position_move_s;
    heading_shifted_s += delay_move_s;
    if (on_round) on_round(shifted_s);
    outcome.dropped_at_shifted_time +=
        calib::ShiftObservations(poses, position_move_s, delay_move_s, observations);
    WarmStart from = warm;
    from.time_offset_s -= position_move_s;  // what is left of each once the poses carry it
    from.heading_delay_s -= delay_move_s;
    const MountEstimate before = std::move(outcome.estimate);  // e refers to it: not used below
    if (std::max(std::abs(position_move_s), std::abs(heading_move_s)) > rule.max_step_shift_s) {
      from.checked = !before.forced;
      outcome.estimate = SolveMountCeres(*observations, walls, options, before.mount, force, &from,
                                         &warm, observation_weight);
    } else {
      outcome.estimate =
          ClockRoundStep(*observations, walls, options, before, from, &warm, observation_weight);
    }
  }
  outcome.estimate.time_offset_s += shifted_s;
  outcome.estimate.heading_delay_s += heading_shifted_s;
  return outcome;
}

}  // namespace wallcal::solvers
