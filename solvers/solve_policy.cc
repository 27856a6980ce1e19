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
  double shifted_s = 0.0;
  while (outcome.clock_rounds < kClockOffsetRounds && outcome.estimate.usable &&
         std::abs(outcome.estimate.time_offset_s) >
             std::max(kClockOffsetToleranceS,
                      kClockOffsetSigmaFraction * outcome.estimate.time_offset_sigma_s)) {
    ++outcome.clock_rounds;
    shifted_s += outcome.estimate.time_offset_s;
    if (on_round) on_round(shifted_s);
    outcome.dropped_at_shifted_time +=
        calib::ShiftObservations(poses, outcome.estimate.time_offset_s, observations);
    WarmStart from = warm;
    from.checked = !outcome.estimate.forced;
    outcome.estimate =
        SolveMountCeres(*observations, walls, options, outcome.estimate.mount, force, &from, &warm,
                        observation_weight);
  }
  outcome.estimate.time_offset_s += shifted_s;
  return outcome;
}

}  // namespace wallcal::solvers
