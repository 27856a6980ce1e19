// SPDX-License-Identifier: Apache-2.0
#include "analysis/error_budget.h"

#include <algorithm>
#include <cmath>

#include "analysis/repeatability.h"
#include "common/enum_text.h"
#include "common/parallel_for.h"
#include "solvers/mount_solver.h"

namespace wallcal::analysis {
namespace {

// A source made exact: its σ times this. Not 0: the adjustment holds a zero-σ wall constant
// but divides by the GNSS and scanner σ.
constexpr double kExact = 1e-3;

Eigen::Vector3d Diagonal(const Eigen::Matrix3d& covariance) {
  return Eigen::Vector3d(covariance(0, 0), covariance(1, 1), covariance(2, 2));
}

}  // namespace

const char* ErrorSourceName(ErrorSource source) {
  static const EnumText<ErrorSource> kTexts[] = {
      {ErrorSource::kSurvey, "survey points"},
      {ErrorSource::kControl, "control points (survey tie)"},
      {ErrorSource::kGnss, "GNSS position"}, {ErrorSource::kHeading, "heading"},
      {ErrorSource::kScanner, "scanner noise"}, {ErrorSource::kRover, "rover points"}};
  return TextOf(kTexts, source, "");
}

const char* ErrorSourceKey(ErrorSource source) {
  static const EnumText<ErrorSource> kTexts[] = {
      {ErrorSource::kSurvey, "survey_points"}, {ErrorSource::kControl, "control_points"},
      {ErrorSource::kGnss, "gnss"}, {ErrorSource::kHeading, "heading"},
      {ErrorSource::kScanner, "scanner_noise"}, {ErrorSource::kRover, "rover_points"}};
  return TextOf(kTexts, source, "");
}

ErrorBudget ComputeErrorBudget(const std::vector<calib::WallObservation>& observations,
                               const std::vector<calib::WallGeometry>& walls,
                               const solvers::SolverOptions& options, const calib::Mount& mount) {
  ErrorBudget budget;
  if (observations.empty()) return budget;
  // Long sessions are thinned as the repeatability's re-solves are (ThinForRefits): the
  // shares are ratios of variances, which the thinning leaves as they are to the sampling of
  // the scans.
  const ThinnedObservations thin = ThinForRefits(observations);
  const std::vector<calib::WallObservation>& base = thin.observations;
  const std::vector<double> weights(base.size(), thin.stride);
  // Linearised at the estimate: one Gauss-Newton step at most (the estimate is the optimum).
  solvers::SolverOptions one_thread = options;
  one_thread.num_threads = 1;
  auto covariance_of = [&](const std::vector<calib::WallObservation>& obs,
                           const std::vector<calib::WallGeometry>& w, const solvers::SolverOptions& o,
                           Eigen::Vector3d* diagonal) {
    const solvers::Refit refit = solvers::RefitMount(obs, w, o, mount, weights, 1);
    if (!refit.converged || !refit.covariance.allFinite()) return false;
    *diagonal = Diagonal(refit.covariance);
    return true;
  };

  // Slot 0: every source as it is; slot 1 + k: source k made exact. Solved over the threads,
  // one Ceres thread each; each slot is its own.
  std::array<Eigen::Vector3d, kNumErrorSources + 1> variances{};
  std::array<bool, kNumErrorSources + 1> ok{};
  const int rover_slot = 1 + static_cast<int>(ErrorSource::kRover);
  const bool any_rover = std::any_of(walls.begin(), walls.end(),
                                     [](const calib::WallGeometry& w) { return w.from_rover; });
  ParallelFor(kNumErrorSources + 1, options.num_threads, [&](int slot) {
    if (slot == rover_slot && !any_rover) {  // nothing to make exact: slot 0's variance
      ok[slot] = true;
      return;
    }
    if (slot == 0) {
      ok[0] = covariance_of(base, walls, one_thread, &variances[0]);
      return;
    }
    const ErrorSource source = static_cast<ErrorSource>(slot - 1);
    std::vector<calib::WallObservation> obs;
    std::vector<calib::WallGeometry> w = walls;
    solvers::SolverOptions o = one_thread;
    switch (source) {
      case ErrorSource::kSurvey:
        // Keep only the tie's part of each wall's prior (calib/survey_tie.cc builds the two
        // as a sum: fit + tie). A rover's wall is the rover term's.
        for (calib::WallGeometry& wall : w) {
          if (wall.from_rover) continue;
          const double tie_offset_var = wall.tie_sigma_translation_m * wall.tie_sigma_translation_m +
                                        std::pow(wall.tie_sigma_rotation_rad * wall.tie_lever_m, 2);
          const double tie_angle_var = wall.tie_sigma_rotation_rad * wall.tie_sigma_rotation_rad;
          wall.sigma_offset_m = std::sqrt(std::max(tie_offset_var, kExact * kExact *
                                                   wall.sigma_offset_m * wall.sigma_offset_m));
          wall.sigma_angle_rad = std::sqrt(std::max(tie_angle_var, kExact * kExact *
                                                    wall.sigma_angle_rad * wall.sigma_angle_rad));
          wall.cov_offset_angle = tie_angle_var * wall.tie_lever_m;
        }
        break;
      case ErrorSource::kControl:
        // Keep only the survey fit's part: remove the tie's.
        for (calib::WallGeometry& wall : w) {
          if (wall.from_rover) continue;  // no tie
          const double tie_offset_var = wall.tie_sigma_translation_m * wall.tie_sigma_translation_m +
                                        std::pow(wall.tie_sigma_rotation_rad * wall.tie_lever_m, 2);
          const double tie_angle_var = wall.tie_sigma_rotation_rad * wall.tie_sigma_rotation_rad;
          const double floor_offset = kExact * wall.sigma_offset_m;
          const double floor_angle = kExact * wall.sigma_angle_rad;
          wall.sigma_offset_m = std::sqrt(std::max(
              wall.sigma_offset_m * wall.sigma_offset_m - tie_offset_var, floor_offset * floor_offset));
          wall.sigma_angle_rad = std::sqrt(std::max(
              wall.sigma_angle_rad * wall.sigma_angle_rad - tie_angle_var, floor_angle * floor_angle));
          wall.cov_offset_angle -= tie_angle_var * wall.tie_lever_m;
          wall.tie_sigma_translation_m = 0.0;
          wall.tie_sigma_rotation_rad = 0.0;
        }
        break;
      case ErrorSource::kGnss:
        o.gnss_white_sigma_m *= kExact;
        o.gnss_bias_sigma_m *= kExact;
        obs = base;
        for (calib::WallObservation& ob : obs) ob.pose.gnss_sigma_m *= kExact;
        break;
      case ErrorSource::kHeading:
        o.heading_sigma_rad *= kExact;
        break;
      case ErrorSource::kRover:
        // A rover's wall has no tie: its whole prior is the rover points' fit.
        for (calib::WallGeometry& wall : w) {
          if (!wall.from_rover) continue;
          wall.sigma_offset_m *= kExact;
          wall.sigma_angle_rad *= kExact;
          wall.cov_offset_angle *= kExact * kExact;
        }
        break;
      case ErrorSource::kScanner:
        obs = base;
        for (calib::WallObservation& ob : obs) {
          ob.sigma_rho_m *= kExact;
          ob.sigma_theta_rad *= kExact;
          ob.cov_rho_theta *= kExact * kExact;
        }
        break;
    }
    ok[slot] = covariance_of(obs.empty() ? base : obs, w, o, &variances[slot]);
  });
  if (!ok[0]) return budget;
  if (!any_rover) variances[rover_slot] = variances[0];
  budget.total_variance = variances[0];
  for (bool slot_ok : ok) {
    if (!slot_ok) return budget;
  }
  for (int k = 0; k < kNumErrorSources; ++k) {
    budget.variance[k] = (budget.total_variance - variances[k + 1]).cwiseMax(0.0);
  }
  for (int axis = 0; axis < 3; ++axis) {
    int best = 0;
    for (int k = 1; k < kNumErrorSources; ++k) {
      if (budget.variance[k][axis] > budget.variance[best][axis]) best = k;
    }
    budget.dominant[axis] = static_cast<ErrorSource>(best);
    budget.dominant_share[axis] = budget.total_variance[axis] > 0.0
                                      ? budget.variance[best][axis] / budget.total_variance[axis]
                                      : 0.0;
  }
  budget.done = true;
  return budget;
}

}  // namespace wallcal::analysis
