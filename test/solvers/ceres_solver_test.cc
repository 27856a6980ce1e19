// SPDX-License-Identifier: Apache-2.0
// Tests of the joint mount adjustment (solvers/ceres_solver.cc), on wall observations
// synthesised from a known mount, known walls and known poses. Its cost functors:
// test/cost_functors_test.cc.

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "calib/wall_geometry.h"
#include "sim/synthetic_observations.h"
#include "test/support/expect_text.h"
#include "test/support/synthetic_fixtures.h"
#include "solvers/information.h"
#include "solvers/mount_problem.h"
#include "solvers/mount_solver.h"
#include "solvers/prior_cost.h"
#include "solvers/wall_line_cost.h"
#include "common/angles.h"

namespace wallcal::solvers {
namespace {
// Synthetic observations: the shared fixture (sim/synthetic_observations.h).
using sim::SimData;
using sim::SimSettings;
SimData Simulate(const SimSettings& s, std::mt19937& rng) { return sim::SimulateObservations(s, rng); }

// The noise model the solver is told, matching the simulation.
using testing_support::OptionsFor;

Eigen::Vector3d Error(const MountEstimate& estimate, const Mount& truth) {
  return Eigen::Vector3d(estimate.mount.x_m - truth.x_m, estimate.mount.y_m - truth.y_m,
                         WrapAngle(estimate.mount.yaw_rad - truth.yaw_rad));
}

Eigen::Vector3d Sigma(const MountEstimate& estimate) {
  return estimate.covariance.diagonal().cwiseSqrt();
}

// The adjustment of `data` from a zero mount, told the noise `settings` drew it with.
MountEstimate SolveFromZero(const SimData& data, const SimSettings& settings) {
  return SolveMountCeres(data.observations, data.walls, OptionsFor(settings), Mount{});
}

// A start away from the truth, as the first pass gives one: 10 cm and 1° off, about ten times
// the σ of the sessions these tests simulate, so that an estimate that stays at its start
// cannot pass for an honest one.
Mount AwayFrom(const Mount& truth) {
  return Mount{truth.x_m + 0.10, truth.y_m - 0.10, truth.yaw_rad + 1.0 * kDegToRad};
}

// RMS of error/σ per axis (x, y, yaw) over `draws` sessions simulated with `settings` from
// `seed`, each solved from a start away from the truth: about 1 when the reported σ is honest.
// A draw the solver refuses fails the test and makes the result NaN.
Eigen::Vector3d RmsNormalisedError(const SimSettings& settings, unsigned seed, int draws) {
  const solvers::SolverOptions options = OptionsFor(settings);
  std::mt19937 rng(seed);
  Eigen::Vector3d sum_sq = Eigen::Vector3d::Zero();
  for (int draw = 0; draw < draws; ++draw) {
    const SimData data = Simulate(settings, rng);
    const MountEstimate estimate =
        SolveMountCeres(data.observations, data.walls, options, AwayFrom(settings.truth));
    if (!estimate.usable) {
      ADD_FAILURE() << "draw " << draw << ": " << estimate.message;
      return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    }
    sum_sq += Error(estimate, settings.truth).cwiseQuotient(Sigma(estimate)).cwiseAbs2();
  }
  return (sum_sq / draws).cwiseSqrt();
}

// ---- The solver -----------------------------------------------------------------------------

TEST(SolveMountCeresTest, RecoversKnownMountFromSeveralStarts) {
  SimSettings settings;
  std::mt19937 rng(20070531);
  const SimData data = Simulate(settings, rng);
  const solvers::SolverOptions options = OptionsFor(settings);
  const Mount& t = settings.truth;
  const double d_yaw = 10.0 * kDegToRad;
  const std::vector<Mount> starts = {{0.0, 0.0, 0.0},
                                     {t.x_m + 0.5, t.y_m + 0.5, t.yaw_rad + d_yaw},
                                     {t.x_m - 0.5, t.y_m - 0.5, t.yaw_rad - d_yaw},
                                     {t.x_m + 0.5, t.y_m - 0.5, t.yaw_rad - d_yaw}};
  std::vector<MountEstimate> estimates;
  for (const Mount& start : starts) {
    const MountEstimate estimate = SolveMountCeres(data.observations, data.walls, options, start);
    ASSERT_TRUE(estimate.usable) << estimate.message;
    EXPECT_EQ(estimate.method, solvers::Method::kCeres);
    const Eigen::Vector3d error = Error(estimate, t);
    const Eigen::Vector3d sigma = Sigma(estimate);
    // σ from the noise: ~1.5 cm GNSS bias over 10 stations, a few mm of wall, 1 mrad of wall
    // direction; the error must be within 4σ, and σ itself of that order.
    EXPECT_LT(sigma.x(), 0.02);
    EXPECT_LT(sigma.y(), 0.03);
    EXPECT_LT(sigma.z(), 0.003);
    for (int k = 0; k < 3; ++k) EXPECT_LT(std::abs(error[k]), 4.0 * sigma[k]) << "axis " << k;
    EXPECT_EQ(static_cast<int>(estimate.residual_rho_m.size()),
              static_cast<int>(data.observations.size()));
    EXPECT_GT(estimate.residual_rms_m, 0.001);
    EXPECT_LT(estimate.residual_rms_m, 0.02);
    EXPECT_FALSE(estimate.solver_report.empty());
    estimates.push_back(estimate);
  }
  // Every start reaches the same minimum.
  for (const auto& estimate : estimates) {
    EXPECT_NEAR(estimate.mount.x_m, estimates[0].mount.x_m, 1e-4);
    EXPECT_NEAR(estimate.mount.y_m, estimates[0].mount.y_m, 1e-4);
    EXPECT_NEAR(estimate.mount.yaw_rad, estimates[0].mount.yaw_rad, 1e-5);
  }
}

TEST(SolveMountCeresTest, ReportedSigmaMatchesScatterUnderCorrelatedGnssError) {
  const Eigen::Vector3d rms = RmsNormalisedError(SimSettings(), 42, 100);
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT(rms[k], 0.6) << "axis " << k;
    EXPECT_LT(rms[k], 1.6) << "axis " << k;
  }
}

TEST(SolveMountCeresTest, SigmaDoesNotShrinkWithMoreScansPerStation) {
  SimSettings settings;
  const solvers::SolverOptions options = OptionsFor(settings);
  std::mt19937 rng(7);
  const SimData few = Simulate(settings, rng);
  settings.scans_per_station *= 10;
  const SimData many = Simulate(settings, rng);
  const MountEstimate a = SolveMountCeres(few.observations, few.walls, options, settings.truth);
  const MountEstimate b = SolveMountCeres(many.observations, many.walls, options, settings.truth);
  ASSERT_TRUE(a.usable) << a.message;
  ASSERT_TRUE(b.usable) << b.message;
  // Independent scans would give a ratio of 1/√10 ≈ 0.32; the station's shared GNSS error and
  // the wall's survey error keep it close to 1.
  const Eigen::Vector3d ratio = Sigma(b).cwiseQuotient(Sigma(a));
  EXPECT_GT(ratio.x(), 0.8);
  EXPECT_GT(ratio.y(), 0.8);
  EXPECT_GT(ratio.z(), 0.6);
  EXPECT_LE(ratio.maxCoeff(), 1.0 + 1e-9);
}

TEST(SolveMountCeresTest, SecondPerpendicularWallShrinksSigma) {
  SimSettings settings;
  settings.heading_half_spread_rad = 12.0 * kDegToRad;  // 24°: allowed, but weak sideways
  const solvers::SolverOptions options = OptionsFor(settings);
  std::mt19937 rng(11);
  const SimData one = Simulate(settings, rng);
  settings.second_wall = true;
  const SimData two = Simulate(settings, rng);
  const MountEstimate a = SolveMountCeres(one.observations, one.walls, options, settings.truth);
  const MountEstimate b = SolveMountCeres(two.observations, two.walls, options, settings.truth);
  ASSERT_TRUE(a.usable) << a.message;
  ASSERT_TRUE(b.usable) << b.message;
  // Facing the north wall, y (lateral) is the weak axis; the east wall measures it directly.
  EXPECT_LT(Sigma(b).y(), 0.5 * Sigma(a).y());
  EXPECT_LT(Sigma(b).x(), Sigma(a).x());
  EXPECT_LT(std::abs(b.mount.y_m - settings.truth.y_m), 4.0 * Sigma(b).y());
}

TEST(WallPriorCovarianceTest, WallsOfOneTieShareItsTranslationAndRotation) {
  SimSettings settings;
  std::mt19937 rng(3);
  SimData data = Simulate(settings, rng);
  // north: normal (0, 1), lever 2 m from the control centroid; east: normal (1, 0), lever −3 m.
  const double st = 0.01, sr = 0.0008;
  const double levers[2] = {2.0, -3.0};
  for (int w = 0; w < 2; ++w) {
    data.walls[w].tie_sigma_translation_m = st;
    data.walls[w].tie_sigma_rotation_rad = sr;
    data.walls[w].tie_lever_m = levers[w];
    data.walls[w].cov_offset_angle = sr * sr * levers[w];
  }
  const Eigen::MatrixXd c = WallPriorCovariance(data.walls, {0, 1});
  ASSERT_EQ(c.rows(), 4);
  // Own blocks: the walls' σ's and their offset–angle covariance.
  EXPECT_DOUBLE_EQ(c(0, 0), settings.wall_sigma_offset_m * settings.wall_sigma_offset_m);
  EXPECT_DOUBLE_EQ(c(1, 1), settings.wall_sigma_angle_rad * settings.wall_sigma_angle_rad);
  EXPECT_DOUBLE_EQ(c(0, 1), sr * sr * 2.0);
  // Shared: perpendicular normals see independent translation components; both turn with the
  // tie's rotation, which moves each offset by its lever.
  EXPECT_NEAR(c(0, 2), sr * sr * 2.0 * -3.0, 1e-15);
  EXPECT_NEAR(c(0, 3), sr * sr * 2.0, 1e-15);
  EXPECT_NEAR(c(1, 2), sr * sr * -3.0, 1e-15);
  EXPECT_NEAR(c(1, 3), sr * sr, 1e-15);
  EXPECT_TRUE(c.isApprox(c.transpose()));
  // Walls made without a tie share nothing.
  data.walls[1].tie_sigma_rotation_rad = 0.0;
  data.walls[1].tie_sigma_translation_m = 0.0;
  const Eigen::MatrixXd independent = WallPriorCovariance(data.walls, {0, 1});
  EXPECT_EQ(independent.topRightCorner(2, 2).norm(), 0.0);
}

TEST(SolveMountCeresTest, TwoWallsOfOneTieShareItsRotationInTheYawSigma) {
  // The tie's rotation error turns both walls alike, and the mount yaw shifts every scan's
  // line direction alike: a second wall of the same tie adds little to the yaw. Counting the
  // walls' directions as independent would divide the yaw σ by about √2 (the bench's two-wall
  // scenario had σ_yaw 0.032° against a bound of 0.046° before the joint prior).
  SimSettings settings;
  const double sr = 0.001;  // rotation σ of the tie, dominating each wall's direction σ
  settings.wall_sigma_angle_rad = std::hypot(sr, 0.0002);
  const solvers::SolverOptions options = OptionsFor(settings);
  std::mt19937 rng(5);
  const SimData one = Simulate(settings, rng);
  settings.second_wall = true;
  SimData two = Simulate(settings, rng);
  const MountEstimate independent =
      SolveMountCeres(two.observations, two.walls, options, settings.truth);
  for (auto& wall : two.walls) {
    wall.tie_sigma_translation_m = 0.003;
    wall.tie_sigma_rotation_rad = sr;
  }
  const MountEstimate shared =
      SolveMountCeres(two.observations, two.walls, options, settings.truth);
  const MountEstimate single =
      SolveMountCeres(one.observations, one.walls, options, settings.truth);
  ASSERT_TRUE(independent.usable) << independent.message;
  ASSERT_TRUE(shared.usable) << shared.message;
  ASSERT_TRUE(single.usable) << single.message;
  std::printf("[ tie      ] yaw sigma: one wall %.5f, two walls shared %.5f, independent %.5f rad\n",
              Sigma(single).z(), Sigma(shared).z(), Sigma(independent).z());
  EXPECT_GT(Sigma(shared).z(), 0.9 * Sigma(single).z());
  EXPECT_LT(Sigma(independent).z(), 0.85 * Sigma(shared).z());
}

TEST(SolveMountCeresTest, OutliersDoNotMoveTheEstimate) {
  SimSettings settings;
  std::mt19937 rng(99);
  const SimData clean = Simulate(settings, rng);
  std::mt19937 same_rng(99);
  settings.outlier_fraction = 0.1;
  const SimData dirty = Simulate(settings, same_rng);
  int outliers = 0;
  for (bool o : dirty.is_outlier) outliers += o ? 1 : 0;
  ASSERT_GT(outliers, 5);

  solvers::SolverOptions options = OptionsFor(settings);
  const MountEstimate reference =
      SolveMountCeres(clean.observations, clean.walls, options, Mount{});
  const MountEstimate robust = SolveMountCeres(dirty.observations, dirty.walls, options, Mount{});
  ASSERT_TRUE(reference.usable) << reference.message;
  ASSERT_TRUE(robust.usable) << robust.message;
  const double tolerance_m = 0.5 * Sigma(reference).head<2>().minCoeff();
  EXPECT_NEAR(robust.mount.x_m, reference.mount.x_m, tolerance_m);
  EXPECT_NEAR(robust.mount.y_m, reference.mount.y_m, tolerance_m);
  EXPECT_NEAR(robust.mount.yaw_rad, reference.mount.yaw_rad, 0.5 * Sigma(reference).z());
  EXPECT_GE(robust.observations_rejected, outliers);
  EXPECT_LE(robust.observations_rejected,
            outliers + static_cast<int>(0.05 * dirty.observations.size()));
  EXPECT_EQ(robust.observations_used + robust.observations_rejected,
            static_cast<int>(dirty.observations.size()));
  // Each outlier's rho residual shows its +0.5 m (observed − predicted).
  for (size_t i = 0; i < dirty.is_outlier.size(); ++i) {
    if (dirty.is_outlier[i]) {
      EXPECT_GT(robust.residual_rho_m[i], 0.4);
    }
  }

  // Without the robust loss the same data pull the estimate well beyond that tolerance: the
  // check above is not vacuous.
  options.huber_scale = 0.0;
  const MountEstimate plain = SolveMountCeres(dirty.observations, dirty.walls, options, Mount{});
  ASSERT_TRUE(plain.usable) << plain.message;
  EXPECT_GT(
      std::hypot(plain.mount.x_m - reference.mount.x_m, plain.mount.y_m - reference.mount.y_m),
      4.0 * tolerance_m);
}

TEST(SolveMountCeresTest, RefusesNarrowHeadingSpreadAndNamesTheWeakAxis) {
  SimSettings settings;
  settings.heading_half_spread_rad = 5.0 * kDegToRad;
  std::mt19937 rng(3);
  const SimData facing = Simulate(settings, rng);
  const solvers::SolverOptions options = OptionsFor(settings);
  const MountEstimate a = SolveMountCeres(facing.observations, facing.walls, options, Mount{});
  EXPECT_FALSE(a.usable);
  testing_support::ExpectContains(a.message, {
      "vehicle-to-wall angles",
      "lateral offset y is not determined",
      "30°"
  });
  // The same for the closed form (one shared check).
  const MountEstimate closed = SolveMountBarawid(facing.observations, facing.walls, options);
  EXPECT_FALSE(closed.usable);
  EXPECT_EQ(closed.message, a.message);

  // Driving along the wall (it is on the vehicle's left): the forward offset is the weak one.
  settings.base_heading_rad = 0.0;
  const SimData alongside = Simulate(settings, rng);
  const MountEstimate b =
      SolveMountCeres(alongside.observations, alongside.walls, options, Mount{});
  EXPECT_FALSE(b.usable);
  EXPECT_NE(b.message.find("forward offset x is not determined"), std::string::npos) << b.message;
}

TEST(SolveMountCeresTest, RefusesTooFewObservationsAndStations) {
  SimSettings settings;
  settings.stations = 5;
  settings.scans_per_station = 2;
  std::mt19937 rng(5);
  const SimData data = Simulate(settings, rng);
  const MountEstimate estimate = SolveFromZero(data, settings);
  EXPECT_FALSE(estimate.usable);
  EXPECT_NE(estimate.message.find("only 10 wall observations; need at least 30"), std::string::npos)
      << estimate.message;

  settings.stations = 2;
  settings.scans_per_station = 50;
  const SimData two = Simulate(settings, rng);
  const MountEstimate stations = SolveFromZero(two, settings);
  EXPECT_FALSE(stations.usable);
  EXPECT_NE(stations.message.find("only 2 stations"), std::string::npos) << stations.message;

  const MountEstimate none = SolveMountCeres({}, data.walls, OptionsFor(settings), Mount{});
  EXPECT_FALSE(none.usable);
}

TEST(SolveMountCeresTest, FixedWallsAndBiasesAreHeldConstant) {
  // σ = 0 for the wall and the GNSS bias: the survey and positions are taken as exact (the
  // blocks are constant), and on noise-free data the mount comes back exactly.
  SimSettings settings;
  settings.noise = false;
  settings.wall_sigma_offset_m = 0.0;
  settings.wall_sigma_angle_rad = 0.0;
  settings.gnss_bias_sigma_m = 0.0;
  std::mt19937 rng(1);
  const SimData data = Simulate(settings, rng);
  const MountEstimate estimate = SolveFromZero(data, settings);
  ASSERT_TRUE(estimate.usable) << estimate.message;
  EXPECT_NEAR(estimate.mount.x_m, settings.truth.x_m, 1e-7);
  EXPECT_NEAR(estimate.mount.y_m, settings.truth.y_m, 1e-7);
  EXPECT_NEAR(estimate.mount.yaw_rad, settings.truth.yaw_rad, 1e-8);
  EXPECT_EQ(estimate.observations_rejected, 0);

  // Only the wall offset known exactly: a subset manifold keeps it, the direction is free.
  const solvers::SolverOptions options = OptionsFor(settings);
  settings.wall_sigma_angle_rad = 0.001;
  const SimData half = Simulate(settings, rng);
  std::string error;
  auto problem = BuildMountProblem(half.observations, half.walls, options, settings.truth,
                                   settings.truth, &error);
  ASSERT_NE(problem, nullptr) << error;
  EXPECT_NE(problem->problem.GetManifold(problem->wall_deltas[0].data()), nullptr);
  EXPECT_TRUE(problem->problem.IsParameterBlockConstant(problem->no_bias.data()));
  const MountEstimate solved = SolveMountProblem(*problem, options);
  ASSERT_TRUE(solved.usable) << solved.message;
  EXPECT_EQ(problem->wall_deltas[0][0], 0.0);
}

TEST(SolveMountCeresTest, TakesBiasSigmaFromGstAndSkipsBiasWithoutSegment) {
  SimSettings settings;
  std::mt19937 rng(8);
  SimData data = Simulate(settings, rng);
  // Station 0 logged GST σ of 0.01 and 0.03 m (mean 0.02); station 1 none (configured σ);
  // observations of station 2 have no segment.
  for (size_t i = 0; i < data.observations.size(); ++i) {
    auto& pose = data.observations[i].pose;
    if (pose.segment == 0) pose.gnss_sigma_m = (i % 2 == 0) ? 0.01 : 0.03;
    if (pose.segment == 2) pose.segment = -1;
  }
  solvers::SolverOptions options = OptionsFor(settings);
  options.use_gst_sigma = true;
  std::string error;
  auto problem = BuildMountProblem(data.observations, data.walls, options, settings.truth,
                                   settings.truth, &error);
  ASSERT_NE(problem, nullptr) << error;
  ASSERT_EQ(problem->segment_ids.size(), 9u);
  EXPECT_EQ(problem->segment_ids[0], 0);
  EXPECT_NEAR(problem->bias_sigma_m[0], 0.02, 1e-12);
  EXPECT_NEAR(problem->bias_sigma_m[1], settings.gnss_bias_sigma_m, 1e-12);
  for (size_t i = 0; i < data.observations.size(); ++i) {
    EXPECT_EQ(problem->bias_block[i] == problem->no_bias.data(),
              data.observations[i].pose.segment < 0);
  }
  EXPECT_TRUE(problem->problem.IsParameterBlockConstant(problem->no_bias.data()));
  const MountEstimate estimate = SolveMountProblem(*problem, options);
  ASSERT_TRUE(estimate.usable) << estimate.message;
  EXPECT_LT(std::abs(estimate.mount.x_m - settings.truth.x_m), 4.0 * Sigma(estimate).x());

  // Without GST the configured σ applies everywhere.
  options.use_gst_sigma = false;
  auto plain = BuildMountProblem(data.observations, data.walls, options, settings.truth,
                                 settings.truth, &error);
  ASSERT_NE(plain, nullptr) << error;
  EXPECT_NEAR(plain->bias_sigma_m[0], settings.gnss_bias_sigma_m, 1e-12);
}

TEST(SolveMountCeresTest, PredictionsMatchNoiseFreeObservations) {
  SimSettings settings;
  settings.noise = false;
  std::mt19937 rng(2);
  const SimData data = Simulate(settings, rng);
  for (const auto& observation : data.observations) {
    const auto& wall = data.walls[observation.wall_index];
    EXPECT_NEAR(calib::PredictRho(observation, wall, settings.truth), observation.rho_m, 1e-12);
    EXPECT_NEAR(WrapAngle(calib::PredictTheta(observation, wall, settings.truth) - observation.theta_rad),
                0.0, 1e-12);
  }
}



// ---- Gauss–Markov GNSS error, determination checks, clock offset ----------------------------

TEST(SolveMountCeresTest, StationsCloseInTimeShareTheirGnssErrorInTheSigma) {
  SimSettings settings;
  const solvers::SolverOptions options = OptionsFor(settings);  // τ = 60 s
  std::mt19937 rng(21);
  const SimData apart = Simulate(settings, rng);  // 10 min between stations
  settings.station_spacing_s = 10.0;
  const SimData close = Simulate(settings, rng);
  const MountEstimate a = SolveMountCeres(apart.observations, apart.walls, options, settings.truth);
  const MountEstimate b = SolveMountCeres(close.observations, close.walls, options, settings.truth);
  ASSERT_TRUE(a.usable) << a.message;
  ASSERT_TRUE(b.usable) << b.message;
  EXPECT_NEAR(a.independent_stations, 10.0, 1e-6);
  EXPECT_LT(b.independent_stations, 4.0);
  // Correlated stations average less of the GNSS error away: the forward σ grows.
  EXPECT_GT(Sigma(b).x(), 1.2 * Sigma(a).x());
  // τ = 0 turns the chain off: the close stations count as independent again.
  solvers::SolverOptions independent = options;
  independent.gnss_bias_tau_s = 0.0;
  const MountEstimate c =
      SolveMountCeres(close.observations, close.walls, independent, settings.truth);
  ASSERT_TRUE(c.usable) << c.message;
  EXPECT_NEAR(c.independent_stations, 10.0, 1e-6);
  EXPECT_LT(Sigma(c).x(), Sigma(b).x());
}

TEST(SolveMountCeresTest, ReportedSigmaMatchesScatterUnderGaussMarkovGnssError) {
  // Stations 15 s apart with an RTK error of τ = 60 s (the simulator's): independent priors
  // per station would report a σ too small by about 1.5×.
  SimSettings settings;
  settings.station_spacing_s = 15.0;
  settings.bias_tau_s = 60.0;
  const Eigen::Vector3d rms = RmsNormalisedError(settings, 43, 100);
  std::printf("[ sigma    ] RMS(error/sigma) x %.2f  y %.2f  yaw %.2f\n", rms.x(), rms.y(),
              rms.z());
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT(rms[k], 0.75) << "axis " << k;
    EXPECT_LT(rms[k], 1.3) << "axis " << k;
  }
}

