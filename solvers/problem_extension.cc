// SPDX-License-Identifier: Apache-2.0
// Observations added to a built mount problem (solvers/problem_extension.h).
#include "solvers/problem_extension.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "solvers/information.h"
#include "solvers/internal/observation_rows.h"
#include "solvers/normal_matrix.h"
#include "solvers/prior_cost.h"
#include "solvers/wall_slice_cost.h"

namespace wallcal::solvers {
namespace {

ceres::Problem::Options ExtensionProblemOptions() {
  ceres::Problem::Options options;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return options;
}

// The extension's free blocks of its own, in a fixed order: the slices' biases, then the
// heading offsets.
std::vector<double*> OwnBlocks(MountProblemExtension& extension) {
  std::vector<double*> blocks;
  for (auto& bias : extension.biases) blocks.push_back(bias.data());
  for (auto& offset : extension.heading_offsets) blocks.push_back(offset.data());
  std::vector<double*> free;
  for (double* block : blocks) {
    if (extension.problem.HasParameterBlock(block) &&
        !extension.problem.IsParameterBlockConstant(block)) {
      free.push_back(block);
    }
  }
  return free;
}

// A dense symmetric matrix and a sparse one scattered into it, summed, as a sparse matrix of
// size `size`: the dense one at the top left, the sparse one's row/column r at at[r].
Eigen::SparseMatrix<double> Sum(const Eigen::MatrixXd& dense,
                                const Eigen::SparseMatrix<double>& sparse,
                                const std::vector<int>& at, int size) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (int r = 0; r < dense.rows(); ++r) {
    for (int c = 0; c < dense.cols(); ++c) {
      if (dense(r, c) != 0.0) triplets.emplace_back(r, c, dense(r, c));
    }
  }
  for (int c = 0; c < sparse.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(sparse, c); it; ++it) {
      triplets.emplace_back(at[it.row()], at[it.col()], it.value());
    }
  }
  Eigen::SparseMatrix<double> sum(size, size);
  sum.setFromTriplets(triplets.begin(), triplets.end());
  return sum;
}

}  // namespace

MountProblemExtension::MountProblemExtension() : problem(ExtensionProblemOptions()) {}

