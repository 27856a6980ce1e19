// SPDX-License-Identifier: Apache-2.0
#include "solvers/unit_scale_reference.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "solvers/mount_problem.h"

namespace wallcal::solvers {
namespace {

// A group's sum without one member: the mean of the others, or the member's own value alone.
double MeanOfOthers(double sum, int count, double own, double fallback) {
  return count > 1 ? (sum - own) / (count - 1) : fallback;
}

}  // namespace

double PredictedRho(const WallLineMeasurement& measurement, const calib::Mount& mount) {
  const Eigen::Vector2d normal = measurement.sign * measurement.wall_normal_local;
  const double c = std::cos(measurement.vehicle_yaw_rad);
  const double s = std::sin(measurement.vehicle_yaw_rad);
  const Eigen::Vector2d scanner =
      measurement.antenna_local_m +
      Eigen::Vector2d(c * mount.x_m - s * mount.y_m, s * mount.x_m + c * mount.y_m);
  return normal.dot(measurement.wall_centre_local_m - scanner);
}

std::vector<double> UnitScaleReferences(const std::vector<calib::WallObservation>& observations,
                                        const std::vector<WallLineMeasurement>& measurements,
                                        const calib::Mount& mount, double window_s) {
  const size_t n = std::min(observations.size(), measurements.size());
  std::vector<double> reference(n);
  // Standing: one group per (dwell, wall).
  std::map<std::pair<int, int>, std::pair<double, int>> dwells;  // sum of rho (m), count
  // Moving: per wall, the scans in time order with measured − predicted rho (m).
  std::map<int, std::vector<std::pair<double, size_t>>> moving;  // (stamp s, index)
  std::vector<double> difference(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const calib::WallObservation& o = observations[i];
    reference[i] = measurements[i].rho_m;
    if (UsesDwellHeading(o)) {
      auto& group = dwells[{o.pose.segment, o.wall_index}];
      group.first += measurements[i].rho_m;
      group.second += 1;
    } else {
      difference[i] = measurements[i].rho_m - PredictedRho(measurements[i], mount);
      moving[o.wall_index].emplace_back(o.pose.stamp_s, i);
    }
  }
  for (size_t i = 0; i < n; ++i) {
    const calib::WallObservation& o = observations[i];
    if (!UsesDwellHeading(o)) continue;
    const auto& group = dwells.at({o.pose.segment, o.wall_index});
    reference[i] =
        MeanOfOthers(group.first, group.second, measurements[i].rho_m, measurements[i].rho_m);
  }
  // A window sliding over each wall's moving scans: [first, last) holds those within window_s.
  for (auto& [wall, scans] : moving) {
    std::stable_sort(scans.begin(), scans.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    size_t first = 0, last = 0;
    double sum = 0.0;
    for (const auto& [stamp_s, i] : scans) {
      while (last < scans.size() && scans[last].first <= stamp_s + window_s) {
        sum += difference[scans[last].second];
        ++last;
      }
      while (scans[first].first < stamp_s - window_s) {
        sum -= difference[scans[first].second];
        ++first;
      }
      const int count = static_cast<int>(last - first);
      if (count > 1) {
        reference[i] =
            PredictedRho(measurements[i], mount) + MeanOfOthers(sum, count, difference[i], 0.0);
      }
    }
  }
  return reference;
}

}  // namespace wallcal::solvers
