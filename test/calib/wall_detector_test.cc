// SPDX-License-Identifier: Apache-2.0
#include "calib/wall_detector.h"
#include "test/support/shipped_presets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "calib/range_model.h"
#include "calib/wall_detector_options.h"
#include "common/angles.h"

namespace wallcal::calib {
namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- A small 2-D ray caster: the scanner at the origin, walls as segments, trunks as circles.

struct Segment {
  Eigen::Vector2d a, b;
};
struct Circle {
  Eigen::Vector2d centre;
  double radius_m;
};
struct Scene {
  std::vector<Segment> walls;
  std::vector<Circle> trunks;
};

// The wall {p : cos θ px + sin θ py = ρ} between along-line positions s0 and s1 (s measured
// along (−sin θ, cos θ) from the foot of the perpendicular).
Segment WallOnLine(double theta_rad, double rho_m, double s0_m, double s1_m) {
  const Eigen::Vector2d n(std::cos(theta_rad), std::sin(theta_rad));
  const Eigen::Vector2d d(-std::sin(theta_rad), std::cos(theta_rad));
  return {rho_m * n + s0_m * d, rho_m * n + s1_m * d};
}

// A scene of the one wall WallOnLine(theta_rad, rho_m, s0_m, s1_m).
Scene OneWall(double theta_rad, double rho_m, double s0_m, double s1_m) {
  Scene scene;
  scene.walls.push_back(WallOnLine(theta_rad, rho_m, s0_m, s1_m));
  return scene;
}

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Distance along the unit ray u to the nearest surface, +inf when nothing is hit.
double Cast(const Scene& scene, const Eigen::Vector2d& u) {
  double best = kInf;
  for (const Segment& w : scene.walls) {
    const Eigen::Vector2d e = w.b - w.a;
    const double den = Cross(u, e);
    if (std::abs(den) < 1e-12) continue;
    const double t = Cross(w.a, e) / den;  // ray: t u; segment: a + s e
    const double s = Cross(w.a, u) / den;
    if (t > 0.0 && s >= 0.0 && s <= 1.0) best = std::min(best, t);
  }
  for (const Circle& c : scene.trunks) {
    const double b = u.dot(c.centre);
    const double disc = b * b - (c.centre.squaredNorm() - c.radius_m * c.radius_m);
    if (disc < 0.0) continue;
    const double t = b - std::sqrt(disc);
    if (t > 0.0) best = std::min(best, t);
  }
  return best;
}

// True ranges of every beam (+inf: nothing hit).
std::vector<double> TrueRanges(const Scene& scene, const io::ScannerPreset& preset) {
  std::vector<double> r(preset.num_beams);
  for (int i = 0; i < preset.num_beams; ++i) {
    const double bearing = preset.start_angle_rad + i * preset.angular_step_rad;
    r[i] = Cast(scene, {std::cos(bearing), std::sin(bearing)});
  }
  return r;
}

// Logs true ranges as the scanner would (Ye & Borenstein 2002; Okubo, Ye & Borenstein 2009: z = Int(n·y + c + ξ)); no-returns at
// the SICK maximum, out-of-range URG readings as error code 0.
io::ScanRecord Log(const std::vector<double>& true_r, const io::ScannerPreset& preset,
                   std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, preset.range_sigma_m);
  io::ScanRecord scan;
  scan.start_angle_rad = preset.start_angle_rad;
  scan.angular_step_rad = preset.angular_step_rad;
  scan.max_range_m = preset.max_range_is_no_return ? preset.max_range_m : 0.0;
  for (double r : true_r) {
    double z = preset.max_range_is_no_return ? preset.max_range_m : 0.0;
    if (r < preset.max_range_m) {
      // ξ is the noise of the corrected range (k ≈ 1/n): divide by k so that σ holds after it.
      const double logged =
          preset.sim_scale_n * r + preset.sim_offset_c_m + noise(*rng) / preset.range_scale_k;
      z = std::round(logged / preset.range_resolution_m) * preset.range_resolution_m;
    }
    scan.ranges_m.push_back(static_cast<float>(z));
  }
  return scan;
}

ScanPoints Points(const io::ScanRecord& scan, const io::ScannerPreset& preset,
                  const calib::DetectorOptions& opt) {
  return ToScanPoints(scan, preset, opt.min_range_m, opt.mixed_pixel_jump_m, nullptr);
}

