// SPDX-License-Identifier: Apache-2.0
#pragma once
// GNSS fixes and headings as the pose interpolator's samples (calib/time_alignment.h): fixes of
// accepted quality as local positions, headings as vehicle yaws in the local frame.

#include <vector>

#include "calib/geodesy.h"
#include "calib/time_alignment.h"
#include "io/types.h"

namespace wallcal::calib {

// The GNSS fixes calibrate uses, as local positions: qualities gnss.min_fix_quality accepts,
// strictly increasing in time, σ from GST (0 without). `used` (may be null) receives the fix of
// each sample, in the same order.
std::vector<PositionSample> PositionSamples(const io::NmeaLog& gnss, int min_fix_quality,
                                            const LocalFrame& frame,
                                            std::vector<const io::GnssFix*>* used);

// The headings as vehicle yaws in the local frame (strictly increasing in time). True headings
// are turned into grid headings with the meridian convergence at the vehicle: at the used fix
// nearest in time (`used` must not be empty then). Grid headings are taken as they are.
std::vector<YawSample> YawSamples(const io::NmeaLog& headings, io::HeadingReference reference,
                                  const LocalFrame& frame,
                                  const std::vector<const io::GnssFix*>& used);

}  // namespace wallcal::calib
