// SPDX-License-Identifier: Apache-2.0
#include "calib/white_noise.h"

#include <algorithm>
#include <cmath>

#include "common/angles.h"

namespace wallcal::calib {

MeasuredWhiteNoise MeasureWhiteNoise(const std::vector<PositionSample>& positions,
                                     const std::vector<YawSample>& yaws,
                                     const std::vector<Dwell>& dwells) {
  MeasuredWhiteNoise noise;
  double gnss_sum_sq_m2 = 0.0;
  int gnss_dof = 0;
  for (const Dwell& dwell : dwells) {
    const auto first =
        std::lower_bound(positions.begin(), positions.end(), dwell.start_s,
                         [](const PositionSample& p, double t) { return p.stamp_s < t; });
    const auto last =
        std::upper_bound(first, positions.end(), dwell.end_s,
                         [](double t, const PositionSample& p) { return t < p.stamp_s; });
    const int n = static_cast<int>(last - first);
    if (n < 3) continue;
    // Least-squares line in time per axis, about the dwell's mean time and position.
    double t_mean_s = 0.0;
    Eigen::Vector2d p_mean = Eigen::Vector2d::Zero();
    for (auto it = first; it != last; ++it) {
      t_mean_s += it->stamp_s / n;
      p_mean += it->p_local_m / n;
    }
    double stt = 0.0;
    Eigen::Vector2d stp = Eigen::Vector2d::Zero();
    for (auto it = first; it != last; ++it) {
      const double dt_s = it->stamp_s - t_mean_s;
      stt += dt_s * dt_s;
      stp += dt_s * (it->p_local_m - p_mean);
    }
    const Eigen::Vector2d slope = stt > 0.0 ? Eigen::Vector2d(stp / stt) : Eigen::Vector2d::Zero();
    for (auto it = first; it != last; ++it) {
      gnss_sum_sq_m2 += (it->p_local_m - p_mean - slope * (it->stamp_s - t_mean_s)).squaredNorm();
    }
    gnss_dof += 2 * (n - 2);
  }
  noise.gnss_degrees_of_freedom = gnss_dof;
  if (gnss_dof >= kMinWhiteNoiseDegreesOfFreedom) {
    noise.gnss_white_sigma_m = std::sqrt(gnss_sum_sq_m2 / gnss_dof);
  }
  double sum_sq_rad2 = 0.0;
  int dof = 0;
  for (const Dwell& dwell : dwells) {
    const auto first = std::lower_bound(yaws.begin(), yaws.end(), dwell.start_s,
                                        [](const YawSample& y, double t) { return y.stamp_s < t; });
    const auto last = std::upper_bound(first, yaws.end(), dwell.end_s,
                                       [](double t, const YawSample& y) { return t < y.stamp_s; });
    const int n = static_cast<int>(last - first);
    if (n < 2) continue;
    // Deviations from the first sample (no wrap inside a dwell), then about their mean.
    double sum_rad = 0.0, sum_sq = 0.0;
    for (auto it = first; it != last; ++it) {
      const double d_rad = WrapAngle(it->yaw_rad - first->yaw_rad);
      sum_rad += d_rad;
      sum_sq += d_rad * d_rad;
    }
    sum_sq_rad2 += std::max(0.0, sum_sq - sum_rad * sum_rad / n);
    dof += n - 1;
  }
  noise.heading_degrees_of_freedom = dof;
  if (dof >= kMinWhiteNoiseDegreesOfFreedom) noise.heading_sigma_rad = std::sqrt(sum_sq_rad2 / dof);
  return noise;
}

}  // namespace wallcal::calib
