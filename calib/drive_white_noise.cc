// SPDX-License-Identifier: Apache-2.0
#include "calib/drive_white_noise.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <Eigen/Dense>

#include "calib/white_noise.h"
#include "common/angles.h"
#include "common/statistics.h"

namespace wallcal::calib {
namespace {

// P(a, x), the regularised lower incomplete gamma function, by its power series (Abramowitz and
// Stegun 6.5.29); the arguments here are below 60, where it converges in a few hundred terms.
double RegularisedLowerGamma(double a, double x) {
  if (x <= 0.0) return 0.0;
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 1000 && term > sum * 1e-15; ++n) {
    term *= x / (a + n);
    sum += term;
  }
  return std::min(1.0, sum * std::exp(-x + a * std::log(x) - std::lgamma(a)));
}

double ChiSquareCdf(double k, double x) { return RegularisedLowerGamma(0.5 * k, 0.5 * x); }

double ChiSquareMedian(double k) {
  double lo = 0.0, hi = 10.0 * k + 10.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ChiSquareCdf(k, mid) < 0.5 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// For windows of pure white noise, s² = σ²·χ²_k / k. Keeping those with s² ≤ ratio × median
// keeps, of Σ s², the fraction E[χ²_k; χ²_k ≤ c] / k = P(χ²_{k+2} ≤ c), and of the windows the
// fraction P(χ²_k ≤ c), c = ratio × the χ²_k median: the pooled variance of the kept windows is
// σ² times their ratio, which this returns.
double KeptVarianceFraction(int k, double ratio) {
  const double c = ratio * ChiSquareMedian(k);
  return ChiSquareCdf(k + 2, c) / ChiSquareCdf(k, c);
}

struct Pooled {
  double sigma = 0.0;  // in the stream's unit; 0 below kMinWhiteNoiseDegreesOfFreedom
  int degrees_of_freedom = 0;
  int windows_used = 0;
  int windows_dropped = 0;
};

// One stream: its stamps and, per sample, `Dims` values (already unwrapped where they wrap).
template <int Dims>
Pooled PoolWindows(const std::vector<double>& stamps_s,
                   const std::vector<Eigen::Matrix<double, Dims, 1>>& values,
                   const std::vector<Dwell>& dwells) {
  constexpr int kN = kDriveWindowSamples;
  constexpr int kParams = kDriveFitDegree + 1;
  constexpr int kWindowDof = Dims * (kN - kParams);
  static_assert(kN > kParams, "a window needs more samples than the fit has parameters");
  assert(stamps_s.size() == values.size());
  const size_t n = stamps_s.size();
  Pooled pooled;
  if (n < static_cast<size_t>(kN)) return pooled;

  std::vector<double> intervals_s;
  intervals_s.reserve(n - 1);
  for (size_t i = 1; i < n; ++i) intervals_s.push_back(stamps_s[i] - stamps_s[i - 1]);
  const double max_gap_s = kDriveMaxGapIntervals * Median(intervals_s);

  // The dwells' samples are out. Dwells are few: a linear search per sample is cheap enough,
  // and needs no order among them.
  auto in_dwell = [&dwells](double t_s) {
    return std::any_of(dwells.begin(), dwells.end(),
                       [t_s](const Dwell& d) { return t_s >= d.start_s && t_s <= d.end_s; });
  };

  std::vector<double> window_rss;  // per window, Σ squared residuals over its axes
  auto fit_window = [&](size_t first) {
    // Time about the window's middle, scaled to [−1, 1]: the cubic's normal equations stay
    // well conditioned whatever the session's clock reads.
    const double t_mid_s = 0.5 * (stamps_s[first] + stamps_s[first + kN - 1]);
    const double half_span_s = 0.5 * (stamps_s[first + kN - 1] - stamps_s[first]);
    if (!(half_span_s > 0.0)) return;
    Eigen::Matrix<double, kN, kParams> a;
    Eigen::Matrix<double, kN, Dims> y;
    for (int i = 0; i < kN; ++i) {
      const double tau = (stamps_s[first + i] - t_mid_s) / half_span_s;
      double power = 1.0;
      for (int j = 0; j < kParams; ++j, power *= tau) a(i, j) = power;
      y.row(i) = (values[first + i] - values[first]).transpose();
    }
    const Eigen::Matrix<double, kParams, Dims> coefficients = a.colPivHouseholderQr().solve(y);
    window_rss.push_back((y - a * coefficients).squaredNorm());
  };

  size_t run_start = 0;
  while (run_start < n) {
    if (in_dwell(stamps_s[run_start])) {
      ++run_start;
      continue;
    }
    size_t run_end = run_start + 1;  // one past the run's last sample
    while (run_end < n && !in_dwell(stamps_s[run_end]) &&
           stamps_s[run_end] - stamps_s[run_end - 1] <= max_gap_s) {
      ++run_end;
    }
    for (size_t first = run_start; first + kN <= run_end; first += kN) fit_window(first);
    run_start = run_end;
  }
  if (window_rss.empty()) return pooled;

  const double limit = kDriveWindowRejectRatio * Median(window_rss);
  double sum_sq = 0.0;
  for (const double rss : window_rss) {
    if (rss <= limit) {
      sum_sq += rss;
      ++pooled.windows_used;
    } else {
      ++pooled.windows_dropped;
    }
  }
  pooled.degrees_of_freedom = pooled.windows_used * kWindowDof;
  if (pooled.degrees_of_freedom >= kMinWhiteNoiseDegreesOfFreedom) {
    pooled.sigma = std::sqrt(sum_sq / pooled.degrees_of_freedom /
                             KeptVarianceFraction(kWindowDof, kDriveWindowRejectRatio));
  }
  return pooled;
}

}  // namespace

DriveWhiteNoise MeasureDriveWhiteNoise(const std::vector<PositionSample>& positions,
                                       const std::vector<YawSample>& yaws,
                                       const std::vector<Dwell>& dwells) {
  DriveWhiteNoise noise;
  {
    std::vector<double> stamps_s;
    std::vector<Eigen::Vector2d> p_m;
    stamps_s.reserve(positions.size());
    p_m.reserve(positions.size());
    for (const PositionSample& p : positions) {
      stamps_s.push_back(p.stamp_s);
      p_m.push_back(p.p_local_m);
    }
    const Pooled gnss = PoolWindows<2>(stamps_s, p_m, dwells);
    noise.gnss_white_sigma_m = gnss.sigma;
    noise.gnss_degrees_of_freedom = gnss.degrees_of_freedom;
    noise.gnss_windows_used = gnss.windows_used;
    noise.gnss_windows_dropped = gnss.windows_dropped;
  }
  {
    // The yaw unwrapped along the whole stream: a window's values are then continuous through
    // ±π (consecutive samples turn by far less than π).
    std::vector<double> stamps_s;
    std::vector<Eigen::Matrix<double, 1, 1>> yaw_rad;
    stamps_s.reserve(yaws.size());
    yaw_rad.reserve(yaws.size());
    double unwrapped_rad = 0.0;
    for (size_t i = 0; i < yaws.size(); ++i) {
      unwrapped_rad = i == 0 ? yaws[0].yaw_rad
                             : unwrapped_rad + WrapAngle(yaws[i].yaw_rad - yaws[i - 1].yaw_rad);
      stamps_s.push_back(yaws[i].stamp_s);
      yaw_rad.push_back(Eigen::Matrix<double, 1, 1>(unwrapped_rad));
    }
    const Pooled heading = PoolWindows<1>(stamps_s, yaw_rad, dwells);
    noise.heading_sigma_rad = heading.sigma;
    noise.heading_degrees_of_freedom = heading.degrees_of_freedom;
    noise.heading_windows_used = heading.windows_used;
    noise.heading_windows_dropped = heading.windows_dropped;
  }
  return noise;
}

}  // namespace wallcal::calib
