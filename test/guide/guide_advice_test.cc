// SPDX-License-Identifier: Apache-2.0
// The guide's advice against what the advised stops give when driven: a session of three stops
// (simulator, explicit stops), the stops the guide advises on it appended, and calibrate's σ on
// the longer session against the σ the guide predicted for it. And the small parts: the spread
// of vehicle-to-wall angles as calibrate's check takes it, the beam model of a stop's line fit.
//
// Tolerance 0.8–1.25, the band the guide's σ is held to: the advised stops' observations are a
// model (the scanner abreast of the wall's centre, the preset's beams on the surveyed extent,
// the wait spent standing at the previous stop after a 5 s drive), the driven ones the
// simulator's (its own places along the wall, drive times from the distance and turn).

#include <cmath>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/angles.h"
#include "guide/guide.h"
#include "guide/guide_text.h"
#include "guide/prediction.h"
#include "guide/stop_model.h"
#include "pipeline/calibration.h"
#include "sim/simulated_session.h"
#include "sim/simulation_config.h"
#include "test/support/json_value.h"
#include "test/support/program_runner.h"
#include "test/support/scratch_dir.h"
#include "test/support/shipped_presets.h"

namespace wallcal {
namespace {

sim::SimStop Stop(double deg, double dwell_s, double wait_s, double distance_m = 8.0) {
  sim::SimStop s;
  s.vehicle_to_wall_rad = deg * kDegToRad;
  s.dwell_s = dwell_s;
  s.wait_s = wait_s;
  s.distance_m = distance_m;
  return s;
}

TEST(GuideAdviceTest, AdvisedStopsGiveTheSigmaTheGuidePredicts) {
  sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/bench_lms291_guide_crew.yaml");
  config.stops = {Stop(-30, 4, 0), Stop(30, 4, 10), Stop(0, 4, 10)};
  const testing_support::ScratchDir scratch("wallcal_guide_advice_");
  const std::string first = (scratch.path() / "first").string();
  sim::WriteSimulatedSession(config, 31, first);
  guide::GuideOptions request;
  request.session_path = first;
  const guide::GuideReport report = guide::AssessSession(request);
  ASSERT_TRUE(report.predicted.known);
  ASSERT_EQ(report.stations.size(), 3u);
  ASSERT_FALSE(report.next.empty());
  ASSERT_FALSE(report.enough);

  for (const guide::Advice& a : report.next) {
    config.stops.push_back(Stop(a.stop.vehicle_to_wall_rad * kRadToDeg, a.stop.dwell_s,
                                a.stop.wait_s, a.stop.distance_m));
  }
  const std::string longer = (scratch.path() / "longer").string();
  sim::WriteSimulatedSession(config, 31, longer);
  pipeline::CalibrateRequest calibrate;
  calibrate.session_path = longer;
  const pipeline::CalibrationResult result = pipeline::RunCalibration(calibrate);
  ASSERT_TRUE(result.solve.estimate.usable) << result.solve.estimate.message;
  const guide::Prediction& predicted = report.next.back().after;
  ASSERT_TRUE(predicted.known);
  const double reported[3] = {std::sqrt(result.solve.estimate.covariance(0, 0)),
                              std::sqrt(result.solve.estimate.covariance(1, 1)),
                              std::sqrt(result.solve.estimate.covariance(2, 2))};
  const double guided[3] = {predicted.sigma_x_m(), predicted.sigma_y_m(),
                            predicted.sigma_yaw_rad()};
  for (int axis = 0; axis < 3; ++axis) {
    RecordProperty("ratio_axis_" + std::to_string(axis), std::to_string(guided[axis] / reported[axis]));
    EXPECT_GE(guided[axis] / reported[axis], 0.8) << "axis " << axis;
    EXPECT_LE(guided[axis] / reported[axis], 1.25) << "axis " << axis;
  }
  // And the advice helped: the largest σ over its tolerance went down.
  EXPECT_LT(guide::WorstSigmaRatio(predicted, report.acceptance),
            guide::WorstSigmaRatio(report.predicted, report.acceptance));
}

TEST(GuideAdviceTest, AngleSpreadIsTakenModuloHalfATurn) {
  EXPECT_NEAR(guide::AngleSpread({-0.3, 0.3}), 0.6, 1e-12);
  EXPECT_NEAR(guide::AngleSpread({0.1}), 0.0, 1e-12);
  // A wall at a right angle: 80° and −80° are 20° apart modulo 180°.
  EXPECT_NEAR(guide::AngleSpread({80 * kDegToRad, -80 * kDegToRad}), 20 * kDegToRad, 1e-12);
  EXPECT_EQ(guide::AngleSpread({}), 0.0);
}

TEST(GuideAdviceTest, LineFitModelSeesTheWallSquareOnAndNotFromBehind) {
  guide::StopModel model;
  model.preset = testing_support::ShippedPreset("sick_lms291");
  calib::WallGeometry wall;
  wall.normal_local = Eigen::Vector2d(0, 1);
  wall.offset_m = 10.0;
  wall.end_a_local = Eigen::Vector2d(-15, 10);
  wall.end_b_local = Eigen::Vector2d(15, 10);
  guide::LineFitModel fit;
  ASSERT_TRUE(guide::ModelLineFit(model, wall, Eigen::Vector2d(0, 2), kPi / 2, &fit));
  // 30 m of wall 8 m away: the beams over ±62° hit it, one every degree.
  EXPECT_GT(fit.beams, 100);
  EXPECT_LT(fit.sigma_rho_m, model.preset.range_sigma_m);
  EXPECT_NEAR(fit.range_min_m, 8.0, 0.01);
  // Facing away: no beam reaches it.
  EXPECT_FALSE(guide::ModelLineFit(model, wall, Eigen::Vector2d(0, 2), -kPi / 2, &fit));
}

TEST(GuideAdviceTest, JsonIsOneObjectWithTheDocumentedKeys) {
  const std::string sample = std::string(WALLCAL_SOURCE_DIR) + "/samples/lms291-sapporo";
  // The keys up to "next" as they always were (a display reads them), in that order and form.
  const std::string number = R"((-?[0-9.]+|null))";
  const std::regex start(R"(\{"stations": [0-9]+, "predicted_sigma": \{"x_m": )" + number +
                         R"(, "y_m": )" + number + R"(, "yaw_deg": )" + number +
                         R"(\}, "forced": (true|false), "enough": (true|false), "next": \[)");
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{sample, "--json"},
        std::vector<std::string>{sample, "--plan", "5", "--json"}}) {
    std::vector<std::string> command = {"guide"};
    command.insert(command.end(), args.begin(), args.end());
    const testing_support::ProgramRun run = testing_support::RunWallcal(command);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const size_t next = run.out.find("\"next\": [");
    ASSERT_NE(next, std::string::npos) << run.out;
    EXPECT_TRUE(std::regex_match(run.out.substr(0, next + 9), start)) << run.out;
    EXPECT_EQ(run.out.find('\n'), run.out.size() - 1) << "one object on one line";
    testing_support::Json j;
    ASSERT_TRUE(testing_support::JsonParser(run.out).Parse(&j)) << run.out;
    for (const char* key : {"session", "scanner", "tolerance", "worst_axis", "worst_ratio",
                            "reason", "message", "logged_s", "sigma_ellipse", "walls",
                            "station_poses", "stops_without_wall", "vehicle", "mount",
                            "scanner_pose", "warnings", "plan"}) {
      EXPECT_EQ(j.members.count(key), 1u) << key;
    }
    for (const testing_support::Json& stop : j["next"].items) {
      for (const char* key : {"vehicle_to_wall_deg", "distance_m", "dwell_s", "wait_s", "wall",
                              "target", "move", "instruction"}) {
        EXPECT_EQ(stop.members.count(key), 1u) << key;
      }
    }
    EXPECT_EQ(j["walls"].items.size(), 1u);
  }
}

