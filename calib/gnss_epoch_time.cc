// SPDX-License-Identifier: Apache-2.0
#include "calib/gnss_epoch_time.h"

#include <algorithm>
#include <cmath>

#include "common/statistics.h"

namespace wallcal::calib {
namespace {

// 1.4826 · median |r|: the σ of a normal sample, robust to a few wild arrivals.
double RobustSigma(const std::vector<double>& residuals) {
  std::vector<double> abs_r(residuals.size());
  std::transform(residuals.begin(), residuals.end(), abs_r.begin(),
                 [](double r) { return std::abs(r); });
  return 1.4826 * Median(std::move(abs_r));
}

}  // namespace

const char* EpochMappingStatusName(EpochMappingStatus status) {
  switch (status) {
    case EpochMappingStatus::kMapped: return "mapped";
    case EpochMappingStatus::kNoLoggerStamp: return "no logger stamps (UTC used)";
    case EpochMappingStatus::kDisabled: return "disabled (arrival used)";
    case EpochMappingStatus::kTooFew: return "too few fixes with UTC (arrival used)";
    case EpochMappingStatus::kInconsistent: return "inconsistent (arrival used)";
  }
  return "?";
}

GnssEpochMapping MapGnssEpochs(std::vector<io::GnssFix>* fixes, bool enabled) {
  GnssEpochMapping m;
  std::vector<size_t> index;
  for (size_t i = 0; i < fixes->size(); ++i) {
    if (std::isfinite((*fixes)[i].utc_epoch_s)) index.push_back(i);
  }
  m.fixes = static_cast<int64_t>(index.size());
  if (index.empty()) return m;
  if (index.size() < static_cast<size_t>(kMinEpochFixes)) {
    m.status = EpochMappingStatus::kTooFew;
    return m;
  }
  const size_t n = index.size();
  std::vector<double> x(n), y(n), r(n);
  m.reference_utc_s = (*fixes)[index.front()].utc_epoch_s;
  bool increasing = true;
  for (size_t k = 0; k < n; ++k) {
    const io::GnssFix& fix = (*fixes)[index[k]];
    x[k] = fix.utc_epoch_s - m.reference_utc_s;
    y[k] = fix.stamp_s - fix.utc_epoch_s;
    if (k > 0 && !(x[k] > x[k - 1])) increasing = false;
  }
  // Start from the median difference (no drift), then a least-squares line through the points
  // within 5 robust σ, three times. The jitter is one-sided (a sentence never arrives early),
  // so the fitted offset is the mean latency, not its minimum.
  double a = Median(y), b = 0.0, sigma = 0.0;
  for (int round = 0; round < 3; ++round) {
    for (size_t k = 0; k < n; ++k) r[k] = y[k] - a - b * x[k];
    sigma = RobustSigma(r);
    const double gate = std::max(5.0 * sigma, 1e-3);
    double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t k = 0; k < n; ++k) {
      if (std::abs(r[k]) > gate) continue;
      sw += 1.0;
      sx += x[k];
      sy += y[k];
      sxx += x[k] * x[k];
      sxy += x[k] * y[k];
    }
    if (sw < 2.0) break;
    const double det = sw * sxx - sx * sx;
    if (det > 1e-9 * sw * sxx && det > 0.0) {
      b = (sw * sxy - sx * sy) / det;
      a = (sy - b * sx) / sw;
    } else {
      b = 0.0;
      a = sy / sw;
    }
  }
  for (size_t k = 0; k < n; ++k) r[k] = y[k] - a - b * x[k];
  sigma = RobustSigma(r);
  m.offset_s = a;
  m.drift = b;
  m.jitter_s = sigma;
  m.max_residual_s = 0.0;
  const double gate = std::max(5.0 * sigma, 1e-3);
  for (double residual : r) {
    m.max_residual_s = std::max(m.max_residual_s, std::abs(residual));
    if (std::abs(residual) > gate) ++m.outliers;
  }
  const bool consistent = increasing && std::isfinite(a) && std::isfinite(b) &&
                          sigma <= kMaxEpochJitterS && std::abs(b) <= kMaxEpochDriftRatio &&
                          m.outliers <= kMaxEpochOutlierShare * static_cast<double>(n);
  if (!consistent) {
    m.status = EpochMappingStatus::kInconsistent;
    return m;
  }
  if (!enabled) {
    m.status = EpochMappingStatus::kDisabled;
    return m;
  }
  m.status = EpochMappingStatus::kMapped;
  for (size_t k = 0; k < n; ++k) {
    io::GnssFix& fix = (*fixes)[index[k]];
    fix.stamp_s = fix.utc_epoch_s + a + b * x[k];
  }
  return m;
}

}  // namespace wallcal::calib
