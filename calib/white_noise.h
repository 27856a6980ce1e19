// SPDX-License-Identifier: Apache-2.0
#pragma once
// The pose streams' white noise, measured where the vehicle stands still. A standing scan
// hardly depends on it (a dwell averages many samples), but a moving scan carries one
// interpolated pose, so a configured σ above the sensors' own inflates the σ of a session with
// drives in it (docs/method.md, "Noise measured at the stops and on the drives"). Where the
// stops are too short, calib/drive_white_noise.h measures it on the drives.

#include <vector>

#include <Eigen/Core>

#include "calib/time_alignment.h"

namespace wallcal::calib {

struct MeasuredWhiteNoise {
  // 1σ of one heading sample (rad): the scatter of the yaw samples about their dwell's mean,
  // pooled over the dwells (Σ squared deviations / Σ (n − 1)). 0 when the dwells hold fewer than
  // kMinWhiteNoiseDegreesOfFreedom.
  double heading_sigma_rad = 0.0;
  int heading_degrees_of_freedom = 0;  // Σ (n − 1) over the dwells
  // 1σ per axis of one GNSS position (m): the scatter of each dwell's positions about a straight
  // line in time per axis (the RTK error's slow drift over the dwell taken out), pooled over the
  // dwells and both axes (Σ squared residuals / Σ 2(n − 2)). 0 below the minimum.
  double gnss_white_sigma_m = 0.0;
  int gnss_degrees_of_freedom = 0;
};

// Degrees of freedom needed for an estimate: its relative standard error is about 1/√(2·dof)
// for white noise, 7 % at 100.
inline constexpr int kMinWhiteNoiseDegreesOfFreedom = 100;

// The scatter about each dwell's mean rather than successive differences: a heading sensor that
// filters its output has errors correlated over a few samples, which differences would miss;
// the heading drift (0.5°/h) moves a 5 s dwell by 0.0007°, far below the white noise.
MeasuredWhiteNoise MeasureWhiteNoise(const std::vector<PositionSample>& positions,
                                     const std::vector<YawSample>& yaws,
                                     const std::vector<Dwell>& dwells);

}  // namespace wallcal::calib