LineGate Gate(double theta_rad, double theta_hw_rad, double rho_m, double rho_hw_m) {
  LineGate g;
  g.theta_rad = theta_rad;
  g.theta_halfwidth_rad = theta_hw_rad;
  g.rho_m = rho_m;
  g.rho_halfwidth_m = rho_hw_m;
  return g;
}

// Wide (first pass) and tight (second pass) gates, deliberately off-centre from the truth as a
// rough mount would place them.
LineGate WideGate(double theta_rad, double rho_m) {
  const calib::DetectorOptions o;
  return Gate(theta_rad + 8.0 * kDegToRad, o.wide_angle_gate_rad, rho_m - 2.0, o.wide_offset_gate_m);
}
LineGate TightGate(double theta_rad, double rho_m) {
  const calib::DetectorOptions o;
  return Gate(theta_rad - 0.8 * kDegToRad, o.tight_angle_gate_rad, rho_m + 0.1, o.tight_offset_gate_m);
}

// Within k reported σ of the truth (3σ for single scans; 4σ where a test runs many seeds, so
// that a 1-in-370 draw does not fail it).
void ExpectNearTruth(const WallDetection& det, double theta_rad, double rho_m, double k = 3.0) {
  ASSERT_TRUE(det.found) << det.reason;
  EXPECT_NEAR(det.rho_m, rho_m, k * det.sigma_rho_m);
  EXPECT_NEAR(std::remainder(det.theta_rad - theta_rad, 2 * kPi), 0.0, k * det.sigma_theta_rad);
  EXPECT_GT(det.sigma_rho_m, 0.0);
  EXPECT_GT(det.sigma_theta_rad, 0.0);
}

// ---- Tests ------------------------------------------------------------------------------------

TEST(WallDetectorTest, FindsCleanWall) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  const calib::DetectorOptions opt;
  const double theta = 0.3, rho = 7.5;
  Scene scene = OneWall(theta, rho, -5.0, 6.0);
  std::mt19937 rng(1);
  const auto true_r = TrueRanges(scene, sick);
  const ScanPoints pts = Points(Log(true_r, sick, &rng), sick, opt);
  for (const LineGate& gate : {WideGate(theta, rho), TightGate(theta, rho), LineGate()}) {
    const WallDetection det = DetectWall(pts, gate, opt, sick.range_sigma_m);
    ExpectNearTruth(det, theta, rho);
    EXPECT_GE(det.num_inliers, 65);  // 72 beams see the wall; the two end points are suspect
    EXPECT_EQ(static_cast<int>(det.inliers.size()), det.num_inliers);
    EXPECT_LT(det.residual_rms_m, 0.015);
    EXPECT_NEAR(det.range_min_m, rho, 0.05);
    EXPECT_GT(det.hough_votes, 10);
    EXPECT_TRUE(det.accumulator.empty());
  }
}

