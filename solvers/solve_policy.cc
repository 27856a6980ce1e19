#include "solvers/solve_policy.h"

#include <algorithm>
#include <cmath>

#include "calib/detection_pass.h"
#include "solvers/mount_problem.h"

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

}  // namespace

const char* MethodName(Method method) {
  return method == Method::kBarawid ? "barawid" : "ceres";
}

PolicyOutcome SolveWithPolicy(Method method, std::vector<calib::WallObservation>* observations,
                              const std::vector<calib::WallGeometry>& walls,
                              const io::SolverOptions& options, const Mount& initial, bool force,
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
  // dt + δh (the headings are stamped on the same clock, δh after the positions): each when it
  // is beyond the tolerance and a quarter of its own σ. On drives along one wall only the sum
  // is in the data; it is moved while dt, which its prior keeps small, stays linear.
  const auto worth_moving = [](double value_s, double sigma_s) {
    return std::abs(value_s) >
           std::max(kClockOffsetToleranceS, kClockOffsetSigmaFraction * sigma_s);
  };
  double shifted_s = 0.0, heading_shifted_s = 0.0;
  while (outcome.clock_rounds < kClockOffsetRounds && outcome.estimate.usable) {
    const MountEstimate& e = outcome.estimate;
    const Eigen::Matrix2d& c = e.time_covariance;  // [dt, δh], s²
    const double turn_s = e.time_offset_s + (e.heading_delay_estimated ? e.heading_delay_s : 0.0);
    const double turn_sigma_s =
        e.heading_delay_estimated ? std::sqrt(std::max(0.0, c(0, 0) + 2.0 * c(0, 1) + c(1, 1)))
                                  : e.time_offset_sigma_s;
    const double position_move_s = worth_moving(e.time_offset_s, e.time_offset_sigma_s)
                                       ? e.time_offset_s : 0.0;
    const double heading_move_s = worth_moving(turn_s, turn_sigma_s) ? turn_s : 0.0;
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
    from.heading_delay_s -= delay_move_s;  // what is left of it once the headings carry it
    const Mount start = e.mount;           // e is overwritten below
    outcome.estimate = SolveMountCeres(*observations, walls, options, start, force, &from, &warm,
                                       observation_weight);
  }
  outcome.estimate.time_offset_s += shifted_s;
  outcome.estimate.heading_delay_s += heading_shifted_s;
  return outcome;
}

}  // namespace wallcal::solvers