std::unique_ptr<MountProblemExtension> ExtendMountProblem(
    MountProblem& base, const std::vector<calib::WallObservation>& extra,
    const std::vector<calib::WallGeometry>& walls, const SolverOptions& options,
    const Mount& lever_mount, const std::vector<double>& weights, ExtensionOutcome* outcome) {
  *outcome = ExtensionOutcome::kChangesBase;
  const auto weight_of = [&weights](size_t i) {
    return i < weights.size() ? std::max(0.0, weights[i]) : 1.0;
  };
  if (base.problem.NumResidualBlocks() == 0) return nullptr;
  // What would change the base's own blocks or priors if both sets were built together: a
  // moving scan (the clock block's estimation, the scans per GNSS fix), an observation
  // without a slice (white noise from the bias σ), a stamp before the base's first (the drift's
  // zero time), a station or slice the base has (their mean heading and time), a slice not
  // after the base's last (the chain's order), a wall the base does not use (the walls' joint
  // prior).
  const std::set<int> base_stations(base.heading_station_ids.begin(),
                                    base.heading_station_ids.end());
  std::map<int, internal::SegmentSums> sums;
  for (size_t i = 0; i < extra.size(); ++i) {
    const calib::WallObservation& observation = extra[i];
    if (!UsesDwellHeading(observation) || calib::GnssSegment(observation) < 0) return nullptr;
    if (observation.pose.stamp_s < base.heading_reference_s) return nullptr;
    if (base_stations.count(observation.pose.segment) > 0) return nullptr;
    if (observation.wall_index < 0 || observation.wall_index >= static_cast<int>(walls.size()) ||
        observation.wall_index >= static_cast<int>(base.wall_deltas.size())) {
      return nullptr;
    }
    if (!(weight_of(i) > 0.0)) continue;
    if (!base.problem.HasParameterBlock(base.wall_deltas[observation.wall_index].data())) {
      return nullptr;
    }
    sums[calib::GnssSegment(observation)].Add(observation, options);
  }
  const int last_base = base.segment_order.empty() ? -1 : base.segment_order.back();
  auto extension = std::make_unique<MountProblemExtension>();
  std::map<int, int> segment_index;
  for (const auto& [segment, entry] : sums) {
    if (std::binary_search(base.segment_ids.begin(), base.segment_ids.end(), segment)) {
      return nullptr;
    }
    if (last_base >= 0 && !(entry.mid_s() > base.segment_mid_s[last_base])) return nullptr;
    segment_index[segment] = static_cast<int>(extension->segment_ids.size());
    extension->segment_ids.push_back(segment);
    extension->bias_sigma_m.push_back(entry.sigma_m(options));
    extension->segment_mid_s.push_back(entry.mid_s());
  }
  extension->biases.assign(extension->segment_ids.size(), {0.0, 0.0});
  const std::map<int, internal::DwellHeading> dwells = internal::DwellHeadings(extra);
  std::map<int, int> heading_index;
  for (const auto& [station, entry] : dwells) {
    heading_index[station] = static_cast<int>(extension->heading_offsets.size());
    extension->heading_offsets.push_back({0.0});
    extension->heading_station_ids.push_back(station);
    extension->heading_offset_sigma_rad.push_back(options.heading_sigma_rad /
                                                  std::sqrt(std::max(1, entry.samples())));
  }

  // The residual blocks, as BuildMountProblem makes them (standing scans only: no scans per
  // GNSS fix).
  std::vector<double*> wall_block, bias_block, heading_block;
  std::vector<double> used_weights;
  extension->measurements.reserve(extra.size());
  for (size_t i = 0; i < extra.size(); ++i) {
    const calib::WallObservation& observation = extra[i];
    WallLineMeasurement m;
    *outcome = ExtensionOutcome::kNoNoiseModel;
    if (!internal::MakeMeasurement(observation, i, walls[observation.wall_index], options,
                                   lever_mount, weight_of(i), 1.0, dwells, base.heading_reference_s,
                                   &m, nullptr)) {
      return nullptr;
    }
    *outcome = ExtensionOutcome::kChangesBase;
    extension->measurements.push_back(m);
    used_weights.push_back(weight_of(i));
    wall_block.push_back(base.wall_deltas[observation.wall_index].data());
    const int slice = segment_index.count(calib::GnssSegment(observation)) > 0
                          ? segment_index.at(calib::GnssSegment(observation))
                          : -1;
    bias_block.push_back(slice >= 0 && extension->bias_sigma_m[slice] > 0.0
                             ? extension->biases[slice].data()
                             : extension->no_bias.data());
    const int station = heading_index.at(observation.pose.segment);
    heading_block.push_back(extension->heading_offset_sigma_rad[station] > 0.0
                                ? extension->heading_offsets[station].data()
                                : extension->no_heading_offset.data());
  }
  for (std::vector<int>& group :
       internal::ResidualGroups(wall_block, bias_block, heading_block, used_weights)) {
    const int first = group.front();
    extension->problem.AddResidualBlock(
        new WallSliceCost(extension->measurements, std::move(group), options.huber_scale), nullptr,
        base.mount.data(), wall_block[first], bias_block[first], base.time_offset.data(),
        heading_block[first], base.heading_drift.data());
  }

  // The GNSS-error chain goes on from the base's last slice (BuildMountProblem's chain over
  // both sets: the new slices come after every slice of the base).
  std::vector<int> order(extension->segment_ids.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::stable_sort(order.begin(), order.end(), [&extension](int a, int b) {
    return extension->segment_mid_s[a] < extension->segment_mid_s[b];
  });
  double* previous_block = nullptr;
  double previous_sigma_m = 0.0;
  double previous_mid_s = 0.0;
  if (last_base >= 0) {
    previous_mid_s = base.segment_mid_s[last_base];
    if (base.bias_sigma_m[last_base] > 0.0) {
      previous_block = base.biases[last_base].data();
      previous_sigma_m = base.bias_sigma_m[last_base];
    }
  }
  for (size_t k = 0; k < order.size(); ++k) {
    const int index = order[k];
    const double sigma_m = extension->bias_sigma_m[index];
    const double rho =
        (k == 0 && last_base < 0)
            ? 0.0
            : internal::SliceCorrelation(extension->segment_mid_s[index] - previous_mid_s, options);
    previous_mid_s = extension->segment_mid_s[index];
    if (!(sigma_m > 0.0)) {
      previous_block = nullptr;
      continue;
    }
    double* block = extension->biases[index].data();
    if (previous_block == nullptr || !(rho > 0.0)) {
      extension->problem.AddResidualBlock(
          GaussianPriorCost::Create(Eigen::Vector2d(sigma_m, sigma_m)), nullptr, block);
    } else {
      extension->problem.AddResidualBlock(
          GaussMarkovStepCost::Create(rho * sigma_m / previous_sigma_m,
                                      sigma_m * std::sqrt(1.0 - rho * rho)),
          nullptr, previous_block, block);
    }
    previous_block = block;
    previous_sigma_m = sigma_m;
  }
  for (size_t k = 0; k < extension->heading_offsets.size(); ++k) {
    double* block = extension->heading_offsets[k].data();
    if (!(extension->heading_offset_sigma_rad[k] > 0.0) ||
        !extension->problem.HasParameterBlock(block)) {
      continue;
    }
    extension->problem.AddResidualBlock(
        ScalarPriorCost::Create(extension->heading_offset_sigma_rad[k]), nullptr, block);
  }
  for (double* block : {extension->no_bias.data(), extension->no_heading_offset.data()}) {
    if (extension->problem.HasParameterBlock(block)) {
      extension->problem.SetParameterBlockConstant(block);
    }
  }
  // The shared blocks are held and shaped as in the base (the manifolds are the base's, not
  // owned here: Ceres takes a mutable pointer but a manifold is not changed by use).
  std::vector<double*> shared = {base.mount.data(), base.time_offset.data(),
                                 base.heading_drift.data()};
  for (auto& wall : base.wall_deltas) shared.push_back(wall.data());
  if (last_base >= 0) shared.push_back(base.biases[last_base].data());
  for (double* block : shared) {
    if (!extension->problem.HasParameterBlock(block)) continue;
    if (base.problem.IsParameterBlockConstant(block)) {
      extension->problem.SetParameterBlockConstant(block);
    } else if (const ceres::Manifold* manifold = base.problem.GetManifold(block)) {
      extension->problem.SetManifold(block, const_cast<ceres::Manifold*>(manifold));
    }
  }
  *outcome = ExtensionOutcome::kExtended;
  return extension;
}

void ApplyWarmStart(const WarmStart& warm, MountProblemExtension* extension) {
  for (size_t k = 0; k < extension->segment_ids.size(); ++k) {
    const auto found = warm.biases.find(extension->segment_ids[k]);
    if (found != warm.biases.end()) extension->biases[k] = found->second;
  }
  for (size_t k = 0; k < extension->heading_station_ids.size(); ++k) {
    const auto found = warm.heading_offsets.find(extension->heading_station_ids[k]);
    if (found != warm.heading_offsets.end()) extension->heading_offsets[k][0] = found->second;
  }
}

SharedInformation MarginalOntoShared(MountProblem& base, int threads) {
  SharedInformation shared;
  std::vector<double*> candidates = {base.mount.data()};
  for (auto& wall : base.wall_deltas) candidates.push_back(wall.data());
  candidates.push_back(base.time_offset.data());
  candidates.push_back(base.heading_drift.data());
  if (!base.segment_order.empty())
    candidates.push_back(base.biases[base.segment_order.back()].data());
  int size = 0;
  for (double* block : candidates) {
    if (!base.problem.HasParameterBlock(block) || base.problem.IsParameterBlockConstant(block)) {
      continue;
    }
    shared.blocks.push_back(block);
    shared.offsets.push_back(size);
    size += base.problem.ParameterBlockTangentSize(block);
  }
  if (shared.blocks.empty() || shared.blocks.front() != base.mount.data()) return shared;
  shared.information = MarginalInformation(base, shared.blocks, threads);
  if (shared.information.rows() != size) shared.information.resize(0, 0);
  return shared;
}

Eigen::Matrix3d MountInformation(const SharedInformation& shared) {
  if (shared.information.rows() < 3) return Eigen::Matrix3d::Zero();
  const Eigen::MatrixXd information =
      SchurComplement(Sum(shared.information, Eigen::SparseMatrix<double>(), {},
                          static_cast<int>(shared.information.rows())),
                      3);
  if (information.rows() != 3) return Eigen::Matrix3d::Zero();
  return information;
}

Eigen::Matrix3d ExtendedMountInformation(const SharedInformation& shared,
                                         MountProblemExtension& extension) {
  if (shared.information.rows() < 3) return Eigen::Matrix3d::Zero();
  // The extension's columns: the shared blocks it uses (free), then its own. Each column's
  // place in the sum: the shared block's rows, or after every shared row.
  std::vector<double*> columns;
  std::vector<int> at;
  for (size_t b = 0; b < shared.blocks.size(); ++b) {
    double* block = shared.blocks[b];
    if (!extension.problem.HasParameterBlock(block) ||
        extension.problem.IsParameterBlockConstant(block)) {
      continue;
    }
    columns.push_back(block);
    for (int c = 0; c < extension.problem.ParameterBlockTangentSize(block); ++c) {
      at.push_back(shared.offsets[b] + c);
    }
  }
  int size = static_cast<int>(shared.information.rows());
  for (double* block : OwnBlocks(extension)) {
    columns.push_back(block);
    for (int c = 0; c < extension.problem.ParameterBlockTangentSize(block); ++c)
      at.push_back(size++);
  }
  // A block of the extension that is neither shared nor its own would be a column lost.
  std::vector<double*> used;
  extension.problem.GetParameterBlocks(&used);
  for (double* block : used) {
    if (!extension.problem.IsParameterBlockConstant(block) &&
        std::find(columns.begin(), columns.end(), block) == columns.end()) {
      return Eigen::Matrix3d::Zero();
    }
  }
  Eigen::SparseMatrix<double> normal;
  if (!ProblemNormalMatrix(extension.problem, columns, 1, &normal)) return Eigen::Matrix3d::Zero();
  const Eigen::MatrixXd information = SchurComplement(Sum(shared.information, normal, at, size), 3);
  if (information.rows() != 3) return Eigen::Matrix3d::Zero();
  return information;
}

}  // namespace wallcal::solvers
