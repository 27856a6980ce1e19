// SPDX-License-Identifier: Apache-2.0
#pragma once
// The 3-D site's share of the Cramér–Rao bound (bench/crb.h): what is random about a site that
// is not level, marginalised into the covariance of the wall lines like the survey's noise.
//   - The yard's grade, where the session has no attitude stream: the estimator takes each
//     scan's roll and pitch from the plane the antenna's RTK heights lie on, so the grade's
//     error is common to every scan. Its covariance is the generalised least-squares fit of a
//     plane to the antenna heights at the GNSS epochs, with the simulator's vertical noise
//     (gnss_vertical_factor times the horizontal Gauss–Markov bias and white noise; on at most
//     kMaxYardEpochs epochs evenly spread, each standing for its share of the white noise).
//   - The attitude stream's white noise (attitude_white_sigma_rad on roll and on pitch, each
//     sample), interpolated to the scan times as the heading's is.
//   - A leaning wall's lean (only a wall whose lean is set: the estimator takes the others as
//     upright), from the total station's horizontal noise on its points at their heights.
// The scanner's height and tilt are known here: the simulator writes them exact. Each term's
// effect on a line, d(rho, theta)/d(nuisance), is the 3-D model's (calib::PredictLine3d) by
// central differences at the truth. A configuration without a 3-D site adds nothing.

#include <Eigen/Core>
#include <vector>

#include "sim/simulation_config.h"

namespace wallcal::bench {

// One wall line of the bound, as the site terms need it.
struct SiteRowInput {
  double t_s = 0.0;        // true time since the start of the run
  int scanner = 0;         // index into the scanner configurations
  int config_wall = 0;     // index into config.walls
  double wall_angle_rad = 0.0;  // the wall's line {q : (cos α, sin α) · q = offset}, local ENU
  double wall_offset_m = 0.0;
  double sign = 1.0;       // the line's orientation towards the scanner (bench/crb.cc Row::sign)
};

// The epochs of the yard fit at most (the covariance of the heights is dense).
inline constexpr int kMaxYardEpochs = 1200;

// The covariance (2n × 2n, rho m and theta rad per row) the site adds to the lines of `rows`;
// all zero for a configuration without a 3-D site.
Eigen::MatrixXd SiteLineCovariance(const std::vector<sim::SimulationConfig>& scanner_configs,
                                   const std::vector<SiteRowInput>& rows);

// The grade's covariance (rise per metre along ENU x and y, squared) from the antenna heights
// of the whole run, as described above; zero without a 3-D site.
Eigen::Matrix2d YardGradeCovariance(const sim::SimulationConfig& config);

}  // namespace wallcal::bench
