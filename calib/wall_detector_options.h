// SPDX-License-Identifier: Apache-2.0
#pragma once
// The wall detector's options (`detector:` in configs/calibrate.yaml), their YAML keys and the
// check of each. Angles are radians here and degrees in the file (keys ending in _deg).

#include "common/angles.h"
#include "io/config/options_map.h"

namespace wallcal::calib {

// Largest Hough accumulator (theta rows x rho columns) the detector options may ask for: 2e7
// cells (80 MB of counters). The defaults need about 1e5.
inline constexpr double kMaxHoughCells = 2e7;

struct DetectorOptions {
  double hough_rho_step_m = 0.02;         // accumulator cell size in distance
  double hough_theta_step_rad = 0.0043633231;  // 0.25 deg
  int min_inliers = 15;                   // fewer points on the line: no detection
  double inlier_band_m = 0.08;            // Hough band kept for the least-squares refinement
  double refine_sigma_factor = 3.0;       // final inliers: |residual| < factor * preset σ + res.
  double mixed_pixel_jump_m = 0.15;       // a range jump this big marks both neighbours suspect
  double min_range_m = 0.5;               // closer points are ignored (vehicle body, mud)
  // Gates around the line predicted from the surveyed wall and the pose:
  double wide_angle_gate_rad = 0.34906585;   // first pass (mount known only roughly), 20 deg
  double wide_offset_gate_m = 6.0;     // first pass distance gate
  double tight_angle_gate_rad = 0.034906585; // second pass (mount from the first solve), 2 deg
  double tight_offset_gate_m = 0.25;   // second pass distance gate
  // Second pass: fewest inliers on the line (a tight gate on a surveyed wall leaves little but
  // the wall; a short stretch of a second wall at the edge of the view still counts). On the
  // two-wall benchmark the lines of 5-14 beams take the bound on x from 8.62 to 7.72 mm.
  int tight_min_inliers = 5;
  double wall_extent_margin_m = 0.5;   // inliers must project onto the surveyed wall ± this
  void Validate() const;
};

// The `detector:` keys and their checks, for any visitor of io/config/options_map.h.
template <class V>
void VisitDetectorOptions(V& v, DetectorOptions& o) {
  v.Number("hough_rho_step_m", o.hough_rho_step_m, io::InRange(1e-4, 1.0));
  v.Scaled("hough_theta_step_deg", o.hough_theta_step_rad, kRadToDeg, io::InRange(0.001, 10.0));
  v.Integer("min_inliers", o.min_inliers, io::AtLeast(3));
  v.Number("inlier_band_m", o.inlier_band_m, io::Positive());
  v.Number("refine_sigma_factor", o.refine_sigma_factor, io::Positive());
  v.Number("mixed_pixel_jump_m", o.mixed_pixel_jump_m, io::Positive());
  v.Number("min_range_m", o.min_range_m, io::NonNegative());
  v.Scaled("wide_angle_gate_deg", o.wide_angle_gate_rad, kRadToDeg, io::AboveUpTo(0.0, 90.0));
  v.Number("wide_offset_gate_m", o.wide_offset_gate_m, io::Positive());
  v.Scaled("tight_angle_gate_deg", o.tight_angle_gate_rad, kRadToDeg, io::AboveUpTo(0.0, 90.0));
  v.Number("tight_offset_gate_m", o.tight_offset_gate_m, io::Positive());
  v.Integer("tight_min_inliers", o.tight_min_inliers, io::AtLeast(3));
  v.Number("wall_extent_margin_m", o.wall_extent_margin_m, io::NonNegative());
}

}  // namespace wallcal::calib
