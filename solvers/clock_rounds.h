// SPDX-License-Identifier: Apache-2.0
#pragma once
// When the clock rounds (solve_policy.h) stop. A round moves what is left of a delay after a
// solve (left_s: the time block's estimate beyond what the poses carry) into the poses and
// solves again; the estimate of the delay then changes by what the linear model p + v·dt,
// ψ + ω·(dt + δh) had wrong over left_s (the path's curvature over it, a smoothed yaw rate),
// which is the new left-over. That error shrinks with the shift: the round before measured by
// how much (its contraction, this left-over over the one it moved; doubled for safety), so the
// change the next round would make is predicted without its solve. The rounds stop when, for
// each delay they move, that predicted change is below a fraction of the delay's own σ: then a
// further round would only repeat the solve (a whole solve of the adjustment, a round's cost).

#include <limits>

namespace wallcal::solvers {

// The stopping rule's numbers.
struct ClockRoundRule {
  int max_rounds = 3;          // re-interpolations at most
  double sigma_fraction = 0.25;  // a change below this fraction of σ adds < 6 % to the variance
  double tolerance_s = 2e-4;     // and a change below this is not worth a solve whatever the σ
  // A round that moves the poses by more than this (s, positions or headings) is a whole solve
  // with its covariance, not ClockRoundStep's steps with the solve before's σ's: over 0.1 s of
  // shift (bench (h), the scanner clock 150 ms behind) the first solve's σ's of the mount are
  // 1–6 % off those at the shifted poses; over 28 ms (the speed bench's hour with drives) 4e-4.
  double max_step_shift_s = 0.05;
};

// What a round that moves left_s into the poses would change the estimate by (s, signed), from
// the round before: previous_left_s is what that round moved (NaN when no round has moved this
// delay: then nothing is measured, and the prediction is left_s itself, the linear model wrong
// by all of it). The contraction is taken as 2 |left_s / previous_left_s| (one round measures
// it roughly), capped at 1 (a round that did not shrink the left-over predicts no better than
// none).
double PredictedRoundChange(double left_s,
                            double previous_left_s = std::numeric_limits<double>::quiet_NaN());

// Whether a change of change_s (s) in a delay of σ sigma_s is worth a round: beyond both the
// rule's tolerance and its fraction of σ.
bool WorthARound(const ClockRoundRule& rule, double change_s, double sigma_s);

}  // namespace wallcal::solvers