TEST(SolveMountCeresTest, ConditioningCheckRefusesAWeakAxisAndNamesIt) {
  // 8° of heading spread passes a relaxed spread check, but leaves the lateral offset with a
  // σ of decimetres: the information-matrix check refuses it and says which axis.
  SimSettings settings;
  settings.heading_half_spread_rad = 4.0 * kDegToRad;
  std::mt19937 rng(31);
  const SimData data = Simulate(settings, rng);
  solvers::SolverOptions options = OptionsFor(settings);
  options.min_heading_spread_rad = 0.0;
  const MountEstimate refused = SolveMountCeres(data.observations, data.walls, options, Mount{});
  EXPECT_FALSE(refused.usable);
  EXPECT_EQ(refused.weak_direction.rfind("lateral offset y", 0), 0u) << refused.weak_direction;
  testing_support::ExpectContains(refused.message, {
      "lateral offset y",
      "is not determined",
      "headings",
      "turned ≥ 30°"
  });

  // Forced: the estimate comes back usable, flagged, with the warning and a σ saying how
  // little is known sideways.
  const MountEstimate forced =
      SolveMountCeres(data.observations, data.walls, options, Mount{}, /*force=*/true);
  ASSERT_TRUE(forced.usable) << forced.message;
  EXPECT_TRUE(forced.forced);
  ASSERT_FALSE(forced.warnings.empty());
  EXPECT_EQ(forced.warnings.front().kind, SolverWarningKind::kForcedObservability);
  EXPECT_EQ(forced.warnings.front().message.rfind("FORCED: ", 0), 0u)
      << forced.warnings.front().message;
  EXPECT_GT(Sigma(forced).y(), options.max_sigma_xy_m);
  EXPECT_LT(Sigma(forced).x(), options.max_sigma_xy_m);

  // The same data with the wide spread check forced through too.
  solvers::SolverOptions strict = OptionsFor(settings);
  const MountEstimate both =
      SolveMountCeres(data.observations, data.walls, strict, Mount{}, /*force=*/true);
  ASSERT_TRUE(both.usable) << both.message;
  EXPECT_TRUE(both.forced);

  // A healthy session passes both checks untouched.
  SimSettings wide;
  const SimData good = Simulate(wide, rng);
  const MountEstimate fine = SolveMountCeres(good.observations, good.walls, OptionsFor(wide),
                                             Mount{}, /*force=*/true);
  ASSERT_TRUE(fine.usable) << fine.message;
  EXPECT_FALSE(fine.forced);
  EXPECT_TRUE(fine.weak_direction.empty());
}