TEST(WallDetectorTest, ReportedSigmaMatchesScatterOverManyScans) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  const calib::DetectorOptions opt;
  const double theta = 0.3, rho = 7.5;
  Scene scene;
  // The wall's centre lies 4 m along the line from the foot of the perpendicular, so rho and
  // theta are strongly correlated.
  scene.walls.push_back(WallOnLine(theta, rho, 0.0, 8.0));
  const auto true_r = TrueRanges(scene, sick);
  std::mt19937 rng(2);
  const int kDraws = 200;
  double sum_r = 0, sum_t = 0, sum_rr = 0, sum_tt = 0, sum_rt = 0;
  double rep_var_r = 0, rep_var_t = 0, rep_cov = 0;
  for (int k = 0; k < kDraws; ++k) {
    const ScanPoints pts = Points(Log(true_r, sick, &rng), sick, opt);
    const WallDetection det = DetectWall(pts, WideGate(theta, rho), opt, sick.range_sigma_m);
    ASSERT_TRUE(det.found) << det.reason;
    const double er = det.rho_m - rho, et = det.theta_rad - theta;
    sum_r += er;
    sum_t += et;
    sum_rr += er * er;
    sum_tt += et * et;
    sum_rt += er * et;
    rep_var_r += det.sigma_rho_m * det.sigma_rho_m / kDraws;
    rep_var_t += det.sigma_theta_rad * det.sigma_theta_rad / kDraws;
    rep_cov += det.cov_rho_theta / kDraws;
  }
  const double mean_r = sum_r / kDraws, mean_t = sum_t / kDraws;
  const double emp_var_r = sum_rr / kDraws - mean_r * mean_r;
  const double emp_var_t = sum_tt / kDraws - mean_t * mean_t;
  const double emp_cov = sum_rt / kDraws - mean_r * mean_t;
  const double ratio_r = std::sqrt(rep_var_r / emp_var_r);
  const double ratio_t = std::sqrt(rep_var_t / emp_var_t);
  EXPECT_GT(ratio_r, 1.0 / 1.5);
  EXPECT_LT(ratio_r, 1.5);
  EXPECT_GT(ratio_t, 1.0 / 1.5);
  EXPECT_LT(ratio_t, 1.5);
  // The reported correlation must have the right sign and size.
  const double emp_corr = emp_cov / std::sqrt(emp_var_r * emp_var_t);
  const double rep_corr = rep_cov / std::sqrt(rep_var_r * rep_var_t);
  EXPECT_NEAR(rep_corr, emp_corr, 0.2);
  // Unbiased: the mean error is well inside its own standard error (×4).
  EXPECT_LT(std::abs(mean_r), 4.0 * std::sqrt(emp_var_r / kDraws));
  EXPECT_LT(std::abs(mean_t), 4.0 * std::sqrt(emp_var_t / kDraws));
  std::printf(
      "sigma rho reported %.2f mm, empirical %.2f mm; sigma theta %.4f / %.4f deg; "
      "corr %.2f / %.2f\n",
      1e3 * std::sqrt(rep_var_r), 1e3 * std::sqrt(emp_var_r), std::sqrt(rep_var_t) / kDegToRad,
      std::sqrt(emp_var_t) / kDegToRad, rep_corr, emp_corr);
}

// Range noise lies along the beams. A fit that takes it as isotropic turns the normal towards
// the beams by about σ² Σ sin 2i / (2 Σ s²) (i the incidence, s the along-line positions), with
// the sign of i: two scanners seeing a wall at mirrored incidence then disagree in yaw. Many
// scans of one wall, seen at +30° and at −30° mean incidence: the mean angle error of each must
// lie within four standard errors of zero (the standard error from the scans' own scatter).
TEST(WallDetectorTest, RangeNoiseAtIncidenceDoesNotTurnTheLine) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  const calib::DetectorOptions opt;
  const double theta = 0.0, rho = 1.0;
  // Incidence 5°..55° on one side, 51 beams: the isotropic fit's bias (about 17 mdeg) is about
  // 1/11 of a scan's σθ (190 mdeg), i.e. 12 standard errors of the mean over kScans scans.
  const double s_near_m = rho * std::tan(5.0 * kDegToRad), s_far_m = rho * std::tan(55.0 * kDegToRad);
  constexpr int kScans = 20000;
  for (const double side : {+1.0, -1.0}) {
    const Scene scene = side > 0 ? OneWall(theta, rho, s_near_m, s_far_m)
                                 : OneWall(theta, rho, -s_far_m, -s_near_m);
    const auto true_r = TrueRanges(scene, sick);
    std::mt19937 rng(side > 0 ? 11 : 12);
    double sum = 0.0, sum_sq = 0.0, reported_var = 0.0;
    for (int k = 0; k < kScans; ++k) {
      const ScanPoints pts = Points(Log(true_r, sick, &rng), sick, opt);
      const WallDetection det = DetectWall(pts, TightGate(theta, rho), opt, sick.range_sigma_m);
      ASSERT_TRUE(det.found) << det.reason;
      const double e = std::remainder(det.theta_rad - theta, 2.0 * kPi);
      sum += e;
      sum_sq += e * e;
      reported_var += det.sigma_theta_rad * det.sigma_theta_rad / kScans;
    }
    const double mean = sum / kScans;
    const double scatter = std::sqrt(sum_sq / kScans - mean * mean);
    const double standard_error = scatter / std::sqrt(double(kScans));
    std::printf("incidence %+.0f deg: mean angle error %+.2f mdeg, standard error %.2f mdeg, "
                "scan sigma %.1f mdeg (reported %.1f)\n",
                side * 30.0, 1e3 * mean / kDegToRad, 1e3 * standard_error / kDegToRad,
                1e3 * scatter / kDegToRad, 1e3 * std::sqrt(reported_var) / kDegToRad);
    EXPECT_LT(std::abs(mean), 4.0 * standard_error) << "side " << side;
    // The reported σ matches the scatter (σ/scatter is known to 1/√(2·kScans) = 0.5 %; the
    // margin is the linearisation's and the quantisation's; the perpendicular model, every
    // point counted with the full range σ, reports 17 % too much here).
    EXPECT_NEAR(std::sqrt(reported_var) / scatter, 1.0, 0.08) << "side " << side;
  }
}

