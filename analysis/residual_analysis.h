// SPDX-License-Identifier: Apache-2.0
#pragma once
// The residual analysis of an adjustment against surveyed surfaces applied to the mount adjustment: after the solve, the distance
// residuals (observed − predicted rho, metres) are examined for their robust spread, their
// outliers, and for trends against the quantities a systematic error would follow.
//
// Per observation (scanner frame, from the fitted wall line and its inliers):
//  - range: the middle of the inliers' range span (m), rho when unknown;
//  - incidence: the angle between that beam and the wall normal, acos(rho / range) (deg);
//  - bearing: the direction of the wall's foot point, theta (deg, scanner frame);
//  - heading: the vehicle's grid heading (deg, unwrapped about the mean);
//  - station: the rank of the observation's GNSS segment in time (0, 1, ...);
//  - time: seconds since the first observation.
// The trends are taken on the residuals with the station's estimated GNSS bias put back
// (r + n·b): a per-station bias parameter would otherwise soak up whatever differs between
// stations, e.g. a range scale error seen from stations at different distances.
// Each trend is a least-squares slope whose σ is computed with the observations clustered by
// station (scans of one station share their GNSS error, so they are not independent: treating
// them so would flag noise as a trend).

#include <vector>

#include <string>
#include "calib/observation.h"
#include "io/types.h"
#include "solvers/mount_solver.h"

namespace wallcal::analysis {

// Residuals examined after the solve (Hartzell, Glennie et al.'s residual analysis): robust spread, outliers,
// and trends against what a systematic error would show up in.
// What a trend is against: the beam's range, its incidence on the wall, its bearing in the
// scanner frame, the vehicle's grid heading, the station's rank, the time since the start.
enum class TrendAxis { kRange, kIncidence, kBearing, kHeading, kStation, kTime };
const char* TrendAxisName(TrendAxis axis);  // "range", "incidence", ... (offsets.yaml's keys)

struct ResidualTrend {
  TrendAxis against = TrendAxis::kRange;
  std::string unit;      // unit of the slope, e.g. "m/m", "m/deg", "m/station"
  double slope = 0.0;    // least-squares slope of the distance residual against that quantity
  double significance = 0.0;  // |slope| / σ(slope)
  bool flagged = false;
  std::string message;   // what a flagged trend suggests (e.g. "range scale error: check k")
};
struct ResidualAnalysis {
  bool done = false;
  double robust_sigma_m = 0.0;  // 1.4826 × median absolute deviation of the distance residuals
  double outlier_share = 0.0;   // share of observations beyond 2 robust σ (Hartzell, Glennie et al.: 2σ rule)
  std::vector<ResidualTrend> trends;
  std::vector<std::string> flags;  // human-readable summaries of the flagged trends
  bool range_model_estimated = false;  // k, b re-estimated jointly when ranges span enough
  double range_scale_k = 1.0, range_offset_b_m = 0.0;
  double sigma_range_scale_k = 0.0, sigma_range_offset_b_m = 0.0;
};



// Significance (|slope| / σ(slope)) from which a trend is flagged, provided it also moves the
// residuals by at least one robust σ over the observed span.
inline constexpr double kTrendFlagSignificance = 4.0;

// `estimate.residual_rho_m` must hold one residual per observation (same order); otherwise (or
// with fewer than 10 observations) the analysis is left not done. `preset` gives the range
// correction k the range trend is compared with. Never throws.
ResidualAnalysis AnalyseResiduals(const std::vector<calib::WallObservation>& observations,
                                  const std::vector<calib::WallGeometry>& walls,
                                  const solvers::MountEstimate& estimate,
                                  const io::ScannerPreset& preset);

}  // namespace wallcal::analysis
