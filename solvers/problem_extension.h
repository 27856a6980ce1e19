// SPDX-License-Identifier: Apache-2.0
#pragma once
// Observations added to a built mount problem without building it anew, for predictions that
// try many small additions to one large set (the guide's candidate stops on an hour's
// evidence). ExtendMountProblem makes the residual blocks and priors BuildMountProblem would
// add for the new observations (their GNSS slices chained on from the base's last, their
// dwells' heading offsets) in a problem of their own that shares the base's mount, wall, clock
// and drift blocks. MarginalOntoShared marginalises the base's information once onto the
// blocks an extension can share (a Schur complement: the base's GNSS slices, heading offsets
// and every other nuisance eliminated); the mount's information of base + extension is then
// that k×k matrix plus the extension's own normal matrix, its own blocks and the shared
// nuisance eliminated (ExtendedMountInformation). It equals MountInformation of the problem
// built from both observation sets, up to rounding, at a cost of the extension's size.

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "calib/observation.h"
#include "solvers/mount_problem.h"
#include "solvers/solver_options.h"

namespace wallcal::solvers {

// What ExtendMountProblem made of the observations.
enum class ExtensionOutcome {
  kExtended,
  // The observations would change what the base problem holds (a GNSS slice, station or wall
  // the base has or lacks, a slice earlier than the base's last, a moving scan, a stamp before
  // the base's first): build the problem from both sets instead.
  kChangesBase,
  kNoNoiseModel,  // an observation's covariance is not positive definite
};

// The new observations' blocks and residuals. Not copyable or movable (Ceres holds the
// addresses). The shared blocks are the base's: the base must outlive the extension and keep
// its values while the extension is evaluated.
struct MountProblemExtension {
  MountProblemExtension();
  MountProblemExtension(const MountProblemExtension&) = delete;
  MountProblemExtension& operator=(const MountProblemExtension&) = delete;

  // The new GNSS slices (ascending ids), their bias [east_m, north_m] and σ (m), mean stamps.
  std::vector<int> segment_ids;
  std::vector<std::array<double, 2>> biases;
  std::vector<double> bias_sigma_m;
  std::vector<double> segment_mid_s;
  // The new stations' heading offsets (rad), their prior σ and station ids.
  std::vector<std::array<double, 1>> heading_offsets;
  std::vector<double> heading_offset_sigma_rad;
  std::vector<int> heading_station_ids;
  std::array<double, 2> no_bias{};
  std::array<double, 1> no_heading_offset{};
  std::vector<WallLineMeasurement> measurements;
  // Declared last so that it goes first. It does not own the manifolds (they are the base's).
  ceres::Problem problem;
};

// The blocks of `extra` (weights as BuildMountProblem's, empty: 1 each) on top of `base`, built
// by BuildMountProblem from other observations with the same walls, options and lever mount.
// nullptr, with *outcome saying why, when the extension is not the difference between the
// problem of both sets and the base's.
std::unique_ptr<MountProblemExtension> ExtendMountProblem(
    MountProblem& base, const std::vector<calib::WallObservation>& extra,
    const std::vector<calib::WallGeometry>& walls, const SolverOptions& options,
    const Mount& lever_mount, const std::vector<double>& weights, ExtensionOutcome* outcome);

// Sets the extension's own blocks from `warm` where it has them (by slice and station id).
void ApplyWarmStart(const WarmStart& warm, MountProblemExtension* extension);

// The base's information marginalised onto the blocks an extension can share with it, in this
// order: the mount (x, y, yaw), the walls in the problem, the clock block and the drift rate
// where free, the last GNSS slice of the chain (each in its tangent space; units as
// MarginalInformation's). information empty when it cannot be computed.
struct SharedInformation {
  std::vector<double*> blocks;
  std::vector<int> offsets;  // each block's first row
  Eigen::MatrixXd information;
};
SharedInformation MarginalOntoShared(MountProblem& base, int threads = 1);

// The mount's information of the base alone (MountInformation of the base, up to rounding).
// Zero when `shared` is empty or the nuisance cannot be factored.
Eigen::Matrix3d MountInformation(const SharedInformation& shared);

// The mount's information of the base and the extension together. Zero on failure.
Eigen::Matrix3d ExtendedMountInformation(const SharedInformation& shared,
                                         MountProblemExtension& extension);

}  // namespace wallcal::solvers
