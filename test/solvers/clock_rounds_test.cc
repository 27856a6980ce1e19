// SPDX-License-Identifier: Apache-2.0
// The clock rounds' stopping rule (solvers/clock_rounds.h) on a model of the rounds: a linear
// model that gets the offset left over wrong by a part proportional to it (a smoothed yaw rate)
// and a part quadratic in it (the path's curvature). A session's rounds: pipeline/delays_test.cc.

#include "solvers/clock_rounds.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace wallcal::solvers {
namespace {

// What a solve leaves of the delay when the poses carry shifted_s of the true truth_s: the
// linear model's estimate of the rest, wrong by rate_error × rest + curvature × rest².
double LeftAfterSolve(double truth_s, double shifted_s, double rate_error,
                      double curvature_per_s) {
  const double rest_s = truth_s - shifted_s;
  return rest_s * (1.0 + rate_error) + curvature_per_s * rest_s * rest_s;
}

struct Rounds {
  int rounds = 0;
  double estimate_s = 0.0;  // what the poses carry plus what the last solve left
};

// The rounds of solve_policy.cc for one delay of σ sigma_s.
Rounds RunRounds(const ClockRoundRule& rule, double truth_s, double sigma_s, double rate_error,
              double curvature_per_s) {
  Rounds run;
  double shifted_s = 0.0;
  double moved_s = std::numeric_limits<double>::quiet_NaN();
  double left_s = LeftAfterSolve(truth_s, shifted_s, rate_error, curvature_per_s);
  while (run.rounds < rule.max_rounds &&
         WorthARound(rule, PredictedRoundChange(left_s, moved_s), sigma_s)) {
    ++run.rounds;
    shifted_s += left_s;
    moved_s = left_s;
    left_s = LeftAfterSolve(truth_s, shifted_s, rate_error, curvature_per_s);
  }
  run.estimate_s = shifted_s + left_s;
  return run;
}

TEST(ClockRoundsTest, NothingLeftNothingPredicted) {
  EXPECT_EQ(PredictedRoundChange(0.0), 0.0);
  EXPECT_EQ(PredictedRoundChange(0.0, 0.03), 0.0);
  EXPECT_EQ(PredictedRoundChange(0.01), 0.01);  // before any round: all of it
  EXPECT_DOUBLE_EQ(PredictedRoundChange(-0.001, 0.03), -0.001 * 2.0 * (0.001 / 0.03));
  EXPECT_EQ(PredictedRoundChange(0.02, 0.01), 0.02);
  EXPECT_EQ(PredictedRoundChange(0.006, 0.01), 0.006);  // no contraction: no better than none
  const ClockRoundRule rule;
  EXPECT_FALSE(WorthARound(rule, 0.0, 1e-3));
  EXPECT_FALSE(WorthARound(rule, 1e-4, 1e-5));   // below the tolerance
  EXPECT_FALSE(WorthARound(rule, 2e-3, 1e-2));   // below a quarter of σ
  EXPECT_TRUE(WorthARound(rule, -3e-3, 1e-2));
}

// Nothing to move: no round at all, on a delay of any size the linear model gets right within
// a quarter of its σ.
TEST(ClockRoundsTest, StopsAtOnceWhenNothingMoves) {
  const ClockRoundRule rule;
  EXPECT_EQ(RunRounds(rule, 0.0, 2e-4, 0.2, 2.0).rounds, 0);
  EXPECT_EQ(RunRounds(rule, 4e-5, 2e-4, 0.0, 0.0).rounds, 0);
}

// The hour with drives' numbers (a 27.8 ms first estimate that the rounds bring to 27.2 ms,
// σ 0.2 ms) and a harder one (150 ms, 10 % rate error, σ 1 ms): the rounds stop once the next
// would change the estimate by less than a quarter of σ, and the estimate is then that close to
// where rounds without end would take it (the truth, in this model), in fewer rounds than the
// cap.
TEST(ClockRoundsTest, ConvergesToWithinAFractionOfSigma) {
  const ClockRoundRule rule;
  struct Case {
    double truth_s, sigma_s, rate_error, curvature_per_s;
  };
  for (const Case& c : {Case{0.0272, 2e-4, 0.0, 0.8}, Case{0.15, 1e-3, -0.1, 1.0},
                        Case{-0.036, 6e-4, 0.1, -0.5}}) {
    const Rounds run = RunRounds(rule, c.truth_s, c.sigma_s, c.rate_error, c.curvature_per_s);
    const double first_s = LeftAfterSolve(c.truth_s, 0.0, c.rate_error, c.curvature_per_s);
    ASSERT_GT(std::abs(first_s - c.truth_s), rule.sigma_fraction * c.sigma_s)
        << "the case must need a round";
    EXPECT_GE(run.rounds, 1);
    EXPECT_LT(run.rounds, rule.max_rounds) << "stopped by the rule, not the cap";
    EXPECT_LT(std::abs(run.estimate_s - c.truth_s), rule.sigma_fraction * c.sigma_s)
        << "truth " << c.truth_s << " estimate " << run.estimate_s << " after " << run.rounds;
  }
  // Without the prediction (every round's change taken as all that is left) the same accuracy
  // costs a round more on the hour's numbers: the round that confirms.
  ClockRoundRule many = rule;
  many.max_rounds = 10;
  const Rounds hour = RunRounds(many, 0.0272, 2e-4, 0.0, 0.8);
  int confirming = 0;
  for (double shifted_s = 0.0, left_s = LeftAfterSolve(0.0272, 0.0, 0.0, 0.8);
       WorthARound(rule, left_s, 2e-4); left_s = LeftAfterSolve(0.0272, shifted_s, 0.0, 0.8)) {
    shifted_s += left_s;
    ++confirming;
  }
  EXPECT_LT(hour.rounds, confirming);
}

}  // namespace
}  // namespace wallcal::solvers
