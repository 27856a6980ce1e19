// SPDX-License-Identifier: Apache-2.0
#pragma once
// The wall detector's line fit (internal to calib/): a trimmed total-least-squares start, its
// refinement by least squares along the beams (the range noise lies along them), and the
// detection's covariance from the same range model.
//
// Frame: scanner frame (x = bearing 0, y left, angles counter-clockwise, radians); metres.

#include <vector>

#include <Eigen/Core>

#include "calib/range_model.h"
#include "calib/wall_detector.h"

namespace wallcal::calib::internal {

// A line {p : normal·p = rho_m}, normal a unit vector pointing from the scanner towards the
// line (rho_m >= 0).
struct LineFit {
  Eigen::Vector2d normal = Eigen::Vector2d::UnitX();
  double rho_m = 0.0;
  // Set by RefineAlongBeams: the range model's information Σ a_i a_iᵀ (unit σ) and its sum of
  // squared range residuals (m²), from its last step (within 1e-6 of the line: FillDetection
  // takes them instead of another pass over the points).
  bool has_beam_model = false;
  Eigen::Matrix2d beam_information = Eigen::Matrix2d::Zero();
  Eigen::Vector2d beam_sum_a = Eigen::Vector2d::Zero();  // Σ a_i (unit σ)
  double beam_sum_e2_m2 = 0.0;
};

// Total-least-squares line through points[idx]: the normal is the eigenvector of the scatter
// matrix with the smaller eigenvalue, and the line passes through the centroid. False for fewer
// than two points or points that all coincide.
bool FitLine(const ScanPoints& points, const std::vector<int>& idx, LineFit* fit);

// Trimmed total-least-squares fit of the candidates (indices into points, ascending): *set
// ends as the candidates within trim_m (m) of the line, *fit as their line. The threshold
// shrinks from half the Hough band band_m to trim_m (halving each round) so that clutter inside
// the band (a trunk touching the wall) cannot drag the first fit far enough to trim away the
// wall itself; then it iterates at trim_m until the set no longer changes. False when a fit
// fails (too few points left).
bool TrimmedFit(const ScanPoints& points, const std::vector<int>& candidates, double trim_m,
                double band_m, LineFit* fit, std::vector<int>* set);

// Refines *fit, the total-least-squares line of points[idx], to the least-squares line along
// the beams: minimises Σ (r_i − ρ / (n(θ)·u_i))² over (ρ, θ), r_i the range and u_i the beam
// direction of point i (Gauss–Newton). Unbiased for range noise at any incidence, where total
// least squares turns the normal towards the beams. Leaves *fit unchanged and returns false
// for a degenerate set (a beam nearly along the line, a step that does not stay small).
bool RefineAlongBeams(const ScanPoints& points, const std::vector<int>& idx, LineFit* fit);

// Fills *det (found, line, covariance, inliers = set, range span, residual RMS, votes) from the
// final fit of the inliers `set`. Covariance σ² (Σ a_i a_iᵀ)⁻¹ with a_i the range model's
// derivatives in (ρ, θ), i.e. each inlier weighted by 1/(σ cos i)² at incidence i, and
// σ = max(range_sigma_m, RMS of the range residuals over N − 2) (m). residual_rms_m is the RMS
// of the range residuals over N.
void FillDetection(const ScanPoints& points, const LineFit& fit, std::vector<int> set,
                   double range_sigma_m, int votes, WallDetection* det);

}  // namespace wallcal::calib::internal
