// SPDX-License-Identifier: Apache-2.0
#include "calib/survey_tie.h"
#include "solvers/solver_options.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "calib/geodesy.h"
#include "calib/rover_survey.h"
#include "test/support/expect_text.h"

namespace wallcal::calib {
namespace {

// The true tie used throughout: the survey's x axis 0.4 rad ccw from grid east, its origin at
// local (-3, 20).
constexpr double kTrueRotationRad = 0.4;
const Eigen::Vector2d kTrueTranslation(-3.0, 20.0);

Eigen::Matrix2d Rot(double angle_rad) {
  Eigen::Matrix2d r;
  r << std::cos(angle_rad), -std::sin(angle_rad), std::sin(angle_rad), std::cos(angle_rad);
  return r;
}

double AngleOf(const Eigen::Matrix2d& r) { return std::atan2(r(1, 0), r(0, 0)); }

// A site near Sapporo, and the inverse of ToLocal to make RTK positions for local points.
struct Site {
  LocalFrame frame = MakeLocalFrame(43.0712345, 141.3398765, std::nullopt);
  void LatLon(const Eigen::Vector2d& p_local, double* lat_deg, double* lon_deg) const {
    FromUtm(io::UtmZone{frame.zone, frame.north}, frame.origin_e_m + frame.scale_k0 * p_local.x(),
            frame.origin_n_m + frame.scale_k0 * p_local.y(), lat_deg, lon_deg);
  }
};

Eigen::Vector2d SurveyOf(const Eigen::Vector2d& p_local) {
  return Rot(kTrueRotationRad).transpose() * (p_local - kTrueTranslation);
}

struct Scenario {
  std::vector<io::SurveyPoint> survey;
  io::SessionSpec spec;
};

// Control points at the given local positions (ids C1, C2, ...), a wall from wall_a to wall_b
// surveyed every metre (code WALL1), σ noise on the survey (total station) and on the RTK.
Scenario MakeScenario(const Site& site, const std::vector<Eigen::Vector2d>& control_local,
                      const Eigen::Vector2d& wall_a, const Eigen::Vector2d& wall_b,
                      double sigma_ts_m, double sigma_rtk_m, std::mt19937* rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Scenario s;
  s.spec.file = "session.yaml";
  int line = 1;
  const auto add_point = [&](const std::string& id, const std::string& code,
                             const Eigen::Vector2d& p_local) {
    const Eigen::Vector2d p = SurveyOf(p_local);
    io::SurveyPoint point;
    point.id = id;
    point.code = code;
    point.x_m = p.x() + sigma_ts_m * normal(*rng);
    point.y_m = p.y() + sigma_ts_m * normal(*rng);
    point.z_m = 0.5;
    point.line = ++line;
    s.survey.push_back(point);
  };
  for (size_t i = 0; i < control_local.size(); ++i) {
    const std::string id = "C" + std::to_string(i + 1);
    add_point(id, "CTRL", control_local[i]);
    io::ControlPoint c;
    c.id = id;
    const Eigen::Vector2d noisy =
        control_local[i] + sigma_rtk_m * Eigen::Vector2d(normal(*rng), normal(*rng));
    site.LatLon(noisy, &c.lat_deg, &c.lon_deg);
    c.line = 10 + static_cast<int>(i);
    s.spec.control.push_back(c);
  }
  const double length_m = (wall_b - wall_a).norm();
  const int count = static_cast<int>(std::floor(length_m)) + 1;
  for (int i = 0; i < count; ++i) {
    const double f = static_cast<double>(i) / (count - 1);
    add_point("W" + std::to_string(i), "WALL1", wall_a + f * (wall_b - wall_a));
  }
  s.spec.walls.push_back(io::WallSpec{"north_wall", "WALL1"});
  return s;
}

const std::vector<Eigen::Vector2d> kThreeControls = {
    Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(15.0, 5.0), Eigen::Vector2d(4.0, 18.0)};
const std::vector<Eigen::Vector2d> kTwoControls = {Eigen::Vector2d(0.0, 0.0),
                                                   Eigen::Vector2d(15.0, 5.0)};
const Eigen::Vector2d kWallA(5.0, 12.0), kWallB(25.0, 14.0);

TEST(SurveyTieTest, RecoversExactTransformWithoutNoise) {
  const Site site;
  std::mt19937 rng(1);
  const Scenario s = MakeScenario(site, kThreeControls, kWallA, kWallB, 0.0, 0.0, &rng);
  const SurveyTie tie = TieSurvey(s.survey, "survey.csv", s.spec, site.frame, solvers::SolverOptions{}.survey());
  EXPECT_NEAR(AngleOf(tie.local_R_survey), kTrueRotationRad, 1e-9);
  EXPECT_NEAR((tie.local_t_survey - kTrueTranslation).norm(), 0.0, 1e-6);
  EXPECT_LT(tie.control_rms_m, 1e-6);
  EXPECT_EQ(tie.num_control, 3);
  EXPECT_NEAR((tie.control_centroid_local - Eigen::Vector2d(19.0 / 3, 23.0 / 3)).norm(), 0.0, 1e-6);
}

TEST(SurveyTieTest, ThreeNoisyControlPointsRecoverTheTie) {
  const Site site;
  std::mt19937 rng(7);
  const solvers::SolverOptions options;
  const Scenario s = MakeScenario(site, kThreeControls, kWallA, kWallB,
                                  options.total_station_sigma_m, options.control_sigma_m, &rng);
  const SurveyTie tie = TieSurvey(s.survey, "survey.csv", s.spec, site.frame, options.survey());
  ASSERT_EQ(tie.control_residuals.size(), 3u);
  // σ from the geometry: spread² = Σ|r_i − r̄|².
  double spread2 = 0.0;
  const Eigen::Vector2d mean = (kThreeControls[0] + kThreeControls[1] + kThreeControls[2]) / 3;
  for (const auto& c : kThreeControls) spread2 += (c - mean).squaredNorm();
  const double sigma = std::hypot(options.control_sigma_m, options.total_station_sigma_m);
  // (The fit uses the noisy survey coordinates: equal to a few 1e-4 relative.)
  EXPECT_NEAR(tie.sigma_rotation_rad, sigma / std::sqrt(spread2), 1e-3 * tie.sigma_rotation_rad);
  EXPECT_NEAR(tie.sigma_translation_m, sigma / std::sqrt(3.0), 1e-9);
  EXPECT_NEAR(AngleOf(tie.local_R_survey), kTrueRotationRad, 4 * tie.sigma_rotation_rad);
  // The translation is tested where it is defined: at the control centroid.
  const Eigen::Vector2d centroid_survey = SurveyOf(mean);
  const Eigen::Vector2d mapped = tie.local_R_survey * centroid_survey + tie.local_t_survey;
  EXPECT_NEAR(mapped.x(), mean.x(), 4 * tie.sigma_translation_m);
  EXPECT_NEAR(mapped.y(), mean.y(), 4 * tie.sigma_translation_m);
  // Residuals: fitted minus RTK; they sum to zero in a least-squares rigid fit, are of the noise
  // size, and their RMS is reported.
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double sum_sq = 0.0;
  for (const ControlResidual& r : tie.control_residuals) {
    sum += r.residual_m;
    sum_sq += r.residual_m.squaredNorm();
    EXPECT_LT(r.residual_m.norm(), 5 * sigma);
  }
  EXPECT_EQ(tie.control_residuals[1].id, "C2");
  EXPECT_NEAR(sum.norm(), 0.0, 1e-9);
  EXPECT_NEAR(tie.control_rms_m, std::sqrt(sum_sq / 3), 1e-12);
  EXPECT_GT(tie.control_rms_m, 1e-4);
}

TEST(SurveyTieTest, TwoNoisyControlPointsRecoverTheTie) {
  const Site site;
  const solvers::SolverOptions options;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE(seed);
    std::mt19937 rng(seed);
    const Scenario s = MakeScenario(site, kTwoControls, kWallA, kWallB,
                                    options.total_station_sigma_m, options.control_sigma_m, &rng);
    const SurveyTie tie = TieSurvey(s.survey, "survey.csv", s.spec, site.frame, options.survey());
    EXPECT_EQ(tie.num_control, 2);
    EXPECT_NEAR(AngleOf(tie.local_R_survey), kTrueRotationRad, 4 * tie.sigma_rotation_rad);
    const Eigen::Vector2d mean = 0.5 * (kTwoControls[0] + kTwoControls[1]);
    const Eigen::Vector2d mapped = tie.local_R_survey * SurveyOf(mean) + tie.local_t_survey;
    EXPECT_NEAR((mapped - mean).norm(), 0.0, 4 * tie.sigma_translation_m);
    ASSERT_EQ(tie.control_residuals.size(), 2u);
    // With two points only the distance mismatch is left, split equally and opposite.
    EXPECT_NEAR((tie.control_residuals[0].residual_m + tie.control_residuals[1].residual_m).norm(),
                0.0, 1e-9);
  }
}

TEST(SurveyTieTest, OneControlPointUsesGivenRotation) {
  const Site site;
  std::mt19937 rng(3);
  solvers::SolverOptions options;
  options.rotation_sigma_rad = 0.002;
  Scenario s = MakeScenario(site, {Eigen::Vector2d(2.0, 3.0)}, kWallA, kWallB, 0.0, 0.0, &rng);
  s.spec.survey_rotation_rad = kTrueRotationRad;
  const SurveyTie tie = TieSurvey(s.survey, "survey.csv", s.spec, site.frame, options.survey());
  EXPECT_NEAR(AngleOf(tie.local_R_survey), kTrueRotationRad, 1e-12);
  EXPECT_NEAR((tie.local_t_survey - kTrueTranslation).norm(), 0.0, 1e-6);
  EXPECT_DOUBLE_EQ(tie.sigma_rotation_rad, 0.002);
  EXPECT_NEAR(tie.sigma_translation_m,
              std::hypot(options.control_sigma_m, options.total_station_sigma_m), 1e-12);
  EXPECT_EQ(tie.control_rms_m, 0.0);
  EXPECT_NEAR((tie.control_centroid_local - Eigen::Vector2d(2.0, 3.0)).norm(), 0.0, 1e-6);
  // Barawid 2007 Eq. 5 by hand: a wall point p_s maps to R(ρ)(p_s − p_s,C) + p_local,C.
  const Eigen::Vector2d p_s(s.survey.back().x_m, s.survey.back().y_m);
  const Eigen::Vector2d p_c(s.survey.front().x_m, s.survey.front().y_m);
  const Eigen::Vector2d expected = Rot(kTrueRotationRad) * (p_s - p_c) + Eigen::Vector2d(2.0, 3.0);
  EXPECT_NEAR((tie.local_R_survey * p_s + tie.local_t_survey - expected).norm(), 0.0, 1e-6);
  EXPECT_NEAR((expected - kWallB).norm(), 0.0, 1e-6);

  s.spec.survey_rotation_rad.reset();
  EXPECT_THROW(TieSurvey(s.survey, "survey.csv", s.spec, site.frame, options.survey()), io::InputError);
}

std::string ErrorOf(const Scenario& s, const Site& site) {
  try {
    TieSurvey(s.survey, "survey.csv", s.spec, site.frame, solvers::SolverOptions{}.survey());
  } catch (const io::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SurveyTieTest, MissingControlIdNamesIt) {
  const Site site;
  std::mt19937 rng(3);
  Scenario s = MakeScenario(site, kThreeControls, kWallA, kWallB, 0.0, 0.0, &rng);
  s.spec.control[2].id = "C3x";
  const std::string message = ErrorOf(s, site);
  testing_support::ExpectContains(message, {
      "session.yaml:12",
      "control point C3x is not in survey.csv"
  });
}

TEST(SurveyTieTest, RejectsCoincidentAndDisagreeingControl) {
  const Site site;
  std::mt19937 rng(3);
  Scenario coincident = MakeScenario(site, {Eigen::Vector2d(0, 0), Eigen::Vector2d(0.001, 0)},
                                     kWallA, kWallB, 0.0, 0.0, &rng);
  EXPECT_NE(ErrorOf(coincident, site).find("coincide"), std::string::npos);

  // C2's RTK position 3 m off: a wrong point was measured.
  Scenario wrong = MakeScenario(site, kThreeControls, kWallA, kWallB, 0.0, 0.0, &rng);
  site.LatLon(kThreeControls[1] + Eigen::Vector2d(3.0, 0.0), &wrong.spec.control[1].lat_deg,
              &wrong.spec.control[1].lon_deg);
  const std::string message = ErrorOf(wrong, site);
  testing_support::ExpectContains(message, {"disagree", "session.yaml:"});

  Scenario none = MakeScenario(site, {}, kWallA, kWallB, 0.0, 0.0, &rng);
  EXPECT_FALSE(ErrorOf(none, site).empty());
}

// A control point typed 10 km off: with three, the one whose removal leaves the others
// agreeing is named; with two, either may be wrong and both are named.
TEST(SurveyTieTest, AControlPointFarOffIsNamedWhenItCanBe) {
  const Site site;
  std::mt19937 rng(3);
  Scenario three = MakeScenario(site, kThreeControls, kWallA, kWallB, 0.0, 0.0, &rng);
  site.LatLon(kThreeControls[1] + Eigen::Vector2d(0.0, 10000.0), &three.spec.control[1].lat_deg,
              &three.spec.control[1].lon_deg);
  const std::string named = ErrorOf(three, site);
  testing_support::ExpectContains(named, {
      "control point C2 disagrees",
      "C1, C3 agree",
      "session.yaml:11"
  });

  Scenario two = MakeScenario(site, {kThreeControls[0], kThreeControls[1]}, kWallA, kWallB, 0.0,
                              0.0, &rng);
  site.LatLon(kThreeControls[0] + Eigen::Vector2d(0.0, 10000.0), &two.spec.control[0].lat_deg,
              &two.spec.control[0].lon_deg);
  const std::string both = ErrorOf(two, site);
  testing_support::ExpectContains(both, {"control points C1 and C2", "cannot be told"});
}

TEST(SurveyTieTest, WallCodesMatchWithoutCase) {
  EXPECT_TRUE(SameSurveyCode("wall1", "WALL1"));
  EXPECT_TRUE(SameSurveyCode("Wall1", "wALL1"));
  EXPECT_FALSE(SameSurveyCode("WALL1", "WALL12"));
  EXPECT_FALSE(SameSurveyCode("WALL1", "WALL2"));
}

TEST(SurveyTieTest, FitWallsRecoversLineAndOrientation) {
  const Site site;
  std::mt19937 rng(11);
  const solvers::SolverOptions options;
  const Scenario s =
      MakeScenario(site, kThreeControls, kWallA, kWallB, options.total_station_sigma_m, 0.0, &rng);
  const SurveyTie tie = TieSurvey(s.survey, "survey.csv", s.spec, site.frame, options.survey());
  const std::vector<WallGeometry> walls = FitWalls(s.survey, "survey.csv", s.spec, tie, options.survey());
  ASSERT_EQ(walls.size(), 1u);
  const WallGeometry& wall = walls[0];
  EXPECT_EQ(wall.id, "north_wall");
  EXPECT_EQ(wall.num_points, 21);
  // Direction from the first surveyed point to the last; normal = direction rotated +90°.
  const Eigen::Vector2d direction = (kWallB - kWallA).normalized();
  const Eigen::Vector2d normal(-direction.y(), direction.x());
  EXPECT_NEAR(wall.normal_local.norm(), 1.0, 1e-12);
  EXPECT_NEAR(std::asin(normal.x() * wall.normal_local.y() - normal.y() * wall.normal_local.x()),
              0.0, 0.003);
  EXPECT_GT(wall.normal_local.dot(normal), 0.99);
  EXPECT_NEAR(wall.offset_m, normal.dot(kWallA), 0.01);
  EXPECT_NEAR((wall.end_a_local - kWallA).norm(), 0.0, 0.05);
  EXPECT_NEAR((wall.end_b_local - kWallB).norm(), 0.0, 0.05);
  EXPECT_NEAR(wall.normal_local.dot(wall.end_a_local), wall.offset_m, 1e-9);
  EXPECT_NEAR(wall.rms_m, options.total_station_sigma_m, 0.0015);
  EXPECT_GT(wall.sigma_offset_m, 0.0);
  EXPECT_GT(wall.sigma_angle_rad, 0.0);
}

// A wall surveyed at two heights whose top leans 1° towards +normal: the lean comes out within
// its σ, far beyond 4 σ from upright, and is used; an upright wall's stays 0.
TEST(SurveyTieTest, FitWallsFindsTheLeanFromTheHeights) {
  const Site site;
  std::mt19937 rng(5);
  const solvers::SolverOptions options;
  for (const double lean_deg : {1.0, 0.0}) {
    Scenario s = MakeScenario(site, kThreeControls, kWallA, kWallB, options.total_station_sigma_m,
                              0.0, &rng);
    const Eigen::Vector2d direction = (kWallB - kWallA).normalized();
    const Eigen::Vector2d normal_survey =
        Rot(kTrueRotationRad).transpose() * Eigen::Vector2d(-direction.y(), direction.x());
    std::vector<io::SurveyPoint> upper;
    for (io::SurveyPoint p : s.survey) {
      if (p.code != "WALL1") continue;
      p.id += "u";
      p.z_m = 2.7;
      const Eigen::Vector2d moved = 2.2 * std::tan(lean_deg * M_PI / 180.0) * normal_survey;
      p.x_m += moved.x();
      p.y_m += moved.y();
      upper.push_back(p);
    }
    s.survey.insert(s.survey.end(), upper.begin(), upper.end());
    const SurveyTie tie = TieSurvey(s.survey, "survey.csv", s.spec, site.frame, options.survey());
    const WallGeometry wall = FitWalls(s.survey, "survey.csv", s.spec, tie, options.survey()).at(0);
    ASSERT_TRUE(wall.lean_fitted) << lean_deg;
    EXPECT_GT(wall.sigma_lean_rad, 0.0);
    EXPECT_NEAR(wall.fitted_lean_rad * 180.0 / M_PI, lean_deg, 4.0 * wall.sigma_lean_rad * 180.0 / M_PI);
    if (lean_deg != 0.0) {
      EXPECT_EQ(wall.lean_rad, wall.fitted_lean_rad);
    } else if (std::abs(wall.fitted_lean_rad) <= 4.0 * wall.sigma_lean_rad) {
      EXPECT_EQ(wall.lean_rad, 0.0);
    }
  }
}

TEST(SurveyTieTest, FitWallsSigmasMatchMonteCarlo) {
  // The whole chain with noise on the wall points, the control points' survey coordinates and
  // their RTK positions; the reported σ must be within a factor 1.5 of the scatter.
  const Site site;
  const solvers::SolverOptions options;
  const Eigen::Vector2d direction = (kWallB - kWallA).normalized();
  const Eigen::Vector2d true_normal(-direction.y(), direction.x());
  const Eigen::Vector2d true_centre = 0.5 * (kWallA + kWallB);
  std::mt19937 rng(2024);
  const int draws = 400;
  double sum_sq_offset = 0.0, sum_sq_angle = 0.0, sum_sigma_offset = 0.0, sum_sigma_angle = 0.0;
  for (int i = 0; i < draws; ++i) {
    const Scenario s = MakeScenario(site, kTwoControls, kWallA, kWallB,
                                    options.total_station_sigma_m, options.control_sigma_m, &rng);
    const SurveyTie tie = TieSurvey(s.survey, "survey.csv", s.spec, site.frame, options.survey());
    const WallGeometry wall = FitWalls(s.survey, "survey.csv", s.spec, tie, options.survey()).at(0);
    const double offset_error = wall.normal_local.dot(true_centre) - wall.offset_m;
    const double angle_error = std::asin(true_normal.x() * wall.normal_local.y() -
                                         true_normal.y() * wall.normal_local.x());
    sum_sq_offset += offset_error * offset_error;
    sum_sq_angle += angle_error * angle_error;
    sum_sigma_offset += wall.sigma_offset_m;
    sum_sigma_angle += wall.sigma_angle_rad;
  }
  const double empirical_offset = std::sqrt(sum_sq_offset / draws);
  const double empirical_angle = std::sqrt(sum_sq_angle / draws);
  const double reported_offset = sum_sigma_offset / draws;
  const double reported_angle = sum_sigma_angle / draws;
  EXPECT_GT(reported_offset, empirical_offset / 1.5);
  EXPECT_LT(reported_offset, empirical_offset * 1.5);
  EXPECT_GT(reported_angle, empirical_angle / 1.5);
  EXPECT_LT(reported_angle, empirical_angle * 1.5);
}

TEST(SurveyTieTest, RoverWallSigmasMatchMonteCarlo) {
  // Rover points straight in latitude and longitude, no tie; the first half of the wall
  // measured with 5 mm, the second with 20 mm (the file's σ per point), so that the fit's
  // offset and direction are correlated. The reported σ and the offset-direction covariance
  // must match the scatter of many draws: with N draws an RMS is off by about 1/√(2N)
  // (1.6 % at N = 2000), a correlation by about 1/√N (2.2 %); the bounds are 5 times those.
  const Site site;
  io::SessionSpec spec;
  spec.walls.push_back(io::WallSpec{"north_wall", "WALL1"});
  const Eigen::Vector2d direction = (kWallB - kWallA).normalized();
  const Eigen::Vector2d true_normal(-direction.y(), direction.x());
  const Eigen::Vector2d true_centre = 0.5 * (kWallA + kWallB);
  const int num_points = 16;
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int draws = 2000;
  double sum_sq_offset = 0.0, sum_sq_angle = 0.0, sum_cross = 0.0;
  WallGeometry wall;
  for (int i = 0; i < draws; ++i) {
    std::vector<io::SurveyPoint> survey;
    for (int k = 0; k < num_points; ++k) {
      const double sigma_m = k < num_points / 2 ? 0.005 : 0.020;
      const Eigen::Vector2d p = kWallA + (kWallB - kWallA) * k / (num_points - 1.0) +
                                sigma_m * Eigen::Vector2d(normal(rng), normal(rng));
      io::SurveyPoint point;
      point.id = "R" + std::to_string(k);
      point.code = "WALL1";
      point.frame = io::SurveyFrame::kGeodetic;
      point.sigma_m = sigma_m;
      site.LatLon(p, &point.lat_deg, &point.lon_deg);
      survey.push_back(point);
    }
    survey = PlaceRoverPoints(survey, "rover.csv", site.frame, 0.010);
    wall = FitWalls(survey, "rover.csv", spec, RoverTie(), solvers::SolverOptions{}.survey()).at(0);
    const double offset_error = wall.normal_local.dot(true_centre) - wall.offset_m;
    const double angle_error = std::asin(true_normal.x() * wall.normal_local.y() -
                                         true_normal.y() * wall.normal_local.x());
    sum_sq_offset += offset_error * offset_error;
    sum_sq_angle += angle_error * angle_error;
    sum_cross += offset_error * angle_error;
  }
  EXPECT_TRUE(wall.from_rover);
  EXPECT_EQ(wall.tie_sigma_translation_m, 0.0);
  const double empirical_offset = std::sqrt(sum_sq_offset / draws);
  const double empirical_angle = std::sqrt(sum_sq_angle / draws);
  EXPECT_NEAR(wall.sigma_offset_m / empirical_offset, 1.0, 0.08);
  EXPECT_NEAR(wall.sigma_angle_rad / empirical_angle, 1.0, 0.08);
  // offset_m grows where the true wall is (n·c − d > 0) when the line turns towards +angle:
  // compare the correlation's size and sign through the errors' own convention.
  const double empirical_correlation = sum_cross / draws / (empirical_offset * empirical_angle);
  const double reported_correlation =
      -wall.cov_offset_angle / (wall.sigma_offset_m * wall.sigma_angle_rad);
  EXPECT_GT(std::abs(reported_correlation), 0.2);  // unequal σ: not independent
  EXPECT_NEAR(reported_correlation, empirical_correlation, 0.11);
}

TEST(SurveyTieTest, WallWithoutPointsNamesWallAndCode) {
  const Site site;
  std::mt19937 rng(5);
  Scenario s = MakeScenario(site, kThreeControls, kWallA, kWallB, 0.0, 0.0, &rng);
  s.spec.walls.push_back(io::WallSpec{"east_wall", "WALL2"});
  const SurveyTie tie = TieSurvey(s.survey, "survey.csv", s.spec, site.frame, solvers::SolverOptions{}.survey());
  try {
    FitWalls(s.survey, "survey.csv", s.spec, tie, solvers::SolverOptions{}.survey());
    FAIL() << "expected InputError";
  } catch (const io::InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("wall east_wall: no survey points with code WALL2"), std::string::npos)
        << message;
    EXPECT_NE(message.find("the survey's codes are CTRL (3), WALL1 ("), std::string::npos)
        << message;
    EXPECT_NE(message.find("survey.csv"), std::string::npos) << message;
  }
  // Points spanning less than half a metre.
  Scenario short_wall =
      MakeScenario(site, kThreeControls, kWallA, kWallA + Eigen::Vector2d(0.3, 0), 0.0, 0.0, &rng);
  EXPECT_THROW(FitWalls(short_wall.survey, "survey.csv", short_wall.spec, tie, solvers::SolverOptions{}.survey()),
               io::InputError);
}

}  // namespace
}  // namespace wallcal::calib
