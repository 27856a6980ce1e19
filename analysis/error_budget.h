// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the mount's σ is made of: how much of the variance of x, y and yaw comes from each error
// source of the adjustment's error model. Method (docs/method.md, "Error budget"): the
// adjustment is linearised at the estimate and its mount covariance computed from the
// information matrix (nuisance parameters marginalised, solvers::RefitMount); then once more
// with one source made exact (its σ multiplied by 10⁻³); the variance that goes away is that
// source's share. The shares need not add up to the whole: the remainder is what the
// geometry of the session does with the sources together (reported as `other`).
// Sessions of more than kMaxRefitObservations observations are thinned for it as the
// repeatability's re-solves are (analysis/repeatability.h). The re-solves (one per source with
// something to make exact, and the whole) run over
// options.num_threads threads; the result does not depend on the count.

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/observation.h"
#include "solvers/solver_options.h"

namespace wallcal::analysis {

enum class ErrorSource {
  kSurvey,    // total-station points fitted to the walls
  kControl,   // the survey's tie to the GNSS frame through the control points
  kGnss,      // the RTK position error (white and time-correlated)
  kHeading,   // heading noise
  kScanner,   // the scanner's range noise (the line fits)
  kRover,     // rover points fitted to the walls (a GNSS-surveyed wall: no tie, no total station)
};
inline constexpr int kNumErrorSources = 6;
const char* ErrorSourceName(ErrorSource source);  // "survey points", "control points", ...
const char* ErrorSourceKey(ErrorSource source);   // "survey_points", "control_points", ...

struct ErrorBudget {
  bool done = false;
  Eigen::Vector3d total_variance = Eigen::Vector3d::Zero();  // x, y (m²), yaw (rad²), linearised
  // variance[source] for x, y, yaw: the part that goes away when that source is exact (≥ 0).
  std::array<Eigen::Vector3d, kNumErrorSources> variance{};
  // The source with the largest share of the axis' variance, per axis (x, y, yaw).
  std::array<ErrorSource, 3> dominant{ErrorSource::kScanner, ErrorSource::kScanner,
                                      ErrorSource::kScanner};
  // Share (0..1) of the axis' variance the largest source explains.
  Eigen::Vector3d dominant_share = Eigen::Vector3d::Zero();
};

// Never throws; done == false when the linearised problem cannot be formed.
ErrorBudget ComputeErrorBudget(const std::vector<calib::WallObservation>& observations,
                               const std::vector<calib::WallGeometry>& walls,
                               const solvers::SolverOptions& options, const calib::Mount& mount);

}  // namespace wallcal::analysis