TEST(WallDetectorTest, FindsWallBehindTrees) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  const calib::DetectorOptions opt;
  const double theta = -0.15, rho = 9.0;
  Scene scene = OneWall(theta, rho, -7.0, 7.0);
  // An orchard row in front of the wall (Barawid 2007 works in an orchard).
  for (double y : {-5.0, -3.2, -1.5, 0.2, 1.9, 3.6, 5.3}) {
    scene.trunks.push_back({Eigen::Vector2d(5.5 + 0.1 * y, y), 0.25});
  }
  std::mt19937 rng(3);
  const ScanPoints pts = Points(Log(TrueRanges(scene, sick), sick, &rng), sick, opt);
  for (const LineGate& gate : {WideGate(theta, rho), TightGate(theta, rho)}) {
    const WallDetection det = DetectWall(pts, gate, opt, sick.range_sigma_m);
    ExpectNearTruth(det, theta, rho);
    EXPECT_GE(det.num_inliers, opt.min_inliers);
    for (int i : det.inliers) EXPECT_GT(pts.range_m[i], rho - 0.1);  // no bark in the fit
  }
}

TEST(WallDetectorTest, IgnoresSecondWallOutsideGate) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  const calib::DetectorOptions opt;
  const double theta = 0.0, rho = 10.0;
  Scene scene = OneWall(theta, rho, -2.0, 2.0);  // the surveyed wall: 23 beams
  // An unsurveyed side wall, perpendicular and closer: many more points.
  scene.walls.push_back({Eigen::Vector2d(0.5, -3.0), Eigen::Vector2d(9.5, -3.0)});
  // A long parallel fence beyond the wall, outside the wide distance gate (10 ± 6 m, centred
  // 2 m short of the truth by WideGate): also more points than the wall.
  scene.walls.push_back({Eigen::Vector2d(17.0, -2.5), Eigen::Vector2d(17.0, 14.0)});
  std::mt19937 rng(4);
  const ScanPoints pts = Points(Log(TrueRanges(scene, sick), sick, &rng), sick, opt);

  // Without a gate the biggest line wins, and it is not the wall: the scene is a real trap.
  const WallDetection ungated = DetectWall(pts, LineGate(), opt, sick.range_sigma_m);
  ASSERT_TRUE(ungated.found);
  EXPECT_GT(std::abs(ungated.theta_rad - theta), 10.0 * kDegToRad);
  EXPECT_GT(ungated.num_inliers, 30);

  for (const LineGate& gate : {WideGate(theta, rho), TightGate(theta, rho)}) {
    const WallDetection det = DetectWall(pts, gate, opt, sick.range_sigma_m);
    ExpectNearTruth(det, theta, rho);
    EXPECT_LE(det.num_inliers, 23);
  }
  // A gate between the scanner and the wall holds no line: neither wall nor fence may be
  // taken through the flanks of their sinusoids.
  const WallDetection between =
      DetectWall(pts, Gate(theta, 0.35, 6.0, 2.0), opt, sick.range_sigma_m);
  EXPECT_FALSE(between.found) << between.rho_m << " " << between.theta_rad;
}

