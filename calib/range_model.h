// SPDX-License-Identifier: Apache-2.0
#pragma once
// The scanner's range model: one logged scan (raw ranges, error codes and no-returns still in
// place) -> corrected points in the scanner frame, ready for the wall detector.
//
// Frame: scanner frame, x = bearing 0 (the scanner's forward beam), y left, bearings
// counter-clockwise positive (radians). Lengths in metres.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "io/types.h"

namespace wallcal::calib {

// The valid returns of one scan, in beam order. All vectors have the same length.
struct ScanPoints {
  std::vector<Eigen::Vector2d> p_scanner_m;  // corrected points in the scanner frame
  std::vector<float> range_m;                // corrected range
  std::vector<float> bearing_rad;            // beam bearing (ccw from scanner x)
  std::vector<int> beam;                     // beam index in the scan
  // 1: next to a range jump (possible mixed pixel, Ye & Borenstein 2002 §4.5; Okubo et al. 2009); see ToScanPoints.
  std::vector<uint8_t> mixed_suspect;
};

// Readings by fate. ToScanPoints adds to these (never resets them), so one struct can total a
// whole log. non_finite also counts negative readings.
struct RangeCounts {
  int64_t valid = 0, error_code = 0, no_return = 0, too_close = 0, non_finite = 0;

  RangeCounts& operator+=(const RangeCounts& other) {
    valid += other.valid;
    error_code += other.error_code;
    no_return += other.no_return;
    too_close += other.too_close;
    non_finite += other.non_finite;
    return *this;
  }
};

// Turns one scan into points. Beam i has bearing scan.start_angle_rad + i·scan.angular_step_rad
// (the log's own geometry, not the preset's). A raw reading is dropped and counted, first match
// wins:
//   non_finite  NaN, ±inf, or negative;
//   error_code  raw < preset.error_codes_below_m (e.g. URG-04LX codes below 20 mm, Okubo, Ye & Borenstein 2009);
//   no_return   raw >= preset.max_range_m when preset.max_range_is_no_return (SICK reports "no
//               echo" as its maximum), or raw >= scan.max_range_m when that is > 0;
//   too_close   raw < preset.min_range_m (the sensor's own floor), or the corrected range
//               < min_range_m (vehicle body, mud on the window), or a corrected range <= 0.
// Thresholds are compared with the raw reading in float precision (the log's precision).
// A valid reading is corrected as r = preset.range_scale_k · raw + preset.range_offset_b_m
// (Ye & Borenstein 2002; Okubo, Ye & Borenstein 2009, "ŷ = k·μ + b").
//
// mixed_suspect (Ye & Borenstein 2002 §4.5; Okubo et al. 2009: at a depth edge a beam may return a range between the
// foreground and the background): a point is flagged when a neighbouring beam is invalid (any
// reason above), or when the range step to a neighbour is a depth jump. A step
// d = r_{i+1} − r_i is a jump when |d| > mixed_jump_m and it is not the continuation of a smooth
// surface, i.e. it differs by more than mixed_jump_m from an adjacent step (r_i − r_{i−1} or
// r_{i+2} − r_{i+1}, where those beams are valid). Without the trend test a flat wall seen at
// high incidence (range steps of ~0.15 m per degree at 8 m and 40°) would be flagged entirely.
// Both points of a jump are flagged. The first and last beams have no neighbour on one side;
// that side flags nothing.
//
// counts may be null. Never throws.
ScanPoints ToScanPoints(const io::ScanRecord& scan, const io::ScannerPreset& preset,
                        double min_range_m, double mixed_jump_m, RangeCounts* counts);
// The same into *points, reusing its storage (a pass converts every scan into one per thread).
// The beams' sines and cosines are computed once per scan geometry and thread.
void FillScanPoints(const io::ScanRecord& scan, const io::ScannerPreset& preset,
                    double min_range_m, double mixed_jump_m, RangeCounts* counts,
                    ScanPoints* points);
// Only the counts: adds the scan's readings by fate to *counts, as FillScanPoints does.
void CountReadings(const io::ScanRecord& scan, const io::ScannerPreset& preset,
                   double min_range_m, RangeCounts* counts);

}  // namespace wallcal::calib
