#pragma once
// Seed 003's residual analysis applied to the mount adjustment: after the solve, the distance
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

#include "apps/pipeline.h"
#include "calib/observation.h"
#include "io/types.h"
#include "solvers/mount_solver.h"

namespace wallcal::app {

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

}  // namespace wallcal::app
