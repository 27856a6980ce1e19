// SPDX-License-Identifier: Apache-2.0
#include "calib/internal/line_fit.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "common/angles.h"

namespace wallcal::calib::internal {
namespace {
// Least squares along the beams.
// The range noise lies along each beam (Ye & Borenstein 2002: z = n·y + c + ξ, the bearing
// exact): point i is p_i = r_i u_i, u_i its beam's unit direction, and the line
// {p : n(θ)·p = ρ} predicts the range ρ / (n(θ)·u_i). Total least squares (FitLine) takes the
// noise as isotropic; at incidence i the scatter matrix gains σ_r² Σ u_i u_iᵀ, whose cross term
// turns the normal by about σ_r² Σ sin 2i / (2 Σ s_i²) towards the beams (a few mdeg for a
// 10 mm scanner on a short wall; two scanners at mirrored incidence see opposite signs). The
// maximum-likelihood line minimises the range residuals instead:
//   e_i = r_i − ρ / c_i,  c_i = n(θ)·u_i = cos of the incidence,
// whose derivatives do not depend on the noise: ∂(ρ/c_i)/∂ρ = 1/c_i and
// ∂(ρ/c_i)/∂θ = −ρ (d·u_i)/c_i² = −(d·p̂_i)/c_i, with d = (−sin θ, cos θ) and p̂_i the predicted
// point. Equivalently e_i = (n·p_i − ρ)/c_i: the perpendicular residual weighted by the
// incidence, but with the weight's own derivative kept (reweighted total least squares that
// drops it keeps a bias of the same kind).

// Beams nearer than this to running along the line (cos of the incidence) stop the refinement;
// the presets' maximum incidence (75° to 80°) keeps every return well above it.
constexpr double kMinBeamCos = 0.05;
// Gauss–Newton from the total-least-squares start, which lies within a few mdeg and a mm of the
// optimum: each step shrinks the error by about the residuals' size over the ranges' (1e-3),
// so two steps usually reach kBeamStepTolerance and a third is a margin.
constexpr int kMaxBeamSteps = 3;
// A step below this (rad in θ, m in ρ) ends the refinement after it is taken: what remains is
// ~1e-9, against a scan's σ of 1e-4 rad and 1e-3 m and a relative mount's σ of 6e-6 rad. The
// refinement runs on every scan of a session: each step is a pass over the inliers.
constexpr double kBeamStepTolerance = 1e-6;

// One inlier's row of the line's range model at (theta, rho): the prediction's derivatives
// a = (∂/∂ρ, ∂/∂θ) and the range residual e. False when the beam runs nearly along the line.
struct BeamRow {
  Eigen::Vector2d a;
  double e_m = 0.0;
};
bool RowAt(const Eigen::Vector2d& p, const Eigen::Vector2d& n, const Eigen::Vector2d& d,
           double rho_m, BeamRow* row) {
  const double r = p.norm();
  if (!(r > 0.0)) return false;
  const double c = n.dot(p) / r;
  if (!(c > kMinBeamCos)) return false;
  const double predicted_r = rho_m / c;
  row->a = Eigen::Vector2d(1.0 / c, -predicted_r * d.dot(p) / (r * c));
  row->e_m = r - predicted_r;
  return true;
}

// Normal equations of the range model at the fit's line over idx: information = Σ a aᵀ
// (unit σ), gradient = Σ a e, and Σ e². False when a beam runs nearly along the line.
struct BeamNormalEquations {
  Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
  Eigen::Vector2d sum_a = Eigen::Vector2d::Zero();  // Σ a: a range offset's share of the gradient
  double sum_e2_m2 = 0.0;
};
bool NormalEquationsAt(const ScanPoints& points, const std::vector<int>& idx, double theta_rad,
                       double rho_m, BeamNormalEquations* eq) {
  const Eigen::Vector2d n(std::cos(theta_rad), std::sin(theta_rad));
  const Eigen::Vector2d d(-n.y(), n.x());
  *eq = BeamNormalEquations();
  BeamRow row;
  for (int i : idx) {
    if (!RowAt(points.p_scanner_m[i], n, d, rho_m, &row)) return false;
    eq->information.noalias() += row.a * row.a.transpose();
    eq->gradient += row.a * row.e_m;
    eq->sum_a += row.a;
    eq->sum_e2_m2 += row.e_m * row.e_m;
  }
  return true;
}

}  // namespace

bool FitLine(const ScanPoints& points, const std::vector<int>& idx, LineFit* fit) {
  if (idx.size() < 2) return false;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (int i : idx) c += points.p_scanner_m[i];
  c /= static_cast<double>(idx.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (int i : idx) {
    const Eigen::Vector2d q = points.p_scanner_m[i] - c;
    scatter += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  if (eig.info() != Eigen::Success) return false;
  // Eigenvalues ascending: column 0 is the normal. A degenerate cloud (all points coincide) has
  // no direction.
  if (!(eig.eigenvalues()(1) > 0.0)) return false;
  Eigen::Vector2d n = eig.eigenvectors().col(0).normalized();
  double rho = n.dot(c);
  if (rho < 0.0) {
    n = -n;
    rho = -rho;
  }
  fit->normal = n;
  fit->has_beam_model = false;
  fit->rho_m = rho;
  return true;
}

bool TrimmedFit(const ScanPoints& points, const std::vector<int>& candidates, double trim_m,
                double band_m, LineFit* fit, std::vector<int>* set) {
  *set = candidates;
  bool ok = FitLine(points, *set, fit);
  double threshold = std::max(trim_m, 0.5 * band_m);
  thread_local std::vector<int> next;  // reused: no allocation per scan once warm
  for (int iter = 0; ok && iter < 30; ++iter) {
    next.clear();
    for (int i : candidates) {
      if (std::abs(fit->normal.dot(points.p_scanner_m[i]) - fit->rho_m) <= threshold) {
        next.push_back(i);
      }
    }
    if (threshold <= trim_m && next == *set) break;
    set->swap(next);
    ok = FitLine(points, *set, fit);
    threshold = std::max(trim_m, 0.5 * threshold);
  }
  return ok;
}

bool RefineAlongBeams(const ScanPoints& points, const std::vector<int>& idx, LineFit* fit) {
  if (idx.size() < 3) return false;
  double theta = std::atan2(fit->normal.y(), fit->normal.x());
  double rho = fit->rho_m;
  BeamNormalEquations eq;
  for (int step = 0; step < kMaxBeamSteps; ++step) {
    if (!NormalEquationsAt(points, idx, theta, rho, &eq)) return false;
    const double det = eq.information.determinant();
    if (!(det > 0.0)) return false;
    const Eigen::Vector2d delta = eq.information.inverse() * eq.gradient;  // (δρ, δθ)
    // The start lies within mdeg of the optimum: a big step means the set is degenerate.
    if (!(std::abs(delta.y()) < 0.05) || !(std::abs(delta.x()) < 0.5)) return false;
    rho += delta.x();
    theta += delta.y();
    if (std::abs(delta.y()) < kBeamStepTolerance && std::abs(delta.x()) < kBeamStepTolerance) {
      break;
    }
  }
  if (!(rho > 0.0)) return false;
  fit->normal = Eigen::Vector2d(std::cos(theta), std::sin(theta));
  fit->rho_m = rho;
  fit->has_beam_model = true;
  fit->beam_information = eq.information;
  fit->beam_sum_a = eq.sum_a;
  fit->beam_sum_e2_m2 = eq.sum_e2_m2;
  return true;
}

// Covariance of (rho, theta): σ² (Σ a_i a_iᵀ)⁻¹ with a_i the range model's rows above (RowAt),
// i.e. each inlier weighted by 1/(σ c_i)², its perpendicular σ being σ c_i at incidence i. With
// every c_i = 1 this is the perpendicular model: with the inlier p_i = c + s_i·d + e_i·n about
// the centroid c (Σ s_i = 0), d·p_i = t + s_i, t = d·c the centroid's position along the line
// from the foot of the perpendicular, so Σ a aᵀ = [[N, −N t], [−N t, N t² + S]], S = Σ s_i²,
// and var θ = σ²/S, var ρ = σ² (1/N + t²/S), cov(ρ, θ) = σ² t/S.
// σ = max(preset σ, RMS of the range residuals over N − 2): the RMS covers walls rougher than
// the preset's noise; the preset keeps a lucky scan from claiming more than the sensor can do.
// residual_rms_m: the RMS of the same range residuals over N (what the σ rule compares).
// range_offset_gain: the fit's response to an offset δb on every range, (Σ a aᵀ)⁻¹ Σ a (the
// Gauss–Newton step for residuals all moved by δb, per metre of δb). A scale error δk moves
// every range by δk·r_i, and since aᵢᵀ(ρ, 0) = ρ/cᵢ = r_i its response is (ρ, 0)·δk exactly.
void FillDetection(const ScanPoints& points, const LineFit& fit, std::vector<int> set,
                   double range_sigma_m, int votes, WallDetection* det) {
  const int n = static_cast<int>(set.size());
  const double theta = WrapAngle(std::atan2(fit.normal.y(), fit.normal.x()));
  BeamNormalEquations eq;
  if (fit.has_beam_model) {
    eq.information = fit.beam_information;
    eq.sum_e2_m2 = fit.beam_sum_e2_m2;
    eq.sum_a = fit.beam_sum_a;
  } else if (!NormalEquationsAt(points, set, theta, fit.rho_m, &eq)) {
    // Only a degenerate set gets here (the refinement refused it): the perpendicular model,
    // every c_i taken as 1.
    const Eigen::Vector2d d(-fit.normal.y(), fit.normal.x());
    eq = BeamNormalEquations();
    for (int i : set) {
      const Eigen::Vector2d a(1.0, -d.dot(points.p_scanner_m[i]));
      const double e = fit.normal.dot(points.p_scanner_m[i]) - fit.rho_m;
      eq.information.noalias() += a * a.transpose();
      eq.sum_e2_m2 += e * e;
      eq.sum_a += a;
    }
  }
  double r_min = std::numeric_limits<double>::infinity(), r_max = 0.0;
  for (int i : set) {
    r_min = std::min(r_min, double(points.range_m[i]));
    r_max = std::max(r_max, double(points.range_m[i]));
  }
  const double rms = std::sqrt(eq.sum_e2_m2 / std::max(1, n - 2));  // two parameters fitted
  const double sigma = std::max(range_sigma_m, rms);
  const Eigen::Matrix2d covariance = sigma * sigma * eq.information.inverse();

  det->found = true;
  det->reason.clear();
  det->rho_m = fit.rho_m;
  det->theta_rad = theta;
  det->sigma_rho_m = std::sqrt(covariance(0, 0));
  det->sigma_theta_rad = std::sqrt(covariance(1, 1));
  det->cov_rho_theta = covariance(0, 1);
  det->range_offset_gain = eq.information.inverse() * eq.sum_a;
  det->num_inliers = n;
  det->range_min_m = r_min;
  det->range_max_m = r_max;
  det->residual_rms_m = std::sqrt(eq.sum_e2_m2 / n);
  det->hough_votes = votes;
  det->inliers = std::move(set);
}

}  // namespace wallcal::calib::internal