TEST(SolveMountCeresTest, MountInformationMatchesTheCeresCovariance) {
  SimSettings settings;
  std::mt19937 rng(17);
  const SimData data = Simulate(settings, rng);
  const solvers::SolverOptions options = OptionsFor(settings);
  std::string error;
  auto problem = BuildMountProblem(data.observations, data.walls, options, settings.truth,
                                   settings.truth, &error);
  ASSERT_NE(problem, nullptr) << error;
  const MountEstimate estimate = SolveMountProblem(*problem, options);
  ASSERT_TRUE(estimate.usable) << estimate.message;
  const Eigen::Matrix3d from_information = MountInformation(*problem).inverse();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(std::sqrt(from_information(k, k)), std::sqrt(estimate.covariance(k, k)),
                0.02 * std::sqrt(estimate.covariance(k, k)))
        << "axis " << k;
  }
}

TEST(SolveMountCeresTest, RecoversAKnownScannerClockOffsetFromMovingScans) {
  // Moving stations (testing_support::MovingStations), the scanner's stamps 80 ms early: a
  // solver that ignored the offset would be biased; this one estimates it.
  const SimSettings settings = testing_support::MovingStations();
  std::mt19937 rng(9);
  const SimData data = Simulate(settings, rng);
  const solvers::SolverOptions options = OptionsFor(settings);
  const MountEstimate estimate =
      SolveMountCeres(data.observations, data.walls, options, settings.truth);
  ASSERT_TRUE(estimate.usable) << estimate.message;
  ASSERT_TRUE(estimate.time_offset_estimated);
  EXPECT_GT(estimate.time_offset_sigma_s, 0.0);
  EXPECT_LT(estimate.time_offset_sigma_s, 0.02);
  EXPECT_NEAR(estimate.time_offset_s, settings.time_offset_s,
              std::max(0.01, 4.0 * estimate.time_offset_sigma_s));
  const Eigen::Vector3d error = Error(estimate, settings.truth);
  EXPECT_LT(std::abs(error.x()), 4.0 * Sigma(estimate).x());
  EXPECT_LT(std::abs(error.z()), 4.0 * Sigma(estimate).z());

  // At stations (no motion) the offset is not in the data and is not estimated.
  SimSettings still;
  const SimData stationary = Simulate(still, rng);
  const MountEstimate held =
      SolveMountCeres(stationary.observations, stationary.walls, OptionsFor(still), still.truth);
  ASSERT_TRUE(held.usable) << held.message;
  EXPECT_FALSE(held.time_offset_estimated);
  EXPECT_EQ(held.time_offset_s, 0.0);
}

