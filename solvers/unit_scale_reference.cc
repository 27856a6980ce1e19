// SPDX-License-Identifier: Apache-2.0
#include "solvers/unit_scale_reference.h"

#include <algorithm>
#include <map>
#include <utility>

#include "calib/wall_geometry.h"
#include "solvers/mount_problem.h"

namespace wallcal::solvers {

std::vector<double> UnitScaleReferences(const std::vector<calib::WallObservation>& observations,
                                        const std::vector<WallLineMeasurement>& measurements,
                                        const std::vector<calib::WallGeometry>& walls,
                                        const calib::Mount& mount, double window_s) {
  const size_t n = std::min(observations.size(), measurements.size());
  std::vector<double> reference(n);
  // Each scan's reference is the mean of the others in its group; alone, its own measured rho.
  // Standing: one group per (dwell, wall).
  std::map<std::pair<int, int>, std::pair<double, int>> dwells;  // sum of rho (m), count
  // Moving: per wall, the scans in time order with measured − predicted rho (m).
  std::map<int, std::vector<std::pair<double, size_t>>> moving;  // (stamp s, index)
  std::vector<double> predicted(n, 0.0), difference(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const calib::WallObservation& o = observations[i];
    reference[i] = measurements[i].rho_m;
    if (UsesDwellHeading(o)) {
      auto& group = dwells[{o.pose.segment, o.wall_index}];
      group.first += measurements[i].rho_m;
      group.second += 1;
    } else {
      predicted[i] = calib::PredictRho(o, walls.at(o.wall_index), mount);
      difference[i] = measurements[i].rho_m - predicted[i];
      moving[o.wall_index].emplace_back(o.pose.stamp_s, i);
    }
  }
  for (size_t i = 0; i < n; ++i) {
    const calib::WallObservation& o = observations[i];
    if (!UsesDwellHeading(o)) continue;
    const std::pair<double, int>& group = dwells.at({o.pose.segment, o.wall_index});
    if (group.second > 1) {
      reference[i] = (group.first - measurements[i].rho_m) / (group.second - 1);
    }
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
        reference[i] = predicted[i] + (sum - difference[i]) / (count - 1);
      }
    }
  }
  return reference;
}

}  // namespace wallcal::solvers
