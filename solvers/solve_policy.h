// SPDX-License-Identifier: Apache-2.0
#pragma once
// The solve policy: which solver runs, and the rounds around it. With moving scans the
// adjustment estimates a scanner clock offset; its p + v·dt, ψ + ω·dt is a linearisation, poor
// where the vehicle accelerates (a simulated 150 ms offset came back as 135 ± 2 ms from it
// alone), so the poses are re-interpolated at the estimated scan times and the problem solved
// again until the offset left over is below a tolerance. The headings are moved the same way
// by what the turns tell, the clock offset plus the heading delay estimated beside it
// (wall_line_cost.h): re-interpolated that much later than the stamps. Left linear, ω·(dt + δh)
// takes a yaw rate smoothed over ±0.5 s while driving on, which overstates a −36 ms heading
// delay by 2–3 ms on short-stop sessions with car-like drives (11 of its σ); with the headings
// moved, the rate only steers the steps, not where they end.

#include <functional>
#include <vector>

#include "calib/observation.h"
#include "calib/time_alignment.h"
#include "solvers/clock_rounds.h"
#include "solvers/solver_options.h"
#include "solvers/mount_solver.h"

namespace wallcal::solvers {

struct PolicyOutcome {
  MountEstimate estimate;
  int clock_rounds = 0;              // re-interpolations done
  int dropped_at_shifted_time = 0;   // observations with no pose at the corrected time
};

// Solves with `method` from `initial`; for ceres with an estimated clock offset, shifts the
// positions of *observations to the estimated scan times (dt) and their headings by dt + δh, and
// solves again (at most rule.max_rounds rounds), and reports the totals; each round is
// ClockRoundStep's two Gauss–Newton steps from where the last ended (WarmStart), with the solve
// before's σ's, about half the first solve's cost (a shift beyond rule.max_step_shift_s: a
// whole solve). Each shift is made only when the data
// determine it (solvers::DelayDetermined; for the sum, σ below half its prior's) and the change
// a round would make to it is beyond rule.tolerance_s and rule.sigma_fraction of its σ
// (clock_rounds.h: before any round, all of what is left; after one, predicted from the
// contraction that round showed); the headings alone, before any round, also only when
// re-interpolating them would move the sum's estimate by that much (else the round would repeat
// the solve). `on_round(shift_s)` (may be empty) is told before each round.
// `observation_weight`: SolveMountCeres's (a thinned preview); barawid takes none.
PolicyOutcome SolveWithPolicy(Method method, std::vector<calib::WallObservation>* observations,
                              const std::vector<calib::WallGeometry>& walls,
                              const solvers::SolverOptions& options, const Mount& initial, bool force,
                              const calib::PoseInterpolator& poses,
                              const std::function<void(double shift_s)>& on_round = nullptr,
                              double observation_weight = 1.0,
                              const ClockRoundRule& rule = ClockRoundRule());

}  // namespace wallcal::solvers
