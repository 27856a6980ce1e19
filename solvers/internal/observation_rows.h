// SPDX-License-Identifier: Apache-2.0
#pragma once
// What BuildMountProblem makes of each observation, shared with ExtendMountProblem
// (problem_extension.h) so that observations added to a built problem get the very residual
// blocks and priors they would get in a problem built anew: the dwells' headings, the GNSS
// slices' σ and mean time, the Gauss–Markov correlation between slices, the residual's
// constants, and the grouping of scans into residual blocks.

#include <map>
#include <string>
#include <vector>

#include "calib/observation.h"
#include "solvers/mount_solver.h"
#include "solvers/solver_options.h"
#include "solvers/wall_line_cost.h"

namespace wallcal::solvers::internal {

// The heading a dwell's scans use, per station (pose.segment), over every observation whatever
// its weight (so that the bootstrap's resamples share it): the dwell's mean heading from the
// pose when the pose interpolator filled it, else the circular mean of the observations' yaws
// (each observation counted as one heading sample).
struct DwellHeading {
  double sin_sum = 0.0, cos_sum = 0.0, stamp_sum = 0.0;
  int count = 0;
  double pose_yaw_rad = 0.0, pose_mid_s = 0.0;
  int pose_samples = 0;
  double yaw_rad() const;  // the dwell's heading (rad)
  double mid_s() const;    // its time (s), for the drift
  int samples() const;     // heading samples averaged
};
// The dwells of the observations that use their dwell's heading (UsesDwellHeading).
std::map<int, DwellHeading> DwellHeadings(const std::vector<calib::WallObservation>& observations);

// A GNSS-error slice: its bias σ is the mean GST σ over its observations (when allowed and
// present), else the configured σ; its time is its observations' mean stamp.
struct SegmentSums {
  double gst_sum = 0.0;
  int gst_count = 0;
  double stamp_sum = 0.0;
  int count = 0;
  void Add(const calib::WallObservation& observation, const SolverOptions& options);
  double sigma_m(const SolverOptions& options) const;
  double mid_s() const { return stamp_sum / count; }
};

// The Gauss–Markov correlation ρ = exp(−Δt/τ) between two slices Δt apart (0 without a τ),
// capped so that a chain step's σ stays a usable weight.
double SliceCorrelation(double dt_s, const SolverOptions& options);

// The measurement (the residual's constants, W with √weight in it) of one observation.
// `dwells`: DwellHeadings of the problem's observations; reference_s: the drift's zero time.
// False, with *error naming the observation `index`, when its covariance is not positive
// definite.
bool MakeMeasurement(const calib::WallObservation& observation, size_t index,
                     const calib::WallGeometry& wall, const SolverOptions& options,
                     const Mount& lever_mount, double weight, double scans_per_fix,
                     const std::map<int, DwellHeading>& dwells, double reference_s,
                     WallLineMeasurement* measurement, std::string* error);

// The observations (indices into the blocks' vectors) that share their wall, bias and heading
// blocks, up to kScansPerResidualBlock in one group, in input order; weight 0 in none.
std::vector<std::vector<int>> ResidualGroups(const std::vector<double*>& wall_block,
                                             const std::vector<double*>& bias_block,
                                             const std::vector<double*>& heading_block,
                                             const std::vector<double>& weights);

}  // namespace wallcal::solvers::internal
