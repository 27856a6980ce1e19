// SPDX-License-Identifier: Apache-2.0
#pragma once
// A scan's own geometry against the scanner preset. A recording's LaserScan message and a
// CARMEN line carry the geometry their driver reports: the beam count, the step between beams
// and the range limit. The preset describes the scanner family: its range model, noise and
// limits. A driver's geometry within the family's limits is taken from the data (each scan's
// bearings come from its own start angle and step); outside them the scans come from another
// scanner, and the preset does not apply.
//
// The family's limits:
//   - the step between beams equals the preset's within kStepTolerance (relative): the
//     angular resolution is the scanner's, a driver does not change it;
//   - the beam count is within BeamSlack(preset) of the preset's (a driver drops or adds a beam
//     at an end of the field: a URG-04LX driver reports 681 of 682), so the field of view
//     agrees to a few steps (a 180° field is not a 240° one);
//   - the range limit the driver reports (0: unknown, accepted) is at most
//     kDriverRangeFactor times the preset's max_range_m (a URG-04LX driver reports 5.6 m where
//     the datasheet promises 4.095 m) and above the preset's min_range_m.

#include <cstdint>
#include <string>

#include "io/types.h"

namespace wallcal::io {

inline constexpr double kStepTolerance = 0.005;
inline constexpr double kDriverRangeFactor = 1.5;
// The beams a driver may differ by: 1 % of the preset's count, at least 2.
int BeamSlack(const ScannerPreset& preset);
// True when `beams` is within BeamSlack(preset) of the preset's count (cheap: for every scan).
bool BeamCountFits(int64_t beams, const ScannerPreset& preset);

enum class GeometryFit {
  kAsPreset,      // beams, step and range limit as the preset's
  kFromData,      // within the family's limits: the data's geometry is used
  kOtherScanner,  // outside them: another scanner
};

struct GeometryCheck {
  GeometryFit fit = GeometryFit::kAsPreset;
  // kFromData: what was taken from the data ("681 beams (preset 682), range_max 5.600 m
  // (preset 4.095 m)"); kOtherScanner: the difference, naming both sides. Empty for kAsPreset.
  std::string what;
};

// beams: the scan's beam count; step_rad: its step (sign ignored); range_max_m: the range limit
// the scan reports (0: unknown).
GeometryCheck CheckScanGeometry(int64_t beams, double step_rad, double range_max_m,
                                const ScannerPreset& preset);

}  // namespace wallcal::io
