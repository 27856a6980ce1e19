// SPDX-License-Identifier: Apache-2.0
// The residual analysis after the mount solve (apps/residual_analysis.cc, Hartzell, Glennie et al.): trends
// are flagged when a systematic error is there, and not on clean data.

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "analysis/residual_analysis.h"
#include "calib/wall_geometry.h"
#include "solvers/mount_solver.h"
#include "common/angles.h"
#include "test/support/flow_names.h"

namespace wallcal {


namespace {
struct Session {
  std::vector<calib::WallGeometry> walls;
  std::vector<calib::WallObservation> observations;
};

// Stations facing a wall along y = 20 from 3 to 15 m away (ranges spanning 12 m), headings
// ±30° about north, 30 scans each, 10 min apart (independent GNSS errors). Measured ranges are
// multiplied by `range_scale`; station `jump_station` has its GNSS positions off by `jump_m`.
Session Make(double range_scale, int jump_station, double jump_m, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  Session s;
  calib::WallGeometry wall;
  wall.id = "north";
  wall.normal_local = Eigen::Vector2d(0.0, 1.0);
  wall.offset_m = 20.0;
  wall.end_a_local = Eigen::Vector2d(-20.0, 20.0);
  wall.end_b_local = Eigen::Vector2d(20.0, 20.0);
  wall.sigma_offset_m = 0.005;
  wall.sigma_angle_rad = 0.001;
  s.walls.push_back(wall);
  const solvers::Mount truth{2.0, 0.1, 0.03};
  const int stations = 12;
  for (int k = 0; k < stations; ++k) {
    const double heading = 0.5 * kPi + (k % 4 - 1.5) * 20.0 * kPi / 180.0;
    const double distance_m = 3.0 + 12.0 * k / (stations - 1);
    const Eigen::Vector2d antenna(-6.0 + (k * 5) % 12, 20.0 - distance_m - 2.0);
    const Eigen::Vector2d bias(0.01 * unit(rng), 0.01 * unit(rng));
    for (int j = 0; j < 30; ++j) {
      const Eigen::Vector2d measured = antenna + bias +
                                       Eigen::Vector2d(0.003 * unit(rng), 0.003 * unit(rng)) +
                                       (k == jump_station ? Eigen::Vector2d(0.0, jump_m)
                                                          : Eigen::Vector2d::Zero());
      const Eigen::Vector2d scanner =
          antenna + Eigen::Rotation2Dd(heading) * Eigen::Vector2d(truth.x_m, truth.y_m);
      calib::WallObservation o;
      o.scan_index = k * 30 + j;
      o.wall_index = 0;
      const double rho = wall.offset_m - scanner.y();
      o.rho_m = range_scale * rho + 0.003 * unit(rng);
      o.theta_rad = WrapAngle(0.5 * kPi - heading - truth.yaw_rad + 0.001 * unit(rng));
      o.sigma_rho_m = 0.003;
      o.sigma_theta_rad = 0.001;
      o.num_inliers = 100;
      o.range_min_m = o.rho_m;
      o.range_max_m = o.rho_m / std::cos(0.7);
      o.pose.stamp_s = 1000.0 + 600.0 * k + 0.1 * j;
      o.pose.antenna_local_m = measured;
      o.pose.yaw_rad = heading + 0.0005 * unit(rng);
      o.pose.stationary = true;
      o.pose.segment = k;
      s.observations.push_back(o);
    }
  }
  return s;
}

ResidualAnalysis Analyse(const Session& s) {
  solvers::SolverOptions options;
  options.use_gst_sigma = false;
  options.gnss_bias_sigma_m = 0.01;
  options.gnss_white_sigma_m = 0.003;
  options.heading_sigma_rad = 0.0005;
  const solvers::MountEstimate estimate =
      solvers::SolveMountCeres(s.observations, s.walls, options, solvers::Mount{2.0, 0.0, 0.0});
  EXPECT_TRUE(estimate.usable) << estimate.message;
  io::ScannerPreset preset;
  preset.range_scale_k = 1.0;
  return AnalyseResiduals(s.observations, s.walls, estimate, preset);
}

const ResidualTrend* Trend(const ResidualAnalysis& a, TrendAxis against) {
  for (const ResidualTrend& t : a.trends) {
    if (t.against == against) return &t;
  }
  return nullptr;
}

TEST(ResidualAnalysisTest, CleanSessionHasNoFlags) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const ResidualAnalysis a = Analyse(Make(1.0, -1, 0.0, seed));
    ASSERT_TRUE(a.done);
    EXPECT_TRUE(a.flags.empty()) << a.flags.front();
    EXPECT_NEAR(a.robust_sigma_m, 0.003, 0.0015);
    EXPECT_LT(a.outlier_share, 0.1);
    ASSERT_NE(Trend(a, TrendAxis::kRange), nullptr);
    EXPECT_FALSE(Trend(a, TrendAxis::kRange)->flagged);
    ASSERT_TRUE(a.range_model_estimated);
    EXPECT_NEAR(a.range_scale_k, 1.0, 4.0 * a.sigma_range_scale_k + 1e-4);
  }
}

TEST(ResidualAnalysisTest, RangeScaleErrorIsFlaggedAndKIsEstimated) {
  const ResidualAnalysis a = Analyse(Make(1.01, -1, 0.0, 5));  // ranges 1 % long
  ASSERT_TRUE(a.done);
  const ResidualTrend* range = Trend(a, TrendAxis::kRange);
  ASSERT_NE(range, nullptr);
  EXPECT_TRUE(range->flagged) << "significance " << range->significance;
  EXPECT_NE(range->message.find("range scale error"), std::string::npos);
  bool flagged = false;
  for (const std::string& f : a.flags) flagged = flagged || f.find("preset's k") != std::string::npos;
  EXPECT_TRUE(flagged);
  // Corrected k ≈ 1/1.01.
  ASSERT_TRUE(a.range_model_estimated);
  EXPECT_NEAR(a.range_scale_k, 1.0 / 1.01, 0.003);
}

TEST(ResidualAnalysisTest, GnssJumpAtOneStationIsFlagged) {
  const ResidualAnalysis a = Analyse(Make(1.0, 6, 0.12, 7));  // 12 cm jump at station 7
  ASSERT_TRUE(a.done);
  bool flagged = false;
  int jump_flags = 0;
  for (const std::string& f : a.flags) {
    if (f.find("GNSS jump") == std::string::npos) continue;
    flagged = true;
    ++jump_flags;
    // Stations are numbered from 1 in time order: index 6 is the seventh.
    EXPECT_NE(f.find("(station 7:"), std::string::npos) << f;
  }
  EXPECT_TRUE(flagged);
  EXPECT_EQ(jump_flags, 1);  // one flag per station, however many GNSS-error slices it has
  ASSERT_NE(Trend(a, TrendAxis::kStation), nullptr);
  EXPECT_TRUE(Trend(a, TrendAxis::kStation)->flagged);
}

}  // namespace
}  // namespace wallcal