// A clock round's steps (ClockRoundStep): where the solve ended they stay (nothing to move), and
// started off the minimum in the clock offset by what a round leaves (a few of its σ) they land
// where a full solve from the same start does, to a small fraction of every σ, with the solve
// before's σ's carried.
TEST(ClockRoundStepTest, OneStepLandsWhereTheFullSolveDoes) {
  SimSettings settings;
  settings.speed_mps = 1.0;
  settings.yaw_rate_rps = 3.0 * kDegToRad;
  settings.time_offset_s = 0.08;
  settings.scans_per_station = 40;
  settings.alternate_direction = true;
  std::mt19937 rng(9);
  const SimData data = Simulate(settings, rng);
  const solvers::SolverOptions options = OptionsFor(settings);
  WarmStart ended;
  const MountEstimate solved = SolveMountCeres(data.observations, data.walls, options,
                                               settings.truth, false, nullptr, &ended);
  ASSERT_TRUE(solved.usable) << solved.message;
  ASSERT_TRUE(solved.time_offset_estimated);
  const Eigen::Vector3d sigma = Sigma(solved);
  const double dt_sigma_s = solved.time_offset_sigma_s;

  const MountEstimate still = ClockRoundStep(data.observations, data.walls, options, solved, ended,
                                             nullptr);
  ASSERT_TRUE(still.usable) << still.message;
  EXPECT_LT(std::abs(still.time_offset_s - solved.time_offset_s), 0.01 * dt_sigma_s);
  EXPECT_LT((Error(still, solved.mount).cwiseQuotient(sigma)).cwiseAbs().maxCoeff(), 0.01);

  WarmStart off = ended;
  off.time_offset_s += 3.0 * dt_sigma_s;
  const MountEstimate step =
      ClockRoundStep(data.observations, data.walls, options, solved, off, nullptr);
  const MountEstimate full =
      SolveMountCeres(data.observations, data.walls, options, solved.mount, false, &off);
  ASSERT_TRUE(step.usable) << step.message;
  ASSERT_TRUE(full.usable) << full.message;
  EXPECT_LT(std::abs(step.time_offset_s - full.time_offset_s), 0.05 * dt_sigma_s)
      << "step " << step.time_offset_s << " full " << full.time_offset_s;
  // One step gets x 0.12 σ from the full solve here, where 3 σ of dt moves the moving scans'
  // residuals past the robust loss's corner; the second step, with the weights redone, 0.04 σ.
  EXPECT_LT((Error(step, full.mount).cwiseQuotient(sigma)).cwiseAbs().maxCoeff(), 0.1)
      << (Error(step, full.mount).cwiseQuotient(sigma)).transpose();
  EXPECT_EQ(step.time_offset_sigma_s, solved.time_offset_sigma_s);
  EXPECT_TRUE(step.covariance.isApprox(solved.covariance));
  EXPECT_NEAR(full.time_offset_sigma_s, step.time_offset_sigma_s, 0.05 * dt_sigma_s);
}