TEST(WallDetectorTest, StrongLineJustOutsideAngleGateIsNotChosen) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  calib::DetectorOptions opt;
  const double theta = 0.0, rho = 8.0;
  const LineGate gate = Gate(theta, 10.0 * kDegToRad, rho, 6.0);
  // A dense wall close by whose normal lies two or four accumulator cells (0.5°, 1°) beyond the
  // gate's edge: its flank spills into the gate's edge rows.
  // (One cell out is within the noise of its own fit, 0.07° here: the gate's edge is that fuzzy.)
  int trapped = 0;
  for (int cells_out : {2, 4}) {
    Scene scene = OneWall(theta, rho, -1.5, 1.5);  // 22 beams
    const double theta_other =
        gate.theta_rad + gate.theta_halfwidth_rad + cells_out * opt.hough_theta_step_rad;
    scene.walls.push_back(WallOnLine(theta_other, 3.0, 1.0, 6.0));  // 45 beams
    for (unsigned seed = 0; seed < 20; ++seed) {
      SCOPED_TRACE(testing::Message() << cells_out << " cells out, seed " << seed);
      std::mt19937 rng(500 + seed);
      const ScanPoints pts = Points(Log(TrueRanges(scene, sick), sick, &rng), sick, opt);
      const WallDetection det = DetectWall(pts, gate, opt, sick.range_sigma_m, true);
      ExpectNearTruth(det, theta, rho, 4.0);
      // The accumulator and its axes are reported for plots.
      ASSERT_FALSE(det.accumulator.empty());
      EXPECT_EQ(det.accumulator.type(), CV_32S);
      EXPECT_EQ(det.accumulator.rows, 2 * 40 + 3);  // ±10° in 0.25° cells and two margin rows
      EXPECT_NEAR(det.acc_theta0_rad + (det.accumulator.rows - 1) / 2.0 * det.acc_theta_step_rad,
                  gate.theta_rad, 1e-9);
      EXPECT_DOUBLE_EQ(det.acc_rho_step_m, opt.hough_rho_step_m);
      double edge_votes = 0;  // in the gate's last row
      cv::minMaxLoc(det.accumulator.row(det.accumulator.rows - 2), nullptr, &edge_votes);
      if (cells_out == 2 && edge_votes > det.hough_votes) ++trapped;
    }
  }
  // The trap is real: mostly, a cell inside the gate outvotes the wall's own peak.
  EXPECT_GE(trapped, 10);
}

TEST(WallDetectorTest, MixedPixelsDoNotBiasTheLine) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  const calib::DetectorOptions opt;
  const double theta = 0.05, rho = 8.0;
  Scene scene = OneWall(theta, rho, -5.0, 5.0);
  scene.walls.push_back(WallOnLine(theta, 14.0, -15.0, 15.0));  // background beyond the ends
  for (double y : {-2.0, -0.7, 0.7, 2.0}) scene.trunks.push_back({Eigen::Vector2d(5.0, y), 0.2});
  const auto true_r = TrueRanges(scene, sick);
  // Mixed pixels (Ye & Borenstein 2002 §4.5; Okubo et al. 2009): a beam at a depth edge returns a range between the two
  // surfaces. Put each one 2.5 cm off the wall, inside the trimming band (3σ = 3 cm), so that
  // only the mixed-pixel flag can keep it out: in front of the wall where the other surface is a
  // trunk, behind it beyond the wall's ends.
  auto on_wall = [&](int i) {
    const double b = sick.start_angle_rad + i * sick.angular_step_rad;
    return std::abs(true_r[i] - rho / std::cos(b - theta)) < 1e-6;
  };
  std::vector<double> mixed_r = true_r;
  int injected = 0;
  for (int i = 1; i + 1 < sick.num_beams; ++i) {
    if (!on_wall(i)) continue;
    for (int j : {i - 1, i + 1}) {
      if (on_wall(j)) continue;
      const double b = sick.start_angle_rad + j * sick.angular_step_rad;
      const double wall_r = rho / std::cos(b - theta);
      mixed_r[j] = true_r[j] < true_r[i] ? wall_r - 0.025 : wall_r + 0.025;
      ++injected;
    }
  }
  ASSERT_EQ(injected, 10);  // both edges of four trunks, both ends of the wall

  // Noise-free scans isolate the bias (the reported σ still assumes the LMS 291's 1 cm).
  io::ScannerPreset exact = sick;
  exact.range_sigma_m = 0.0;
  exact.range_resolution_m = 1e-5;
  std::mt19937 rng(6);
  const ScanPoints mixed = Points(Log(mixed_r, exact, &rng), sick, opt);
  const WallDetection det = DetectWall(mixed, WideGate(theta, rho), opt, sick.range_sigma_m);
  ASSERT_TRUE(det.found) << det.reason;
  EXPECT_LT(std::abs(det.rho_m - rho), det.sigma_rho_m);
  EXPECT_LT(std::abs(det.theta_rad - theta), det.sigma_theta_rad);
  for (int i : det.inliers) EXPECT_FALSE(mixed.mixed_suspect[i]);

  // The same scan with the flags cleared: the mixed pixels do get in and do bias the line, so
  // the check above is not vacuous.
  ScanPoints unflagged = mixed;
  std::fill(unflagged.mixed_suspect.begin(), unflagged.mixed_suspect.end(), 0);
  const WallDetection biased = DetectWall(unflagged, WideGate(theta, rho), opt, sick.range_sigma_m);
  ASSERT_TRUE(biased.found);
  EXPECT_GT(std::abs(biased.rho_m - rho) / det.sigma_rho_m, 1.0);

  // With noise, the line stays within 3σ of the truth.
  const ScanPoints noisy = Points(Log(mixed_r, sick, &rng), sick, opt);
  ExpectNearTruth(DetectWall(noisy, WideGate(theta, rho), opt, sick.range_sigma_m), theta, rho);
}

