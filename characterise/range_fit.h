// SPDX-License-Identifier: Apache-2.0
#pragma once
// The range model fitted to the wall returns (Ye & Borenstein 2002; Okubo, Ye & Borenstein 2009,
// whose straight-line fit of measured against true distance this is, with the true distance
// from a survey instead of a motion table):
//   z_i = n·t_i(θ) + c + drift(τ_i) + ξ_i,  ξ_i ~ N(0, σ²) independent between beams,
// t_i the true range of beam i from its station's pose and the surveyed wall, θ what every beam
// of a station (or of the session) shares and no beam can tell apart from the range model:
//   - per station: the antenna's GNSS error (2-D, first-order Gauss–Markov prior with the
//     options' τ and the station's GST σ, as the mount solver's), the heading's error (prior
//     solver.heading_sigma);
//   - per scan: its own pose error about the station's (eliminated scan by scan, see the .cc);
//   - per wall: its offset (prior: the survey's σ, calib/observation.h);
//   - the mount x, y, yaw (prior: --mount's covariance, or a loose one when estimated here).
// drift is piecewise linear in time (knots at 0, 7.5, 15, 30, 60, 120, 240 min and the end,
// within the session; none under 10 min), 0 at the first scan.
// Gauss–Newton on the linearised model; beams beyond 4 robust σ are left out (mixed pixels,
// occlusions), and so are beams whose footprint (one angular step wide) spans 10 cm or more of
// the wall's depth (t·tan(incidence)·step): their range is a mix over that depth. The covariance is the inverse of the normal matrix, priors included: the σ of
// n and c carry the shared errors, which is what makes them honest (a fit with independent
// beams only would give σ(c) ≈ σ/√N, far below the GNSS error every beam of a station shares).
// Internal to characterise/.

#include <vector>

#include <Eigen/Core>

#include "calib/observation.h"
#include "characterise/beam_returns.h"
#include "characterise/characterisation.h"

namespace wallcal::characterise {

struct FitSetup {
  const BeamSet* beams = nullptr;
  const std::vector<calib::WallGeometry>* walls = nullptr;
  calib::Mount mount_prior;
  Eigen::Matrix3d mount_prior_covariance = Eigen::Matrix3d::Identity();
  bool mount_given = false, mount_sigma_given = false;
  double gnss_tau_s = 60.0;
  double heading_sigma_rad = 0.0017;
  double gnss_white_sigma_m = 0.005, gnss_bias_sigma_m = 0.015;  // calibrate's solver options
  double quantum_m = 0.0;  // for Sheppard's correction of σ
  double angular_step_rad = 0.0175;  // |step| between beams (the footprint's width)
  double start_n = 1.0, start_c_m = 0.0;
  double start_sigma_m = 0.01;
};

struct FitOutput {
  RangeModel model;
  // Per beam (BeamSet order): the true range and incidence at the fitted θ (NaN for beams that
  // meet no wall), the residual z − model (NaN when not fitted: no reading, off the wall,
  // rejected), and the drift at its time.
  std::vector<float> true_range_m, incidence_rad, residual_m, drift_m;
  // The residual of the beams the noise is measured on, after the scan's own shift and turn
  // are removed (NaN for the others).
  std::vector<float> noise_residual_m;
  double robust_sigma_m = 0.0;  // the gate's σ (1.4826 MAD)
};

FitOutput FitRangeModel(const FitSetup& setup);

}  // namespace wallcal::characterise
