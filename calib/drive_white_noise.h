// SPDX-License-Identifier: Apache-2.0
#pragma once
// The pose streams' white noise, measured while the vehicle drives: for sessions whose stops are
// too short to hold kMinWhiteNoiseDegreesOfFreedom (calib/white_noise.h), the high-frequency
// part of the fixes and headings about the smooth trajectory the vehicle drove
// (docs/method.md, "Noise measured at the stops and on the drives").
//
// The method, per stream (GNSS: east and north; heading: the unwrapped yaw):
// - The samples outside the dwells are split into runs of consecutive samples, a run ending at a
//   gap longer than kDriveMaxGapIntervals times the stream's median sample interval (a lost
//   sentence or two stays inside a run; an outage does not).
// - Each run is cut into non-overlapping windows of kDriveWindowSamples samples (the remainder
//   of a run is left out, so that every window's estimate has the same distribution), and a
//   polynomial of degree kDriveFitDegree in time is fitted to each axis of each window.
//   Why a cubic over 11 samples (1 s of 10 Hz fixes, 0.5 s of 20 Hz headings): a quadratic
//   leaves a drive's jerk in the residuals (on the simulator's benchmark drives at 0.6–0.8 m/s,
//   1.7–2.0 mm RMS beside a 3 mm white noise: σ 17–21 % high), a cubic leaves its fourth derivative
//   (below 0.1 mm), and of a step of the acceleration Δa (a stop starting) on average
//   0.2·Δa·Δt² RMS against a quadratic's 0.6. The RTK error's slow wander (a Gauss–Markov
//   process, 15 mm over 60 s: 0.9 mm per 0.1 s step) adds 0.48 of one step's variance per
//   degree of freedom after a cubic over 11 samples, about 4 % of a 3 mm white noise's variance
//   (2 % in σ); shorter windows would take out more of it and of the steps but keep fewer
//   degrees of freedom (7 of 11 here, 5 of 9), longer ones more of both.
// - Where the motion is not smooth inside a window (a stop starting or ending, a turn starting:
//   the acceleration steps), its residuals hold more than the noise. Each window's variance
//   estimate (its residual sum of squares over its degrees of freedom) is compared with the
//   median window's; windows beyond kDriveWindowRejectRatio times the median are dropped and
//   counted. The rest are pooled: Σ squared residuals / Σ degrees of freedom, divided by the
//   fraction of a χ² variance that the cut keeps for white noise (so that white noise alone
//   gives an unbiased variance: with the headings' 7 degrees of freedom a window of pure noise
//   is beyond 3× the median once in 120 and the cut takes 1.7 % of the variance, with the
//   fixes' 14 once in 4 000).
// Unlike the stops' scatter over a whole dwell, this measure does not see errors correlated over
// longer than a window (about 1 s): those are the RTK error's slow part, which the solver
// models as its GNSS bias. Stamp jitter left in the fixes' stamps (calibrate puts each fix at
// its GGA epoch mapped onto the logger clock where it can, docs/time-alignment.md) counts as
// white noise of speed × jitter: it is noise at the fixes, as a moving scan sees it.

#include <vector>

#include "calib/time_alignment.h"

namespace wallcal::calib {

inline constexpr int kDriveWindowSamples = 11;
inline constexpr int kDriveFitDegree = 3;
inline constexpr double kDriveWindowRejectRatio = 3.0;
inline constexpr double kDriveMaxGapIntervals = 2.5;

struct DriveWhiteNoise {
  // 1σ per axis of one GNSS position (m), pooled over the kept windows and both axes. 0 when
  // they hold fewer than kMinWhiteNoiseDegreesOfFreedom.
  double gnss_white_sigma_m = 0.0;
  int gnss_degrees_of_freedom = 0;  // of the kept windows: 2 (kDriveWindowSamples − 4) each
  int gnss_windows_used = 0;
  int gnss_windows_dropped = 0;  // beyond kDriveWindowRejectRatio × the median window's variance
  // 1σ of one heading sample (rad), likewise; 0 below the minimum.
  double heading_sigma_rad = 0.0;
  int heading_degrees_of_freedom = 0;  // kDriveWindowSamples − 4 per kept window
  int heading_windows_used = 0;
  int heading_windows_dropped = 0;
};

// `positions` and `yaws` in time order (as PositionSamples and YawSamples give them); the
// samples within a dwell ([start_s, end_s] of any of `dwells`) are left out.
DriveWhiteNoise MeasureDriveWhiteNoise(const std::vector<PositionSample>& positions,
                                       const std::vector<YawSample>& yaws,
                                       const std::vector<Dwell>& dwells);

}  // namespace wallcal::calib
