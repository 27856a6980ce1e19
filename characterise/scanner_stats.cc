// SPDX-License-Identifier: Apache-2.0
// Quantum, noise growth, incidence limit and mixed pixels (characterise/scanner_stats.h).

#include "characterise/scanner_stats.h"

#include <cmath>

#include "common/angles.h"

namespace wallcal::characterise {
namespace {

// Least-squares slope of y against x, σ from the scatter (points independent).
Value Slope(const std::vector<double>& x, const std::vector<double>& y) {
  const size_t n = x.size();
  if (n < 10) return {};
  double mx = 0, my = 0;
  for (size_t i = 0; i < n; ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  if (!(sxx > 0)) return {};
  const double slope = sxy / sxx;
  double rss = 0;
  for (size_t i = 0; i < n; ++i) {
    const double e = y[i] - my - slope * (x[i] - mx);
    rss += e * e;
  }
  return {slope, std::sqrt(rss / (n - 2) / sxx)};
}

// The squared residual's slope turned into dσ/dx: d(σ²)/dx = 2σ·dσ/dx.
NoiseTrend Trend(const std::vector<double>& x, const std::vector<double>& r2, double sigma_m) {
  NoiseTrend trend;
  const Value s = Slope(x, r2);
  if (!s.known() || !(sigma_m > 0)) return trend;
  trend.slope = {s.value / (2 * sigma_m), s.sigma / (2 * sigma_m)};
  trend.grows = trend.slope.value > 4.0 * trend.slope.sigma;
  return trend;
}

}  // namespace

double RangeQuantum(const BeamSet& set, double* share) {
  int64_t total = 0, on_cm = 0, on_mm = 0;
  for (const BeamReturn& beam : set.beams) {
    if (!beam.near_wall || !std::isfinite(beam.z_m)) continue;
    ++total;
    const double z = beam.z_m;
    if (std::abs(z / 0.01 - std::round(z / 0.01)) < 0.02) ++on_cm;
    if (std::abs(z / 0.001 - std::round(z / 0.001)) < 0.2) ++on_mm;
  }
  *share = 0.0;
  if (total == 0) return 0.0;
  if (on_cm >= 0.98 * total) {
    *share = static_cast<double>(on_cm) / total;
    return 0.01;
  }
  if (on_mm >= 0.98 * total) {
    *share = static_cast<double>(on_mm) / total;
    return 0.001;
  }
  return 0.0;
}

ScannerStats MeasureStats(const BeamSet& set, const FitOutput& fit, double quantum_m,
                          double quantum_share) {
  ScannerStats stats;
  stats.quantum_m = quantum_m;
  stats.quantum_share = quantum_share;
  const RangeModel& model = fit.model;
  const double gate_m = std::max(4.0 * fit.robust_sigma_m, 1e-3);

  // Noise growth over the fitted beams.
  std::vector<double> range, incidence, r2;
  constexpr int kBins = 18;  // 5° bins of incidence, 0–90°
  std::vector<int64_t> expected(kBins, 0), returned(kBins, 0);
  double max_incidence = 0.0;
  int64_t edge = 0, mixed = 0;
  for (size_t b = 0; b < set.beams.size(); ++b) {
    const BeamReturn& beam = set.beams[b];
    const double t = fit.true_range_m[b], inc = fit.incidence_rad[b], r = fit.residual_m[b];
    if (!std::isfinite(t)) continue;
    if (beam.kind == BeamKind::kEdge) {
      ++edge;
      if (std::isfinite(beam.z_m) &&
          std::abs(beam.z_m - (model.n.value * t + model.c_m.value)) > gate_m) {
        ++mixed;
      }
      continue;
    }
    const int bin = std::min(kBins - 1, static_cast<int>(inc * kRadToDeg / 5.0));
    ++expected[bin];
    const bool on_wall = std::isfinite(r) && std::abs(r) <= gate_m;
    if (on_wall) {
      ++returned[bin];
      max_incidence = std::max(max_incidence, inc);
    }
    const double e = fit.noise_residual_m[b];
    if (std::isfinite(e)) {
      range.push_back(t);
      incidence.push_back(inc);
      r2.push_back(e * e);
    }
  }
  const double sigma_obs = std::hypot(model.sigma_m.value, quantum_m / std::sqrt(12.0));
  stats.noise_vs_range = Trend(range, r2, sigma_obs);
  stats.noise_vs_incidence = Trend(incidence, r2, sigma_obs);

  // The incidence limit: where the share of returns first falls below one half (bins with at
  // least 30 beams expected), interpolated between bin centres; σ: a bin's width / √12.
  double previous_share = -1.0, previous_centre = 0.0;
  for (int bin = 0; bin < kBins; ++bin) {
    if (expected[bin] < 30) continue;
    const double share = static_cast<double>(returned[bin]) / expected[bin];
    const double centre = 5.0 * bin + 2.5;
    stats.incidence_bin_deg.push_back(centre);
    stats.return_share.push_back(share);
    if (!stats.incidence_limit_reached && share < 0.5) {
      double limit_deg = centre - 2.5;
      if (previous_share >= 0.5) {
        limit_deg = previous_centre +
                    (previous_share - 0.5) / (previous_share - share) * (centre - previous_centre);
      }
      stats.incidence_limit_reached = previous_share >= 0.5;
      stats.incidence_limit_rad = {limit_deg / kRadToDeg, 5.0 / std::sqrt(12.0) / kRadToDeg};
      if (!stats.incidence_limit_reached) stats.incidence_limit_rad.sigma = -1.0;
    }
    previous_share = share;
    previous_centre = centre;
  }
  if (!stats.incidence_limit_rad.known() && !stats.incidence_limit_reached) {
    stats.incidence_limit_rad = {max_incidence, -1.0};  // a lower bound only
  }

  stats.edge_beams = static_cast<int>(edge);
  if (edge >= 20) {
    const double p = static_cast<double>(mixed) / edge;
    stats.mixed_pixel_rate = {p, std::sqrt(std::max(p * (1 - p), 1.0 / edge) / edge)};
  }
  return stats;
}

}  // namespace wallcal::characterise
