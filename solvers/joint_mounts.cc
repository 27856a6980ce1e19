// SPDX-License-Identifier: Apache-2.0
// The joint adjustment of several scanners (solvers/joint_mounts.h). Each scanner's part is
// built by BuildMountProblem as for one scanner (its noise model, its dwell headings, its time
// prior); the joint problem then takes every scanner's observation rows with their blocks
// mapped onto one set of shared blocks, and states each shared prior once: the walls' joint
// prior, one Gauss–Markov chain over the union of the GNSS-error slices, one prior per dwell's
// heading offset, one drift prior. The white noise of each GNSS fix and heading sample the
// scans were interpolated from is a parameter of its own (EpochNoiseCost, with the
// interpolation's weights), not part of each scan's covariance: two scanners' scans of one
// instant share it, and it cancels in the transform between the scanners.

#include "solvers/joint_mounts.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <utility>

#include "common/angles.h"
#include "solvers/epoch_noise_cost.h"
#include "solvers/information.h"
#include "solvers/mount_problem.h"
#include "solvers/prior_cost.h"
#include "solvers/wall_slice_cost.h"
#include "solvers/unit_range_cost.h"
#include "solvers/unit_scale_reference.h"

namespace wallcal::solvers {
namespace {

// As in mount_problem.cc: slices closer in time than ~τ/10⁵ are one GNSS error, and a residual
// block holds at most this many scans.
constexpr double kMaxSegmentCorrelation = 0.99999;
constexpr size_t kScansPerResidualBlock = 32;
// A moving scan's reference rho for its unit's scale averages the scans within this of its
// stamp (solvers/unit_scale_reference.h): the RTK error wanders σ_b √(2Δ/τ) over it, 1.9 mm at
// σ_b 15 mm and τ 60 s, which a δk of 0.005 turns into 0.01 mm.
constexpr double kScaleReferenceWindowS = 0.5;

// Everything the joint problem points into. Destroyed in reverse order: the joint problem
// (which owns only the costs it made) first, the scanners' own problems (whose measurement
// vectors the joint costs read) last.
struct JointProblem {
  std::vector<std::unique_ptr<MountProblem>> parts;
  std::vector<std::array<double, 3>> mounts;
  std::vector<std::array<double, 2>> times;
  // Each unit's range model [δb_m, δk] (solvers/unit_range_cost.h); used by a scanner with a σ.
  std::vector<std::array<double, 2>> units;
  std::vector<std::array<double, 2>> walls;
  std::map<int, std::array<double, 2>> biases;     // by GNSS slice id
  std::map<int, std::array<double, 1>> headings;   // by station id
  std::array<double, 1> drift{};
  std::array<double, 1> no_heading{};
  std::array<double, 2> no_bias{};
  // The shared white noise of the GNSS fixes [east_m, north_m] and heading samples [rad] by
  // their index in the streams (every scanner's poses come from the session's one GNSS and one
  // heading stream; solvers/epoch_noise_cost.h), and the zero stand-ins for the samples a scan
  // does not share or gives no weight (four of each: Ceres takes a block once per residual
  // block).
  std::map<int, std::array<double, 2>> fix_noise;
  std::map<int, std::array<double, 1>> heading_noise;
  std::array<std::array<double, 2>, 4> no_fix_noise{};
  std::array<std::array<double, 1>, 4> no_heading_noise{};
  MountProblem joint;  // only its ceres::Problem is used (for solvers/information.h)
};

// Two scanners' heading delays are one: their totals δh + H are equal, with δh the second entry
// of each time block [dt, δh] (s) and H the delay its poses already carry (s):
//   r = (δh_b − δh_a − (H_a − H_b)) / σ_tie      (dimensionless; offset_s = H_a − H_b)
// σ_tie (0.1 ms) is far below any delay's σ (milliseconds): to the solve and the covariance the
// two are one.
class HeadingDelayTieCost {
 public:
  explicit HeadingDelayTieCost(double offset_s) : offset_s_(offset_s) {}
  template <typename T>
  bool operator()(const T* const holder, const T* const tied, T* residual) const {
    residual[0] = (tied[1] - holder[1] - offset_s_) / kTieSigmaS;
    return true;
  }
  static ceres::CostFunction* Create(double offset_s) {
    return new ceres::AutoDiffCostFunction<HeadingDelayTieCost, 1, 2, 2>(
        new HeadingDelayTieCost(offset_s));
  }

