// SPDX-License-Identifier: Apache-2.0
// Observations added to a built problem (solvers/problem_extension.h): the mount's information
// from the base's marginal onto the shared blocks plus the extension equals the information of
// the problem built from both sets; additions that would change the base are refused.
#include "solvers/problem_extension.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "sim/synthetic_observations.h"
#include "solvers/information.h"
#include "solvers/mount_problem.h"
#include "test/support/synthetic_fixtures.h"

namespace wallcal::solvers {
namespace {

// Two walls, stations 20 s apart (their GNSS errors correlated under τ = 60 s), the dwell's
// heading from its samples, the mount to start 5 cm and 0.3° off (the Jacobians away from the
// truth, some scans in the robust loss's linear region).
struct Split {
  std::vector<calib::WallObservation> base, extra;
  std::vector<double> base_weights, extra_weights;
  std::vector<calib::WallGeometry> walls;
  SolverOptions options;
  Mount start;
};

Split MakeSplit(int first_extra_station) {
  sim::SimSettings settings;
  settings.second_wall = true;
  settings.station_spacing_s = 20.0;
  settings.bias_tau_s = 60.0;
  settings.dwell_heading_samples = 40;
  std::mt19937 rng(5);
  const sim::SimData data = sim::SimulateObservations(settings, rng);
  Split split;
  split.walls = data.walls;
  split.options = testing_support::OptionsFor(settings);
  split.options.huber_scale = 1.0;
  split.start = settings.truth;
  split.start.x_m += 0.05;
  split.start.yaw_rad += 0.3 * kDegToRad;
  for (size_t i = 0; i < data.observations.size(); ++i) {
    const calib::WallObservation& o = data.observations[i];
    if (o.pose.segment < first_extra_station) {
      split.base.push_back(o);
      split.base_weights.push_back(3.0);  // a thinned set
    } else {
      split.extra.push_back(o);
      split.extra_weights.push_back(1.0 + static_cast<double>(i % 3));
    }
  }
  return split;
}

Eigen::Matrix3d Covariance(const Eigen::Matrix3d& information) {
  Eigen::MatrixXd covariance;
  EXPECT_TRUE(CovarianceOfKept(information, &covariance));
  return covariance;
}

TEST(ProblemExtensionTest, MountInformationEqualsTheProblemBuiltFromBoth) {
  const Split split = MakeSplit(7);
  ASSERT_FALSE(split.base.empty());
  ASSERT_FALSE(split.extra.empty());
  std::vector<calib::WallObservation> all = split.base;
  all.insert(all.end(), split.extra.begin(), split.extra.end());
  std::vector<double> all_weights = split.base_weights;
  all_weights.insert(all_weights.end(), split.extra_weights.begin(), split.extra_weights.end());
  std::string error;
  auto both = BuildMountProblem(all, split.walls, split.options, split.start, split.start, &error,
                                all_weights);
  ASSERT_NE(both, nullptr) << error;
  auto base = BuildMountProblem(split.base, split.walls, split.options, split.start, split.start,
                                &error, split.base_weights);
  ASSERT_NE(base, nullptr) << error;

  const SharedInformation shared = MarginalOntoShared(*base);
  // mount 3, two walls 2 each, the drift rate, the last slice 2 (no moving scans: no clock).
  ASSERT_EQ(shared.information.rows(), 10);
  const Eigen::Matrix3d base_covariance = Covariance(MountInformation(*base));
  EXPECT_LT((Covariance(MountInformation(shared)) - base_covariance).norm(),
            1e-9 * base_covariance.norm());

  ExtensionOutcome outcome = ExtensionOutcome::kChangesBase;
  auto extension = ExtendMountProblem(*base, split.extra, split.walls, split.options, split.start,
                                      split.extra_weights, &outcome);
  ASSERT_EQ(outcome, ExtensionOutcome::kExtended);
  ASSERT_NE(extension, nullptr);
  const Eigen::Matrix3d expected = Covariance(MountInformation(*both));
  const Eigen::Matrix3d extended = Covariance(ExtendedMountInformation(shared, *extension));
  EXPECT_LT((extended - expected).norm(), 1e-9 * expected.norm());
  // The extra stations are worth something: the check above is not the base's σ again.
  EXPECT_LT(expected(0, 0), 0.95 * base_covariance(0, 0));
}

TEST(ProblemExtensionTest, RefusesObservationsThatWouldChangeTheBase) {
  const Split split = MakeSplit(7);
  std::string error;
  auto base = BuildMountProblem(split.base, split.walls, split.options, split.start, split.start,
                                &error, split.base_weights);
  ASSERT_NE(base, nullptr) << error;
  ExtensionOutcome outcome = ExtensionOutcome::kExtended;
  // A station the base has (its dwell's heading and its GNSS slice would change).
  std::vector<calib::WallObservation> again = {split.base.back()};
  again.front().pose.stamp_s = split.extra.front().pose.stamp_s;
  EXPECT_EQ(ExtendMountProblem(*base, again, split.walls, split.options, split.start, {}, &outcome),
            nullptr);
  EXPECT_EQ(outcome, ExtensionOutcome::kChangesBase);
  // A moving scan (the clock block would be estimated).
  std::vector<calib::WallObservation> moving = {split.extra.front()};
  moving.front().pose.stationary = false;
  EXPECT_EQ(
      ExtendMountProblem(*base, moving, split.walls, split.options, split.start, {}, &outcome),
      nullptr);
  EXPECT_EQ(outcome, ExtensionOutcome::kChangesBase);
  // A wall the base does not use (the walls' joint prior would change).
  std::vector<calib::WallObservation> one_wall;
  for (const calib::WallObservation& o : split.base) {
    if (o.wall_index == 0) one_wall.push_back(o);
  }
  auto first_wall_only =
      BuildMountProblem(one_wall, split.walls, split.options, split.start, split.start, &error);
  ASSERT_NE(first_wall_only, nullptr) << error;
  EXPECT_EQ(ExtendMountProblem(*first_wall_only, split.extra, split.walls, split.options,
                               split.start, {}, &outcome),
            nullptr);
  EXPECT_EQ(outcome, ExtensionOutcome::kChangesBase);
  // The same extra observations on the base itself are taken.
  EXPECT_NE(
      ExtendMountProblem(*base, split.extra, split.walls, split.options, split.start, {}, &outcome),
      nullptr);
  EXPECT_EQ(outcome, ExtensionOutcome::kExtended);
}

}  // namespace
}  // namespace wallcal::solvers