TEST(RefitMountTest, WeightsSelectStationsAndZeroWeightsDropThem) {
  SimSettings settings;
  std::mt19937 rng(4);
  const SimData data = Simulate(settings, rng);
  const solvers::SolverOptions options = OptionsFor(settings);
  const MountEstimate full = SolveMountCeres(data.observations, data.walls, options, settings.truth);
  ASSERT_TRUE(full.usable) << full.message;
  // All weights 1: the full solution again.
  const Refit same = RefitMount(data.observations, data.walls, options, full.mount,
                                std::vector<double>(data.observations.size(), 1.0), 20);
  ASSERT_TRUE(same.converged);
  EXPECT_TRUE(same.determined);
  EXPECT_NEAR(same.mount.x_m, full.mount.x_m, 1e-6);
  EXPECT_NEAR(same.mount.yaw_rad, full.mount.yaw_rad, 1e-7);
  // Keeping only the observations of one station: that station's data alone cannot tell y.
  std::vector<double> one(data.observations.size(), 0.0);
  for (size_t i = 0; i < one.size(); ++i) one[i] = data.observations[i].pose.segment == 3 ? 1.0 : 0.0;
  const Refit single = RefitMount(data.observations, data.walls, options, full.mount, one, 20);
  EXPECT_FALSE(single.determined);
}

}  // namespace
}  // namespace wallcal::solvers
