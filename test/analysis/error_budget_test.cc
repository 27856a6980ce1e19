// SPDX-License-Identifier: Apache-2.0
// What the mount's σ is made of (analysis/error_budget.h), on synthetic sessions whose error
// sources are known: the total is the adjustment's variance, each source's share lies within
// it, and the source the session is made to be dominated by is named.

#include "analysis/error_budget.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "sim/synthetic_observations.h"
#include "solvers/mount_solver.h"
#include "test/support/synthetic_fixtures.h"

namespace wallcal::analysis {
namespace {

using testing_support::OptionsFor;

// A session drawn from `settings` with `seed`, solved, and its budget at the estimate.
struct Budgeted {
  solvers::MountEstimate estimate;
  ErrorBudget budget;
};
Budgeted SolveAndBudget(const sim::SimSettings& settings, unsigned seed) {
  std::mt19937 rng(seed);
  const sim::SimData data = sim::SimulateObservations(settings, rng);
  const solvers::SolverOptions options = OptionsFor(settings);
  Budgeted out;
  out.estimate = solvers::SolveMountCeres(data.observations, data.walls, options, settings.truth);
  if (out.estimate.usable) {
    out.budget = ComputeErrorBudget(data.observations, data.walls, options, out.estimate.mount);
  }
  return out;
}

TEST(ErrorBudgetTest, SharesLieWithinTheAdjustmentsVariance) {
  const Budgeted run = SolveAndBudget(sim::SimSettings(), 5);
  const solvers::MountEstimate& estimate = run.estimate;
  const ErrorBudget& budget = run.budget;
  ASSERT_TRUE(estimate.usable) << estimate.message;
  ASSERT_TRUE(budget.done);
  for (int axis = 0; axis < 3; ++axis) {
    // The budget's linearised variance is the adjustment's (both from the information matrix
    // at the estimate; the budget's weights are its own linearisation: a few per cent apart).
    const double total = budget.total_variance[axis];
    EXPECT_NEAR(total, estimate.covariance(axis, axis), 0.05 * estimate.covariance(axis, axis))
        << "axis " << axis;
    for (int s = 0; s < kNumErrorSources; ++s) {
      EXPECT_GE(budget.variance[s][axis], 0.0) << ErrorSourceName(static_cast<ErrorSource>(s));
      EXPECT_LE(budget.variance[s][axis], total * (1.0 + 1e-9))
          << ErrorSourceName(static_cast<ErrorSource>(s));
    }
    EXPECT_GE(budget.dominant_share[axis], 0.0);
    EXPECT_LE(budget.dominant_share[axis], 1.0 + 1e-9);
    EXPECT_NEAR(budget.dominant_share[axis],
                budget.variance[static_cast<int>(budget.dominant[axis])][axis] / total, 1e-9);
  }
}

TEST(ErrorBudgetTest, ALargeRtkErrorDominatesTheOffsets) {
  // 4 cm of RTK error per station against 3 mm line fits and a 5 mm survey: the offsets' σ is
  // the GNSS error's (and still within the accepted 5 cm).
  sim::SimSettings settings;
  settings.gnss_bias_sigma_m = 0.04;
  const Budgeted run = SolveAndBudget(settings, 6);
  ASSERT_TRUE(run.estimate.usable) << run.estimate.message;
  const ErrorBudget& budget = run.budget;
  ASSERT_TRUE(budget.done);
  for (int axis = 0; axis < 2; ++axis) {
    EXPECT_EQ(budget.dominant[axis], ErrorSource::kGnss) << "axis " << axis;
    EXPECT_GT(budget.dominant_share[axis], 0.5) << "axis " << axis;
  }
}

}  // namespace
}  // namespace wallcal::analysis