TEST(GuideAdviceTest, OneStationIsForcedInTextAndJson) {
  // One 4 s stop: the σ exists only forced past calibrate's station count.
  sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/bench_lms291_guide_crew.yaml");
  config.stops = {Stop(-30, 4, 0)};
  const testing_support::ScratchDir scratch("wallcal_guide_forced_");
  const std::string one = (scratch.path() / "one").string();
  sim::WriteSimulatedSession(config, 31, one);
  guide::GuideOptions request;
  request.session_path = one;
  const guide::GuideReport report = guide::AssessSession(request);
  ASSERT_TRUE(report.predicted.known);
  EXPECT_TRUE(report.forced);
  EXPECT_FALSE(report.enough);
  EXPECT_NE(guide::GuideText(report).find("note       FORCED"), std::string::npos);
  EXPECT_NE(guide::GuideJson(report).find("\"forced\": true"), std::string::npos);
}

TEST(GuideAdviceTest, PlanTooShortSaysWhy) {
  guide::GuideOptions options;
  options.session_path = std::string(WALLCAL_SOURCE_DIR) + "/samples/lms291-sapporo";
  const guide::GuideReport too_short = guide::PlanSession(options, 60.0);
  ASSERT_TRUE(too_short.plan.has_value());
  EXPECT_TRUE(too_short.plan->stops.empty());
  EXPECT_EQ(too_short.not_yet, guide::NotYet::kBudgetTooShort);
  EXPECT_FALSE(too_short.enough);
  // The shortest plan: three stops of 10 s, 15 s apart (75 s).
  const guide::GuideReport shortest = guide::PlanSession(options, 75.0);
  EXPECT_EQ(static_cast<int>(shortest.plan->stops.size()), guide::kMinPlanStops);
  EXPECT_EQ(shortest.not_yet, guide::NotYet::kNone);
}

TEST(GuideAdviceTest, UsageErrorsExitTwo) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{}, std::vector<std::string>{"a", "b"},
        std::vector<std::string>{"a", "--plan", "0"}, std::vector<std::string>{"a", "--next", "4"},
        std::vector<std::string>{"a", "--bogus"},
        std::vector<std::string>{"/nonexistent/session.yaml"}}) {
    std::vector<std::string> command = {"guide"};
    command.insert(command.end(), args.begin(), args.end());
    const testing_support::ProgramRun run = testing_support::RunWallcal(command);
    EXPECT_EQ(run.exit_code, 2) << (args.empty() ? "" : args[0]);
    EXPECT_FALSE(run.err.empty());
  }
}

}  // namespace
}  // namespace wallcal