TEST(WallDetectorTest, RejectsWhenTooFewInliers) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  calib::DetectorOptions opt;
  const double theta = 0.0, rho = 8.0;
  Scene scene = OneWall(theta, rho, -0.6, 0.6);  // 9 beams, 7 not at an edge
  std::mt19937 rng(7);
  const ScanPoints pts = Points(Log(TrueRanges(scene, sick), sick, &rng), sick, opt);
  // The wide gate: seven points leave the wall's direction uncertain to ~1°.
  const WallDetection det = DetectWall(pts, WideGate(theta, rho), opt, sick.range_sigma_m);
  EXPECT_FALSE(det.found);
  EXPECT_NE(det.reason.find("inliers (need 15)"), std::string::npos) << det.reason;
  EXPECT_TRUE(det.inliers.empty());

  opt.min_inliers = 5;
  const WallDetection relaxed = DetectWall(pts, WideGate(theta, rho), opt, sick.range_sigma_m);
  EXPECT_TRUE(relaxed.found) << relaxed.reason;

  // Nothing at all in the gate.
  const WallDetection empty = DetectWall(pts, Gate(kPi, 0.1, 8.0, 0.5), opt, sick.range_sigma_m);
  EXPECT_FALSE(empty.found);
  EXPECT_EQ(empty.reason, "no line within the gates");
  EXPECT_FALSE(DetectWall(ScanPoints(), LineGate(), opt, sick.range_sigma_m).found);
}

TEST(WallDetectorTest, SegmentGateDropsPointsBeyondWallEnds) {
  const io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  const calib::DetectorOptions opt;
  const double theta = 0.0, rho = 8.0;
  Scene scene = OneWall(theta, rho, -3.0, 3.0);  // the surveyed wall
  // A longer fence almost in line with it, 4 cm behind, beyond its end: inside the Hough band.
  scene.walls.push_back(WallOnLine(theta, rho + 0.04, 3.6, 12.0));
  std::mt19937 rng(8);
  const ScanPoints pts = Points(Log(TrueRanges(scene, sick), sick, &rng), sick, opt);

  LineGate gate = WideGate(theta, rho);
  const WallDetection loose = DetectWall(pts, gate, opt, sick.range_sigma_m);
  ASSERT_TRUE(loose.found);
  int beyond = 0;
  for (int i : loose.inliers) beyond += pts.p_scanner_m[i].y() > 3.5;
  EXPECT_GT(beyond, 10);  // without the segment the fence is taken as wall

  gate.has_segment = true;
  gate.segment_a_scanner = Eigen::Vector2d(rho, 3.0);  // either order
  gate.segment_b_scanner = Eigen::Vector2d(rho, -3.0);
  const WallDetection det = DetectWall(pts, gate, opt, sick.range_sigma_m);
  ExpectNearTruth(det, theta, rho);
  for (int i : det.inliers) {
    EXPECT_LE(std::abs(pts.p_scanner_m[i].y()), 3.0 + opt.wall_extent_margin_m);
  }
}

