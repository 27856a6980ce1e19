// SPDX-License-Identifier: Apache-2.0
#pragma once
// Checks, before any solve, whether a set of wall observations can determine the mount at all.
// Both solvers run these same checks, so that they refuse the same data with the same words.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/observation.h"
#include "solvers/solver_options.h"

namespace wallcal::solvers {

struct ObservabilityReport {
  bool ok = false;
  std::string message;  // empty when ok; otherwise why the mount is not determined
  // false when no solve is possible at all (no observations, a bad wall index): --force cannot
  // help. The other failures (few observations or stations, narrow spread) can be forced.
  bool solvable = true;
  int num_observations = 0;
  int num_stations = 0;  // distinct pose.segment >= 0 (segment −1 is not counted as a station)
  // Vehicle-to-wall angles φ = atan2(n) − ψ (Barawid 2007, Eq. 8), taken as axes (modulo π, since
  // a normal and its opposite constrain the same mount component): the narrowest arc that
  // holds them all, [min, max] (rad), and its width.
  double angle_min_rad = 0.0;
  double angle_max_rad = 0.0;
  double angle_spread_rad = 0.0;
};

// Never throws. A wall_index outside `walls` makes the report not ok (a bug upstream, reported
// rather than crashed on). Checks, in this order: the number of observations against
// options.min_observations, the number of stations against options.min_stations, and the
// spread of φ against options.min_heading_spread_rad. A narrow spread leaves the mount
// component perpendicular to the mean wall normal (in vehicle coordinates) undetermined; the
// message names the mount axis (x forward or y lateral) closest to it.
ObservabilityReport CheckObservability(const std::vector<calib::WallObservation>& observations,
                                       const std::vector<calib::WallGeometry>& walls,
                                       const solvers::SolverOptions& options);

// The conditioning check on the mount's information matrix (nuisance parameters marginalised,
// see MountInformation in mount_problem.h). In units scaled by options.max_sigma_xy_m and
// max_sigma_yaw_rad, the weakest direction (smallest eigenvalue) must have σ ≤ 1. When it does
// not, `message` names that direction in words ("lateral offset y", "forward offset x", "yaw",
// or a combination "forward offset x with yaw"), its σ, the headings and vehicle-to-wall
// angles seen, and what to collect.
struct DeterminationReport {
  bool ok = false;
  std::string weak_direction;  // empty when ok
  std::string message;
  Eigen::Vector3d sigma = Eigen::Vector3d::Zero();  // per axis from the information (inf: none)
};
DeterminationReport CheckDetermination(const Eigen::Matrix3d& information,
                                       const std::vector<calib::WallObservation>& observations,
                                       const std::vector<calib::WallGeometry>& walls,
                                       const solvers::SolverOptions& options);

// Grid headings (clockwise from grid north, deg, [0, 360)) of the observations: the narrowest
// arc holding them all, as "85°–97°".
std::string HeadingArc(const std::vector<calib::WallObservation>& observations);

}  // namespace wallcal::solvers