 private:
  static constexpr double kTieSigmaS = 1e-4;
  double offset_s_;
};

void AddWallPrior(const std::vector<calib::WallGeometry>& walls, const std::set<int>& used,
                  JointProblem* jp) {
  ceres::Problem& problem = jp->joint.problem;
  std::vector<int> prior_walls;
  std::vector<std::pair<int, int>> coordinates;
  for (int w : used) {
    double* block = jp->walls[w].data();
    const bool offset_free = walls[w].sigma_offset_m > 0.0;
    const bool angle_free = walls[w].sigma_angle_rad > 0.0;
    if (!offset_free && !angle_free) {
      problem.SetParameterBlockConstant(block);
      continue;
    }
    if (!offset_free || !angle_free) {
      problem.SetManifold(block, new ceres::SubsetManifold(2, {offset_free ? 1 : 0}));
    }
    const int index = static_cast<int>(prior_walls.size());
    prior_walls.push_back(w);
    if (offset_free) coordinates.emplace_back(index, 0);
    if (angle_free) coordinates.emplace_back(index, 1);
  }
  if (coordinates.empty()) return;
  const Eigen::MatrixXd full = WallPriorCovariance(walls, prior_walls);
  const int k = static_cast<int>(coordinates.size());
  Eigen::MatrixXd covariance(k, k);
  for (int r = 0; r < k; ++r) {
    for (int c = 0; c < k; ++c) {
      covariance(r, c) = full(2 * coordinates[r].first + coordinates[r].second,
                              2 * coordinates[c].first + coordinates[c].second);
    }
  }
  Eigen::LLT<Eigen::MatrixXd> llt(covariance);
  if (llt.info() != Eigen::Success || !(llt.matrixLLT().diagonal().minCoeff() > 0.0)) {
    covariance = Eigen::MatrixXd(covariance.diagonal().asDiagonal());
    llt.compute(covariance);
  }
  const Eigen::MatrixXd whitening = llt.matrixL().solve(Eigen::MatrixXd::Identity(k, k));
  std::vector<double*> blocks;
  for (int w : prior_walls) blocks.push_back(jp->walls[w].data());
  problem.AddResidualBlock(
      new JointPriorCost(whitening, coordinates, std::vector<int>(blocks.size(), 2)), nullptr,
      blocks);
}

// One Gauss–Markov chain over the union of every scanner's GNSS-error slices (mount_problem.cc
// states it per scanner): the slices are one time grid of the one GNSS stream.
void AddBiasChain(const SolverOptions& options, JointProblem* jp) {
  struct Slice {
    double sigma_m = 0.0;
    double mid_sum_s = 0.0;
    int parts = 0;
  };
  std::map<int, Slice> slices;
  for (const auto& part : jp->parts) {
    for (size_t k = 0; k < part->segment_ids.size(); ++k) {
      Slice& slice = slices[part->segment_ids[k]];
      slice.sigma_m = std::max(slice.sigma_m, part->bias_sigma_m[k]);
      slice.mid_sum_s += part->segment_mid_s[k];
      slice.parts += 1;
    }
  }
  std::vector<std::pair<double, int>> order;  // (mid time, slice id)
  for (const auto& [id, slice] : slices) order.emplace_back(slice.mid_sum_s / slice.parts, id);
  std::stable_sort(order.begin(), order.end());
  ceres::Problem& problem = jp->joint.problem;
  int previous = -1;
  double previous_mid_s = 0.0;
  for (const auto& [mid_s, id] : order) {
    const double sigma_m = slices[id].sigma_m;
    double* block = jp->biases[id].data();
    if (!(sigma_m > 0.0) || !problem.HasParameterBlock(block)) {
      previous = -1;
      continue;
    }
    const double rho =
        previous >= 0 && options.gnss_bias_tau_s > 0.0
            ? std::min(kMaxSegmentCorrelation,
                       std::exp(-std::max(0.0, mid_s - previous_mid_s) / options.gnss_bias_tau_s))
            : 0.0;
    if (previous < 0 || !(rho > 0.0)) {
      problem.AddResidualBlock(GaussianPriorCost::Create(Eigen::Vector2d(sigma_m, sigma_m)),
                               nullptr, block);
    } else {
      const double a = rho * sigma_m / slices[previous].sigma_m;
      problem.AddResidualBlock(GaussMarkovStepCost::Create(a, sigma_m * std::sqrt(1.0 - rho * rho)),
                               nullptr, jp->biases[previous].data(), block);
    }
    previous = id;
    previous_mid_s = mid_s;
  }
}

// Which white noise the joint problem carries as parameters shared by the scanners for this
// observation. A standing scan: the GNSS white noise of its two fixes (its position is their
// linear interpolation at its stamp; its heading is the dwell's, whose error is the dwell's
// offset). A moving scan: the white noise of its fixes and heading samples, with the weights of
// the cubics it was interpolated with, when its pose is at its estimated scan time
// (pose.clock_shift_s != 0: moved there by the clock rounds, or by the joint adjustment's
// caller, pipeline/multi_scanner.cc). Every scanner's scans of one instant are then
// interpolated at that instant, from the same samples with the same weights. A moving pose
// left at its stamp, moved to the scan's time by v·dt within the adjustment, is interpolated at
// a phase of the GNSS period that differs from scanner to scanner (their logger latencies
// differ, 20 and 50 ms: phases 0.2 and 0.5 of one fix interval): the two scanners' poses of one
// instant are then different combinations of the same fixes, their difference seems to tell
// each fix's white error apart to the line fits' σ, and the model is not that exact (v·dt
// misses the path's curvature over the latency). Such a scan keeps the white noise in its
// covariance, as one scanner has it.
SharedWhiteNoise SharedNoiseOf(const calib::WallObservation& observation,
                               const SolverOptions& options) {
  const calib::VehiclePose& pose = observation.pose;
  const bool standing = UsesDwellHeading(observation);
  const bool at_scan_time = pose.clock_shift_s != 0.0;
  SharedWhiteNoise shared;
  shared.gnss_fixes =
      options.gnss_white_sigma_m > 0.0 && pose.gnss_fix >= 0 && (standing || at_scan_time);
  shared.heading_samples =
      options.heading_sigma_rad > 0.0 && pose.heading_sample >= 0 && !standing && at_scan_time;
  return shared;
}

// Scanner s's observations on the joint blocks. Scans with shared white noise: one residual
// block each (EpochNoiseCost), their W made again without that noise; the others grouped as
// BuildMountProblem groups them. Returns the walls they use.
std::set<int> AddObservations(size_t s, const ScannerObservations& scanner,
                              const std::vector<calib::WallGeometry>& walls,
                              const SolverOptions& options, JointProblem* jp) {
  MountProblem& part = *jp->parts[s];
  const std::vector<calib::WallObservation>& observations = *scanner.observations;
  std::map<const double*, double*> joint_block;
  joint_block[part.no_bias.data()] = jp->no_bias.data();
  joint_block[part.no_heading_offset.data()] = jp->no_heading.data();
  for (size_t w = 0; w < part.wall_deltas.size(); ++w) {
    joint_block[part.wall_deltas[w].data()] = jp->walls[w].data();
  }
  for (size_t k = 0; k < part.segment_ids.size(); ++k) {
    joint_block[part.biases[k].data()] = jp->biases[part.segment_ids[k]].data();
  }
  for (size_t k = 0; k < part.heading_station_ids.size(); ++k) {
    joint_block[part.heading_offsets[k].data()] =
        jp->headings[part.heading_station_ids[k]].data();
  }
  const double scans_per_fix = MovingScansPerGnssFix(observations);
  // With its unit's range model estimated, every scan is a residual block of its own: the
  // model moves each scan's line by its own gain.
  const bool unit = scanner.range_offset_sigma_m > 0.0 || scanner.range_scale_sigma > 0.0;
  const size_t scans_per_block = unit ? 1 : kScansPerResidualBlock;
  const std::vector<double> scale_rho =
      unit ? UnitScaleReferences(observations, part.measurements, walls, scanner.initial,
                                 kScaleReferenceWindowS)
           : std::vector<double>();
  const auto add = [&](ceres::CostFunction* cost, std::vector<double*> blocks, size_t i) {
    if (unit) {
      cost = new UnitRangeCost(std::unique_ptr<ceres::CostFunction>(cost),
                               part.measurements[i].sign, observations[i].drho_drange_offset,
                               observations[i].dtheta_drange_offset_per_m, scale_rho[i]);
      blocks.push_back(jp->units[s].data());
    }
    jp->joint.problem.AddResidualBlock(cost, nullptr, blocks);
  };
  std::set<int> walls_used;
  std::map<std::array<const double*, 3>, size_t> open_group;
  std::vector<std::vector<int>> groups;
  for (size_t i = 0; i < part.measurements.size(); ++i) {
    if (!(part.weights[i] > 0.0)) continue;
    const calib::WallObservation& observation = observations[i];
    walls_used.insert(observation.wall_index);
    const SharedWhiteNoise shared = SharedNoiseOf(observation, options);
    if (!shared.gnss_fixes && !shared.heading_samples) {
      const std::array<const double*, 3> key = {part.wall_block[i], part.bias_block[i],
                                                part.heading_block[i]};
      auto found = open_group.find(key);
      if (found == open_group.end() || groups[found->second].size() >= scans_per_block) {
        found = open_group.insert_or_assign(key, groups.size()).first;
        groups.emplace_back();
      }
      groups[found->second].push_back(static_cast<int>(i));
      continue;
    }
    // BuildMountProblem checked this covariance with the white noise in; without it, it is the
    // line fit's plus what the pose keeps, positive definite where that was.
    const Eigen::Matrix2d covariance = ObservationCovariance(
        observation, walls[observation.wall_index], options, scanner.initial,
        PoseBiasSigma(observation.pose, options), scans_per_fix, shared);
    const Eigen::LLT<Eigen::Matrix2d> llt(covariance);
    if (llt.info() == Eigen::Success && llt.matrixLLT().diagonal().minCoeff() > 0.0) {
      part.measurements[i].sqrt_information =
          std::sqrt(part.weights[i]) *
          Eigen::Matrix2d(llt.matrixL().solve(Eigen::Matrix2d::Identity()));
    }
    // The samples k − 1 .. k + 2 of each stream with a weight in this scan's pose; the others
    // (and a stream not shared) take the zero stand-ins.
    const calib::VehiclePose& pose = observation.pose;
    std::array<double, 4> fix_weights{}, sample_weights{};
    std::vector<double*> blocks = {jp->mounts[s].data(), joint_block.at(part.wall_block[i]),
                                   joint_block.at(part.bias_block[i]), jp->times[s].data(),
                                   joint_block.at(part.heading_block[i]), jp->drift.data()};
    for (int j = 0; j < 4; ++j) {
      const bool used = shared.gnss_fixes && pose.gnss_fix_weights[j] != 0.0;
      if (used) fix_weights[j] = pose.gnss_fix_weights[j];
      blocks.push_back(used ? jp->fix_noise[pose.gnss_fix - 1 + j].data()
                            : jp->no_fix_noise[j].data());
    }
    for (int j = 0; j < 4; ++j) {
      const bool used = shared.heading_samples && pose.heading_sample_weights[j] != 0.0;
      if (used) sample_weights[j] = pose.heading_sample_weights[j];
      blocks.push_back(used ? jp->heading_noise[pose.heading_sample - 1 + j].data()
                            : jp->no_heading_noise[j].data());
    }
    auto scan = std::make_unique<WallSliceCost>(
        part.measurements, std::vector<int>{static_cast<int>(i)}, options.huber_scale);
    add(new EpochNoiseCost(std::move(scan), fix_weights, sample_weights), blocks, i);
  }
  for (std::vector<int>& group : groups) {
    const int first = group.front();
    std::vector<double*> blocks = {jp->mounts[s].data(), joint_block.at(part.wall_block[first]),
                                   joint_block.at(part.bias_block[first]), jp->times[s].data(),
                                   joint_block.at(part.heading_block[first]), jp->drift.data()};
    add(new WallSliceCost(part.measurements, std::move(group), options.huber_scale),
        std::move(blocks), static_cast<size_t>(first));
  }
  return walls_used;
}

// The white noise of every GNSS fix and heading sample a scan shares: a zero-mean prior of the
// options' σ on each (the noise ObservationCovariance otherwise puts in every scan's
// covariance); the stand-ins for scans that share none held at 0.
void AddEpochNoisePriors(const SolverOptions& options, JointProblem* jp) {
  ceres::Problem& problem = jp->joint.problem;
  for (auto& [fix, noise] : jp->fix_noise) {
    problem.AddResidualBlock(
        GaussianPriorCost::Create(Eigen::Vector2d::Constant(options.gnss_white_sigma_m)), nullptr,
        noise.data());
  }
  for (auto& [sample, noise] : jp->heading_noise) {
    problem.AddResidualBlock(ScalarPriorCost::Create(options.heading_sigma_rad), nullptr,
                             noise.data());
  }
  for (auto& block : jp->no_fix_noise) {
    if (problem.HasParameterBlock(block.data())) problem.SetParameterBlockConstant(block.data());
  }
  for (auto& block : jp->no_heading_noise) {
    if (problem.HasParameterBlock(block.data())) problem.SetParameterBlockConstant(block.data());
  }
}

// Scanner s's time block as its own problem has it: its prior (centred on what its poses
// already carry), or held constant. The heading delay is one for the session (one heading
// stream, its delay after the GNSS epochs): the first scanner that estimates it states its
// prior; each later one's total delay (what its poses carry plus its block's) is tied to that
// one's (HeadingDelayTieCost) and its own block has no delay prior, so the prior counts once.
// Returns the scanner whose prior holds the delay (-1 when none estimates it yet).
int AddTimeBlock(size_t s, const ScannerObservations& scanner, const SolverOptions& options,
                 int delay_holder, const std::vector<ScannerObservations>& scanners,
                 JointProblem* jp) {
  const MountProblem& part = *jp->parts[s];
  ceres::Problem& problem = jp->joint.problem;
  double* block = jp->times[s].data();
  if (!problem.HasParameterBlock(block)) return delay_holder;
  if (!part.time_offset_estimated) {
    problem.SetParameterBlockConstant(block);
    return delay_holder;
  }
  const calib::VehiclePose& carried = scanner.observations->front().pose;
  const bool delay = part.heading_delay_estimated;
  const bool tied = delay && delay_holder >= 0;
  // A tied block's delay has no prior of its own: a σ so wide it adds no information.
  constexpr double kNoPriorS = 1e3;
  problem.AddResidualBlock(
      GaussianPriorCost::Create(
          Eigen::Vector2d(options.time_offset_sigma_s,
                          delay ? (tied ? kNoPriorS : options.heading_delay_sigma_s) : 1.0),
          Eigen::Vector2d(-carried.clock_shift_s, delay ? -carried.heading_shift_s : 0.0)),
      nullptr, block);
  if (!delay) {
    problem.SetManifold(block, new ceres::SubsetManifold(2, {1}));
    return delay_holder;
  }
  if (!tied) return static_cast<int>(s);
  const double holder_shift_s = scanners[delay_holder].observations->front().pose.heading_shift_s;
  problem.AddResidualBlock(
      HeadingDelayTieCost::Create(holder_shift_s - carried.heading_shift_s), nullptr,
      jp->times[delay_holder].data(), block);
  return delay_holder;
}

// Each unit's range model: a zero-mean prior of its preset's σ on the offset and the scale; a
// term with σ 0 held at 0 (both: the block is not in the problem).
void AddUnitPriors(const std::vector<ScannerObservations>& scanners, JointProblem* jp) {
  ceres::Problem& problem = jp->joint.problem;
  for (size_t s = 0; s < scanners.size(); ++s) {
    double* block = jp->units[s].data();
    if (!problem.HasParameterBlock(block)) continue;
    const bool offset = scanners[s].range_offset_sigma_m > 0.0;
    const bool scale = scanners[s].range_scale_sigma > 0.0;
    problem.AddResidualBlock(
        GaussianPriorCost::Create(Eigen::Vector2d(offset ? scanners[s].range_offset_sigma_m : 1.0,
                                                  scale ? scanners[s].range_scale_sigma : 1.0)),
        nullptr, block);
    if (!offset || !scale) problem.SetManifold(block, new ceres::SubsetManifold(2, {offset ? 1 : 0}));
  }
}

}  // namespace

JointMountEstimate SolveJointMounts(const std::vector<ScannerObservations>& scanners,
                                    const std::vector<calib::WallGeometry>& walls,
                                    const SolverOptions& options) {
  JointMountEstimate estimate;
  const size_t n = scanners.size();
  auto jp = std::make_unique<JointProblem>();
  jp->mounts.resize(n);
  jp->times.assign(n, {0.0, 0.0});
  jp->units.assign(n, {0.0, 0.0});
  jp->walls.assign(walls.size(), {0.0, 0.0});
  // The drift's reference time: the earliest observation of any scanner (each part counts its
  // drift times from its own earliest; they are moved onto the joint reference below).
  double reference_s = std::numeric_limits<double>::infinity();
  for (size_t s = 0; s < n; ++s) {
    const ScannerObservations& scanner = scanners[s];
    if (scanner.observations == nullptr || scanner.observations->empty()) {
      estimate.message = "scanner '" + scanner.id + "' has no wall observation";
      return estimate;
    }
    std::string error;
    std::unique_ptr<MountProblem> part = BuildMountProblem(
        *scanner.observations, walls, options, scanner.initial, scanner.initial, &error);
    if (part == nullptr) {
      estimate.message = "scanner '" + scanner.id + "': " + error;
      return estimate;
    }
    if (scanner.warm != nullptr) ApplyWarmStart(*scanner.warm, part.get());
    reference_s = std::min(reference_s, part->heading_reference_s);
    jp->mounts[s] = {scanner.initial.x_m, scanner.initial.y_m, scanner.initial.yaw_rad};
    jp->times[s] = part->time_offset;
    jp->parts.push_back(std::move(part));
  }
  // Shared blocks start where the first scanner's own adjustment ended.
  const MountProblem& first = *jp->parts.front();
  for (size_t w = 0; w < walls.size(); ++w) jp->walls[w] = first.wall_deltas[w];
  jp->drift = first.heading_drift;
  for (const auto& part : jp->parts) {
    for (auto& m : part->measurements) m.drift_time_s += part->heading_reference_s - reference_s;
    for (size_t k = 0; k < part->segment_ids.size(); ++k) {
      jp->biases.emplace(part->segment_ids[k], part->biases[k]);
    }
    for (size_t k = 0; k < part->heading_station_ids.size(); ++k) {
      jp->headings.emplace(part->heading_station_ids[k], part->heading_offsets[k]);
    }
  }

  std::set<int> walls_used;
  int delay_holder = -1;
  for (size_t s = 0; s < n; ++s) {
    const std::set<int> used = AddObservations(s, scanners[s], walls, options, jp.get());
    walls_used.insert(used.begin(), used.end());
    delay_holder = AddTimeBlock(s, scanners[s], options, delay_holder, scanners, jp.get());
    for (size_t i = 0; i < jp->parts[s]->weights.size(); ++i) {
      if (jp->parts[s]->weights[i] > 0.0) ++estimate.observations_used;
    }
  }
  ceres::Problem& problem = jp->joint.problem;
  AddWallPrior(walls, walls_used, jp.get());
  AddBiasChain(options, jp.get());
  AddEpochNoisePriors(options, jp.get());
  AddUnitPriors(scanners, jp.get());
  // Heading offsets: one prior per dwell, σ as the first scanner that saw the dwell has it.
  std::set<int> stated;
  for (const auto& part : jp->parts) {
    for (size_t k = 0; k < part->heading_station_ids.size(); ++k) {
      const int station = part->heading_station_ids[k];
      double* block = jp->headings[station].data();
      if (!(part->heading_offset_sigma_rad[k] > 0.0) || !problem.HasParameterBlock(block) ||
          !stated.insert(station).second) {
        continue;
      }
      problem.AddResidualBlock(ScalarPriorCost::Create(part->heading_offset_sigma_rad[k]),
                               nullptr, block);
    }
  }
  if (problem.HasParameterBlock(jp->no_heading.data())) {
    problem.SetParameterBlockConstant(jp->no_heading.data());
  }
  if (problem.HasParameterBlock(jp->no_bias.data())) {
    problem.SetParameterBlockConstant(jp->no_bias.data());
  }
  if (problem.HasParameterBlock(jp->drift.data())) {
    if (options.heading_drift_sigma_rad_per_s > 0.0) {
      problem.AddResidualBlock(ScalarPriorCost::Create(options.heading_drift_sigma_rad_per_s),
                               nullptr, jp->drift.data());
    } else {
      problem.SetParameterBlockConstant(jp->drift.data());
    }
  }

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.max_iterations;
  // Stops about 0.01 σ from the minimum along the weakest direction (as ceres_solver.cc).
  solver_options.function_tolerance =
      std::min(1e-6, 0.02 / std::max(1, problem.NumResiduals()));
  solver_options.num_threads = std::max(1, options.num_threads);
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  estimate.solver_report = summary.BriefReport();
  if (!summary.IsSolutionUsable()) {
    estimate.message = "the joint adjustment did not solve: " + summary.message;
    return estimate;
  }

  std::vector<double*> kept;
  for (auto& mount : jp->mounts) kept.push_back(mount.data());
  const Eigen::MatrixXd information = MarginalInformation(jp->joint, kept, options.num_threads);
  Eigen::MatrixXd covariance;
  if (information.rows() != static_cast<int>(3 * n) || !CovarianceOfKept(information, &covariance)) {
    estimate.message = "the joint covariance of the mounts could not be computed (a mount "
                       "direction the data do not determine)";
    return estimate;
  }
  estimate.covariance = covariance;
  // The units' share: the covariance with their models held where the adjustment put them
  // (the data's alone) taken from the one that estimates them.
  estimate.range_model_covariance = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  std::vector<double*> units;
  for (auto& unit : jp->units) {
    if (problem.HasParameterBlock(unit.data())) units.push_back(unit.data());
  }
  if (!units.empty()) {
    for (double* unit : units) problem.SetParameterBlockConstant(unit);
    const Eigen::MatrixXd held = MarginalInformation(jp->joint, kept, options.num_threads);
    for (double* unit : units) problem.SetParameterBlockVariable(unit);
    Eigen::MatrixXd data;
    if (held.rows() == static_cast<int>(3 * n) && CovarianceOfKept(held, &data)) {
      estimate.range_model_covariance = covariance - data;
    }
  }
  estimate.unit_ranges.assign(n, JointMountEstimate::UnitRange());
  for (size_t s = 0; s < n; ++s) {
    double* unit = jp->units[s].data();
    if (!problem.HasParameterBlock(unit)) continue;
    JointMountEstimate::UnitRange& range = estimate.unit_ranges[s];
    range.estimated = true;
    range.offset_m = jp->units[s][0];
    range.scale = jp->units[s][1];
    // Its own covariance, everything else marginalised (a held term has no column).
    Eigen::MatrixXd unit_covariance;
    if (!CovarianceOfKept(MarginalInformation(jp->joint, {unit}, options.num_threads),
                          &unit_covariance)) {
      continue;
    }
    const bool offset = scanners[s].range_offset_sigma_m > 0.0;
    const bool scale = scanners[s].range_scale_sigma > 0.0;
    if (offset) range.sigma_offset_m = std::sqrt(unit_covariance(0, 0));
    const int scale_row = offset ? 1 : 0;
    if (scale && scale_row < unit_covariance.rows()) {
      range.sigma_scale = std::sqrt(unit_covariance(scale_row, scale_row));
    }
  }
  for (size_t s = 0; s < n; ++s) {
    Mount mount;
    mount.x_m = jp->mounts[s][0];
    mount.y_m = jp->mounts[s][1];
    mount.yaw_rad = WrapAngle(jp->mounts[s][2]);
    estimate.mounts.push_back(mount);
    const bool estimated = jp->parts[s]->time_offset_estimated;
    estimate.time_offset_estimated.push_back(estimated);
    estimate.time_offset_s.push_back(scanners[s].observations->front().pose.clock_shift_s +
                                     (estimated ? jp->times[s][0] : 0.0));
  }
  estimate.usable = true;
  return estimate;
}

RelativeMount RelativeMountOf(const Mount& from, const Mount& to,
                              const Eigen::Matrix<double, 6, 6>& joint_covariance) {
  // from_T_to: t = R(−ψ_f)(p_t − p_f), yaw = ψ_t − ψ_f.
  const double c = std::cos(from.yaw_rad), s = std::sin(from.yaw_rad);
  const double dx = to.x_m - from.x_m, dy = to.y_m - from.y_m;
  RelativeMount relative;
  relative.from_T_to.x_m = c * dx + s * dy;
  relative.from_T_to.y_m = -s * dx + c * dy;
  relative.from_T_to.yaw_rad = WrapAngle(to.yaw_rad - from.yaw_rad);
  Eigen::Matrix<double, 3, 6> jacobian = Eigen::Matrix<double, 3, 6>::Zero();
  // d/d(from): −R(−ψ_f) on the position, and d/dψ_f of R(−ψ_f)(p_t − p_f) = (y, −x).
  jacobian.block<2, 2>(0, 0) << -c, -s, s, -c;
  jacobian(0, 2) = relative.from_T_to.y_m;
  jacobian(1, 2) = -relative.from_T_to.x_m;
  jacobian(2, 2) = -1.0;
  jacobian.block<2, 2>(0, 3) << c, s, -s, c;
  jacobian(2, 5) = 1.0;
  relative.covariance = jacobian * joint_covariance * jacobian.transpose();
  relative.covariance = 0.5 * (relative.covariance + relative.covariance.transpose());
  return relative;
}

}  // namespace wallcal::solvers