TEST(WallDetectorTest, HandlesUrgGeometry) {
  // Hokuyo URG-04LX (Okubo, Ye & Borenstein 2009): 682 beams over 240°, 4 m range, error codes for no return,
  // range correction k = 1.0102, b = −7 mm undoing the simulation model n, c. A room corner.
  const io::ScannerPreset urg = testing_support::ShippedPreset("hokuyo_urg04lx");
  calib::DetectorOptions opt;
  opt.min_range_m = 0.1;
  const double theta = 0.1, rho = 2.0;
  Scene scene = OneWall(theta, rho, -1.5, 1.7);
  scene.walls.push_back(WallOnLine(theta + kPi / 2, 1.7, -2.0, 1.6));  // side wall: a corner
  scene.trunks.push_back({Eigen::Vector2d(1.2, -0.4), 0.08});           // a table leg
  std::mt19937 rng(9);
  const io::ScanRecord scan = Log(TrueRanges(scene, urg), urg, &rng);
  RangeCounts counts;
  const ScanPoints pts = ToScanPoints(scan, urg, opt.min_range_m, opt.mixed_pixel_jump_m, &counts);
  EXPECT_GT(counts.error_code, 100);  // the open side of the room
  for (const LineGate& gate : {WideGate(theta, rho), TightGate(theta, rho)}) {
    const WallDetection det = DetectWall(pts, gate, opt, urg.range_sigma_m);
    ExpectNearTruth(det, theta, rho);
    EXPECT_GT(det.num_inliers, 150);
    EXPECT_LT(det.sigma_rho_m, 0.001);
  }
}

}  // namespace
}  // namespace wallcal::calib

namespace wallcal::calib {
namespace {

// The detection's range-offset gain predicts how its line moves when every range of the scan is
// off by an offset (the same draws of noise, a resolution too fine to round differently), and
// a scale error moves rho by rho·δk and theta not at all. The wall lies to one side of the foot
// of the perpendicular, so an offset also turns the line (the far points move less along the
// normal than the near ones).
TEST(WallDetectorTest, RangeOffsetGainPredictsTheLinesMove) {
  io::ScannerPreset sick = testing_support::ShippedPreset("sick_lms291");
  sick.range_resolution_m = 1e-7;
  sick.range_sigma_m = 0.002;
  const calib::DetectorOptions opt;
  const double theta = -0.2, rho = 5.0;
  const Scene scene = OneWall(theta, rho, 1.0, 9.0);
  const auto true_r = TrueRanges(scene, sick);
  const auto detect = [&](const io::ScannerPreset& logged) {
    std::mt19937 rng(7);
    return DetectWall(Points(Log(true_r, logged, &rng), sick, opt), TightGate(theta, rho), opt,
                      sick.range_sigma_m);
  };
  const WallDetection base = detect(sick);
  ASSERT_TRUE(base.found) << base.reason;
  // The points move by δb·cos of their incidence (0.98 to 0.49 along the wall), and the line
  // turns with them: rho at the foot of the perpendicular, off the wall, moves by about δb.
  EXPECT_GT(base.range_offset_gain.x(), 0.5);
  EXPECT_LT(base.range_offset_gain.x(), 1.5);
  EXPECT_GT(std::abs(base.range_offset_gain.y()), 1e-3);  // rad per metre of offset

  constexpr double kOffsetM = 0.02;
  io::ScannerPreset offset = sick;
  offset.sim_offset_c_m += kOffsetM / sick.range_scale_k;
  const WallDetection moved = detect(offset);
  ASSERT_TRUE(moved.found) << moved.reason;
  ASSERT_EQ(moved.inliers, base.inliers);
  // Linear in the offset to second order: 20 mm against ranges of 5–10 m.
  EXPECT_NEAR(moved.rho_m - base.rho_m, kOffsetM * base.range_offset_gain.x(), 2e-5);
  EXPECT_NEAR(moved.theta_rad - base.theta_rad, kOffsetM * base.range_offset_gain.y(), 2e-6);

  constexpr double kScale = 1e-3;
  io::ScannerPreset scaled = sick;
  scaled.sim_scale_n *= 1.0 + kScale;
  const WallDetection stretched = detect(scaled);
  ASSERT_TRUE(stretched.found) << stretched.reason;
  EXPECT_NEAR(stretched.rho_m - base.rho_m, kScale * base.rho_m, 2e-5);
  EXPECT_NEAR(stretched.theta_rad - base.theta_rad, 0.0, 2e-6);
}

}  // namespace
}  // namespace wallcal::calib
