// SPDX-License-Identifier: Apache-2.0
#include "analysis/residual_analysis.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "common/format.h"
#include "common/statistics.h"

namespace wallcal::analysis {
namespace {
// Estimated GNSS bias beyond this many prior σ: the station's position jumped.
constexpr double kJumpSigmas = 3.5;
// Range span (m) from which the range trend is turned into a corrected k.
constexpr double kMinRangeSpanForK = 3.0;

struct Slope {
  double slope = 0.0;
  double sigma = 0.0;  // 0 when it cannot be estimated
  double span = 0.0;   // max − min of the quantity
};

// Least-squares slope of r against q (equal weights) within groups (each group, a wall, has its
// own mean of q and r: q̃, r̃ are deviations from them), with the cluster-robust (sandwich)
// variance Σ_g (Σ_{i∈g} q̃_i e_i)² / (Σ q̃²)², clusters = stations, scaled by G/(G − 1).
// span: the largest within-group span of q.
Slope FitSlope(const std::vector<double>& q, const std::vector<double>& r,
               const std::vector<int>& cluster, const std::vector<int>& group,
               const std::vector<bool>& use) {
  Slope out;
  // Per group (wall): sums for the means, and the span of q.
  struct Sums {
    double q = 0.0, r = 0.0, q_min = 0.0, q_max = 0.0;
    int n = 0;
  };
  std::map<int, Sums> groups;
  int n = 0;
  for (size_t i = 0; i < q.size(); ++i) {
    if (!use[i]) continue;
    Sums& g = groups[group[i]];
    if (g.n == 0) g.q_min = g.q_max = q[i];
    g.q_min = std::min(g.q_min, q[i]);
    g.q_max = std::max(g.q_max, q[i]);
    g.q += q[i];
    g.r += r[i];
    ++g.n;
    ++n;
  }
  if (n < 3) return out;
  for (auto& [id, g] : groups) {
    out.span = std::max(out.span, g.q_max - g.q_min);
    g.q /= g.n;
    g.r /= g.n;
  }
  double sqq = 0.0, sqr = 0.0;
  for (size_t i = 0; i < q.size(); ++i) {
    if (!use[i]) continue;
    const Sums& g = groups.at(group[i]);
    sqq += (q[i] - g.q) * (q[i] - g.q);
    sqr += (q[i] - g.q) * (r[i] - g.r);
  }
  if (!(sqq > 0.0)) return out;
  out.slope = sqr / sqq;
  std::map<int, double> score;
  for (size_t i = 0; i < q.size(); ++i) {
    if (!use[i]) continue;
    const Sums& g = groups.at(group[i]);
    const double e = (r[i] - g.r) - out.slope * (q[i] - g.q);
    score[cluster[i]] += (q[i] - g.q) * e;
  }
  const double clusters = static_cast<double>(score.size());
  if (clusters < 3) return out;
  double meat = 0.0;
  for (const auto& [id, value] : score) meat += value * value;
  out.sigma = std::sqrt(clusters / (clusters - 1.0) * meat) / sqq;
  return out;
}


}  // namespace

const char* TrendAxisName(TrendAxis axis) {
  switch (axis) {
    case TrendAxis::kRange: return "range";
    case TrendAxis::kIncidence: return "incidence";
    case TrendAxis::kBearing: return "bearing";
    case TrendAxis::kHeading: return "heading";
    case TrendAxis::kStation: return "station";
    case TrendAxis::kTime: return "time";
  }
  return "";
}

ResidualAnalysis AnalyseResiduals(const std::vector<calib::WallObservation>& observations,
                                  const std::vector<calib::WallGeometry>& walls,
                                  const solvers::MountEstimate& estimate,
                                  const io::ScannerPreset& preset) {
  ResidualAnalysis analysis;
  const size_t n = observations.size();
  if (n < 10 || estimate.residual_rho_m.size() != n) return analysis;
  const std::vector<double>& r = estimate.residual_rho_m;

  // Robust spread and the 2σ outliers (Hartzell, Glennie et al.).
  const double median = Median(r);
  std::vector<double> deviation(n);
  for (size_t i = 0; i < n; ++i) deviation[i] = std::abs(r[i] - median);
  analysis.robust_sigma_m = 1.4826 * Median(deviation);
  const double sigma = std::max(analysis.robust_sigma_m, 1e-6);
  int outliers = 0;
  std::vector<bool> use(n, true);
  for (size_t i = 0; i < n; ++i) {
    if (deviation[i] > 2.0 * sigma) ++outliers;
    use[i] = deviation[i] <= 3.0 * sigma;  // trends on the inliers only
  }
  analysis.outlier_share = static_cast<double>(outliers) / static_cast<double>(n);

  // Stations in time order (the mean stamp of each segment).
  std::map<int, std::pair<double, int>> segment_time;
  double t0 = observations.front().pose.stamp_s;
  for (const auto& o : observations) {
    auto& entry = segment_time[o.pose.segment];
    entry.first += o.pose.stamp_s;
    entry.second += 1;
    t0 = std::min(t0, o.pose.stamp_s);
  }
  std::vector<std::pair<double, int>> order;
  for (const auto& [segment, sum] : segment_time) order.emplace_back(sum.first / sum.second, segment);
  std::sort(order.begin(), order.end());
  std::map<int, int> rank;
  for (size_t k = 0; k < order.size(); ++k) rank[order[k].second] = static_cast<int>(k);

  // The quantities. Heading unwrapped about its circular mean.
  double sx = 0.0, sy = 0.0;
  for (const auto& o : observations) {
    sx += std::cos(HeadingFromYaw(o.pose.yaw_rad));
    sy += std::sin(HeadingFromYaw(o.pose.yaw_rad));
  }
  const double mean_heading = std::atan2(sy, sx);
  std::vector<double> range(n), incidence(n), bearing(n), heading(n), station(n), time(n);
  std::vector<int> cluster(n);
  // Each wall is its own group in the trend fits: different walls see different components of
  // a station's 2-D GNSS error (added back below), so pooling them made "range trends" out of
  // the far wall's view of the RTK error on clean two-wall sessions (6 of 20 flagged).
  std::vector<int> wall_of(n);
  std::map<int, Eigen::Vector2d> bias_of;
  for (size_t k = 0; k < estimate.segment_ids.size() && k < estimate.segment_bias_m.size(); ++k) {
    bias_of[estimate.segment_ids[k]] = estimate.segment_bias_m[k];
  }
  std::vector<double> with_bias(r);
  for (size_t i = 0; i < n; ++i) {
    const calib::WallObservation& o = observations[i];
    const auto found = bias_of.find(calib::GnssSegment(o));
    if (found != bias_of.end() && o.wall_index >= 0 &&
        o.wall_index < static_cast<int>(walls.size())) {
      const calib::OrientedWall wall =
          calib::OrientWall(walls[o.wall_index], o.pose.antenna_local_m);
      with_bias[i] = r[i] + wall.normal_local.dot(found->second);
    }
    const double mid_m = o.range_max_m > 0.0 ? 0.5 * (o.range_min_m + o.range_max_m) : o.rho_m;
    range[i] = std::max(mid_m, o.rho_m);
    incidence[i] = std::acos(std::clamp(o.rho_m / range[i], -1.0, 1.0)) * kRadToDeg;
    bearing[i] = o.theta_rad * kRadToDeg;
    const double h = HeadingFromYaw(o.pose.yaw_rad) - mean_heading;
    heading[i] = std::remainder(h, 2.0 * kPi) * kRadToDeg;
    station[i] = rank[o.pose.segment];
    time[i] = o.pose.stamp_s - t0;
    cluster[i] = o.pose.segment;
    wall_of[i] = o.wall_index;
  }

  struct Spec {
    TrendAxis against;
    const char* unit;
    const std::vector<double>* values;
    const char* suggestion;
  };
  const Spec specs[] = {
      {TrendAxis::kRange, "m/m", &range,
       "range scale error: the preset's k may be wrong (residuals grow with range)"},
      {TrendAxis::kIncidence, "m/deg", &incidence,
       "residuals change with incidence angle: beam footprint / mixed pixels at grazing angles?"},
      {TrendAxis::kBearing, "m/deg", &bearing,
       "residuals change with beam bearing: the scanner's angular zero or the mount yaw?"},
      {TrendAxis::kHeading, "m/deg", &heading, "a trend with heading: a yaw/heading problem"},
      {TrendAxis::kStation, "m/station", &station, "a step between stations: a GNSS jump?"},
      {TrendAxis::kTime, "m/s", &time, "residuals drift with time: heading drift or a clock offset?"},
  };
  // The RTK error's σ between stations: the mean prior σ of the GNSS-error slices (0 when the
  // estimate has none, e.g. barawid).
  double station_error_m = 0.0;
  if (!estimate.segment_bias_sigma_m.empty()) {
    for (double s_b : estimate.segment_bias_sigma_m) station_error_m += s_b;
    station_error_m /= static_cast<double>(estimate.segment_bias_sigma_m.size());
  }
  for (const Spec& spec : specs) {
    const Slope fit = FitSlope(*spec.values, with_bias, cluster, wall_of, use);
    ResidualTrend trend;
    trend.against = spec.against;
    trend.unit = spec.unit;
    trend.slope = fit.slope;
    trend.significance = fit.sigma > 0.0 ? std::abs(fit.slope) / fit.sigma : 0.0;
    // Flag only what is both significant and material: the trend moves the residuals by at
    // least one robust σ over the span seen, and by more than the RTK error can between
    // stations (2 σ_b): the residuals carry each station's GNSS error added back, and when a
    // quantity changes mostly from station to station (range and incidence at a wall 2.4 m
    // away change by 6 cm and 2° over a session) the time-correlated RTK error alone made
    // "trends" at 10σ on clean simulated sessions (the cluster-robust σ takes the stations
    // as independent; the RTK error is not).
    trend.flagged = fit.sigma > 0.0 && trend.significance >= kTrendFlagSignificance &&
                    std::abs(fit.slope) * fit.span >= std::max(sigma, 2.0 * station_error_m);
    if (trend.flagged) {
      trend.message = spec.suggestion;
      analysis.flags.push_back(std::string(spec.suggestion) + " (slope " +
                               Format("%.3g ", fit.slope) + spec.unit +
                               Format(", %.1f sigma)", trend.significance));
    }
    analysis.trends.push_back(trend);

    // The range trend as a corrected k: corrected ranges scaled by s give residuals ≈ (s − 1)
    // rho, so k / s ≈ k (1 − slope) undoes it. b is not separable from the mount's x.
    if (spec.against == TrendAxis::kRange && fit.sigma > 0.0 && fit.span >= kMinRangeSpanForK) {
      analysis.range_model_estimated = true;
      analysis.range_scale_k = preset.range_scale_k * (1.0 - fit.slope);
      analysis.sigma_range_scale_k = std::abs(preset.range_scale_k) * fit.sigma;
      analysis.range_offset_b_m = preset.range_offset_b_m;
      analysis.sigma_range_offset_b_m = 0.0;
    }
  }

  // A GNSS jump is mostly absorbed by the GNSS-error slices' bias parameters: look at the
  // estimated biases against their prior σ as well, one flag per station (its largest slice).
  std::map<int, int> station_of_slice;  // GNSS-error slice key -> station (pose.segment)
  for (const auto& o : observations) station_of_slice.emplace(calib::GnssSegment(o), o.pose.segment);
  std::map<int, std::pair<double, double>> worst;  // station rank -> (ratio, |bias| m)
  for (size_t k = 0; k < estimate.segment_ids.size(); ++k) {
    const double sigma_b =
        k < estimate.segment_bias_sigma_m.size() ? estimate.segment_bias_sigma_m[k] : 0.0;
    if (!(sigma_b > 0.0) || k >= estimate.segment_bias_m.size()) continue;
    const double ratio = estimate.segment_bias_m[k].norm() / sigma_b;
    if (!(ratio > kJumpSigmas)) continue;
    const auto slice = station_of_slice.find(estimate.segment_ids[k]);
    const auto found = slice == station_of_slice.end() ? rank.end() : rank.find(slice->second);
    const int station_rank = found == rank.end() ? -1 : found->second;
    auto& entry = worst[station_rank];
    if (ratio > entry.first) entry = {ratio, estimate.segment_bias_m[k].norm()};
  }
  for (const auto& [station_rank, entry] : worst) {
    analysis.flags.push_back(
        "a step between stations: a GNSS jump? (station " + std::to_string(station_rank + 1) +
        Format(": GNSS bias %.3f m, ", entry.second) + Format("%.1f prior sigma)", entry.first));
    for (ResidualTrend& trend : analysis.trends) {
      if (trend.against == TrendAxis::kStation && !trend.flagged) {
        trend.flagged = true;
        trend.message = "a step between stations: a GNSS jump?";
      }
    }
  }
  analysis.done = true;
  return analysis;
}

}  // namespace wallcal::analysis
