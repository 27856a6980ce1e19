// SPDX-License-Identifier: Apache-2.0
#pragma once
// Linear interpolation of a sampled stream (samples at j / rate_hz, j >= 0) in the Cramér–Rao
// bound (bench/crb.h): the weights of a scan's two neighbouring samples, and the covariance two
// such interpolations of one white stream share.

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace wallcal::bench {

struct Interp {
  int64_t j0 = 0;
  double w0 = 1.0, w1 = 0.0;  // weights of samples j0 and j0 + 1
};

inline Interp Weights(double t_s, double rate_hz) {
  Interp w;
  const double x = std::max(0.0, t_s * rate_hz);
  w.j0 = static_cast<int64_t>(std::floor(x + 1e-9));
  const double f = std::clamp(x - w.j0, 0.0, 1.0);
  w.w0 = 1.0 - f;
  w.w1 = f;
  return w;
}

// Σ_j w_kj w_lj for two interpolations of the same white stream (unit variance per sample).
inline double Overlap(const Interp& a, const Interp& b) {
  double s = 0.0;
  const int64_t a_idx[2] = {a.j0, a.j0 + 1}, b_idx[2] = {b.j0, b.j0 + 1};
  const double a_w[2] = {a.w0, a.w1}, b_w[2] = {b.w0, b.w1};
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      if (a_idx[i] == b_idx[j]) s += a_w[i] * b_w[j];
    }
  }
  return s;
}

}  // namespace wallcal::bench
