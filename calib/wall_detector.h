// SPDX-License-Identifier: Apache-2.0
#pragma once
// Finds the surveyed wall as a straight line in one scan (Barawid 2007 §III.1, Eq. 2–3: the Hough
// transform r = x cos θ + y sin θ), improved: the accumulator covers only the gate predicted
// from the surveyed wall, points next to depth jumps (possible mixed pixels) do not vote, and
// the Hough line is refined by a trimmed least-squares fit along the beams that also gives its
// covariance.
//
// Frame: scanner frame (x = bearing 0, y left, angles counter-clockwise, radians); metres.

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "calib/range_model.h"
#include "common/angles.h"
#include "calib/wall_detector_options.h"

namespace wallcal::calib {

// Where the wall is expected in the scanner frame: the line
// {p : cos(theta)·px + sin(theta)·py = rho}, theta the normal from the scanner towards the wall.
// Gates are half-widths. Predicted from the surveyed wall, the vehicle pose and the current mount
// estimate. The defaults accept any line (theta over the full circle, any rho > 0).
struct LineGate {
  double theta_rad = 0, theta_halfwidth_rad = kPi;
  double rho_m = 0, rho_halfwidth_m = 1e9;
  // Optional: the surveyed wall's ends in the scanner frame; inliers must project onto the
  // segment ± margin (calib::DetectorOptions::wall_extent_margin_m).
  bool has_segment = false;
  Eigen::Vector2d segment_a_scanner = Eigen::Vector2d::Zero(),
                  segment_b_scanner = Eigen::Vector2d::Zero();
};

struct WallDetection {
  bool found = false;
  // When not found: "no line within the gates", "only N inliers (need M)", "best line (...)
  // lies outside the gates", "invalid detector options or gate".
  std::string reason;
  double rho_m = 0, theta_rad = 0;  // rho > 0, theta in (−π, π]
  // From the least-squares fit (range noise only): m, rad, m·rad.
  double sigma_rho_m = 0, sigma_theta_rad = 0, cov_rho_theta = 0;
  // How the fitted (rho, theta) move per metre of an offset on every range: (m/m, rad/m). A
  // relative scale error δk moves them by (rho·δk, 0).
  Eigen::Vector2d range_offset_gain = Eigen::Vector2d::Zero();
  int num_inliers = 0;
  double range_min_m = 0, range_max_m = 0;  // range span of the inliers
  double residual_rms_m = 0;                // RMS of the inliers' range residuals (m)
  int hough_votes = 0;                      // votes in the chosen accumulator cell
  std::vector<int> inliers;                 // indices into ScanPoints, ascending
  // For reports: the accumulator around the gate (rows = theta cells, cols = rho cells) and its
  // axes. Row k is centred on theta acc_theta0_rad + k·acc_theta_step_rad, column j on rho
  // acc_rho0_m + j·acc_rho_step_m. It includes one margin cell beyond the gate on each side (none
  // in theta when the gate spans the circle) and holds the votes before any withdrawal.
  cv::Mat accumulator;  // CV_32S; filled only when keep_accumulator is true
  double acc_theta0_rad = 0, acc_theta_step_rad = 0, acc_rho0_m = 0, acc_rho_step_m = 0;
};

// Detects the wall line in `points` inside `gate`:
//  1. Hough voting (Barawid 2007 Eq. 2) over theta cells of options.hough_theta_step_rad spanning the
//     gate's angular range and rho cells of options.hough_rho_step_m spanning its distance range;
//     mixed_suspect points do not vote. Peaks must be local maxima inside the gate, so a strong
//     line just outside (another wall, a parallel fence) is not picked through its spill-over.
//  2. Points within options.inlier_band_m of the peak line (not mixed_suspect; with
//     gate.has_segment, projecting onto the segment ± options.wall_extent_margin_m) are candidates.
//  3. Total-least-squares line fit, trimmed iteratively: keep candidates with |residual| <=
//     options.refine_sigma_factor · max(range_sigma_m, 3 mm) until the set is stable. The
//     trimmed set's line is then refined by least squares along the beams (the range noise lies
//     along them): Σ (r_i − ρ / cos i_i)² over (ρ, θ), i_i the incidence of beam i, by a few
//     Gauss–Newton steps. Total least squares alone turns the normal towards the beams by about
//     σ² Σ sin 2i / (2 Σ s²) (s the positions along the line).
//  4. Found when >= options.min_inliers remain and the fitted line lies inside the gate (to half
//     an accumulator cell). Up to three peaks are tried, strongest first. A fitted line outside
//     the gate withdraws its points' votes and the peak search starts again (a few rounds).
// Covariance of the range model: σ² (Σ a_i a_iᵀ)⁻¹, a_i = (1, −d·p_i) / cos i_i the derivatives
// of the predicted range ρ / cos i_i in (ρ, θ) (d the line's direction, p_i the point), i.e.
// each inlier counts with its perpendicular σ·cos i_i; σ = max(range_sigma_m, RMS of the range
// residuals). At normal incidence: with N inliers, s_i their positions along the line about
// their centroid and t the centroid's position along the line from the foot of the
// perpendicular, var θ = σ²/Σs_i², var ρ = σ²(1/N + t²/Σs_i²), cov(ρ, θ) = σ² t/Σs_i²
// (derivation in internal/line_fit.cc).
// range_sigma_m: the preset's 1σ range noise (m). Never throws; a scan without the wall is a
// result with found = false and a reason.
WallDetection DetectWall(const ScanPoints& points, const LineGate& gate,
                         const calib::DetectorOptions& options,
                         double range_sigma_m /* preset noise σ */, bool keep_accumulator = false);

}  // namespace wallcal::calib
