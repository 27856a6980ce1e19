// SPDX-License-Identifier: Apache-2.0
#pragma once
// How much the mount moves when the session is split or resampled ("how do I know it is
// right?"): the Ceres adjustment re-run on
//  - the first and second half of the stations (by time), the odd and the even stations;
//  - `samples` bootstrap resamples of the stations (drawn with replacement; a station drawn m
//    times counts m times), warm-started from the full solution with few iterations.
// Stations are the GNSS segments (dwells, or time slices of moving data). Long sessions are
// thinned to at most kMaxRefitObservations observations per re-solve (every k-th scan, its
// weight ×k), which keeps the cost bounded; the station-level spread it measures is set by the
// GNSS and wall errors, not by the scan count.

#include <array>
#include <cstdint>
#include <vector>

#include <string>
#include "calib/observation.h"
#include "solvers/solver_options.h"
#include "solvers/mount_solver.h"

namespace wallcal::analysis {

// How much the mount moves when the session is split or resampled.
struct RepeatabilitySplit {
  std::string name;          // "first half", "second half", "odd stations", ...
  solvers::Mount mount;
  bool usable = false;
};
struct Repeatability {
  bool done = false;
  std::vector<RepeatabilitySplit> splits;
  int bootstrap_samples = 0;
  double bootstrap_sigma_x_m = 0.0, bootstrap_sigma_y_m = 0.0, bootstrap_sigma_yaw_rad = 0.0;
  double max_split_shift_x_m = 0.0, max_split_shift_y_m = 0.0, max_split_shift_yaw_rad = 0.0;
};



inline constexpr int kMaxRefitObservations = 3000;

// The observations a re-solve gets: every stride-th (at most kMaxRefitObservations), each to
// be weighted by the stride. stride 1: all of them.
struct ThinnedObservations {
  std::vector<calib::WallObservation> observations;
  double stride = 1.0;
};
ThinnedObservations ThinForRefits(const std::vector<calib::WallObservation>& observations);

// A split is usable when its re-solve converged and passes the solver's determination check
// (options.max_sigma_*): half the stations may see the wall from one side only. Bootstrap σ
// is the standard deviation of the resamples that converged and are determined (yaw wrapped
// about the full solution). Deterministic for a given `seed`. Never throws; with fewer than 4
// stations it is left not done. held_time_block: the full solution's clock (scanner offset,
// heading delay: MountEstimate::time_block_s), held in every re-solve; a half of the stations
// may not fix the drives' timing that the whole session does, and would turn the mount by
// yaw rate × its error. warm: the full solution's nuisance parameters
// (MountEstimate::solution_state), where every re-solve starts.
Repeatability AssessRepeatability(const std::vector<calib::WallObservation>& observations,
                                  const std::vector<calib::WallGeometry>& walls,
                                  const solvers::SolverOptions& options, const solvers::Mount& full,
                                  int samples, uint64_t seed = 2007,
                                  const std::array<double, 2>* held_time_block = nullptr,
                                  const solvers::WarmStart* warm = nullptr);

}  // namespace wallcal::analysis
