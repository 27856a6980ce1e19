// SPDX-License-Identifier: Apache-2.0
#include "calib/range_model.h"

#include <algorithm>
#include <cmath>

namespace wallcal::calib {
namespace {

enum class Fate { kValid, kNonFinite, kErrorCode, kNoReturn, kTooClose };

// Raw readings are floats as logged, while thresholds come from text as doubles: compare in
// float, or a logged 8.183 (8.18299961f) would slip under an 8.183 maximum and a logged 0.020
// under the URG's 20 mm error-code limit.
Fate Classify(float raw_m, double corrected_m, const io::ScanRecord& scan,
              const io::ScannerPreset& preset, double min_range_m) {
  if (!std::isfinite(raw_m) || raw_m < 0.0f) return Fate::kNonFinite;
  // Error codes are sensor words, not distances: test the raw value before any correction.
  if (raw_m < static_cast<float>(preset.error_codes_below_m)) return Fate::kErrorCode;
  if (preset.max_range_is_no_return && preset.max_range_m > 0.0 &&
      raw_m >= static_cast<float>(preset.max_range_m)) {
    return Fate::kNoReturn;
  }
  if (scan.max_range_m > 0.0 && raw_m >= static_cast<float>(scan.max_range_m)) {
    return Fate::kNoReturn;
  }
  // The preset's floor is the sensor's (raw); the option's is physical (corrected).
  if (raw_m < static_cast<float>(preset.min_range_m) || corrected_m < min_range_m ||
      corrected_m <= 0.0) {
    return Fate::kTooClose;
  }
  return Fate::kValid;
}

// The counter of `fate` in *counts.
int64_t& Counter(Fate fate, RangeCounts* counts) {
  switch (fate) {
    case Fate::kNonFinite: return counts->non_finite;
    case Fate::kErrorCode: return counts->error_code;
    case Fate::kNoReturn: return counts->no_return;
    case Fate::kTooClose: return counts->too_close;
    case Fate::kValid: break;
  }
  return counts->valid;
}

void CountFate(Fate fate, RangeCounts* counts) { ++Counter(fate, counts); }

}  // namespace

namespace {

// The beams' cosines and sines for one scan geometry, computed once per thread while the
// geometry stays the same (every scan of a log, as a rule): bit-identical to computing them
// per scan.
struct BearingTable {
  int n = -1;
  double start_rad = 0.0, step_rad = 0.0;
  std::vector<double> cos, sin;

  void For(const io::ScanRecord& scan) {
    const int beams = static_cast<int>(scan.ranges_m.size());
    if (beams == n && scan.start_angle_rad == start_rad && scan.angular_step_rad == step_rad) {
      return;
    }
    n = beams;
    start_rad = scan.start_angle_rad;
    step_rad = scan.angular_step_rad;
    cos.resize(static_cast<size_t>(n));
    sin.resize(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
      const double bearing = scan.start_angle_rad + i * scan.angular_step_rad;
      cos[static_cast<size_t>(i)] = std::cos(bearing);
      sin[static_cast<size_t>(i)] = std::sin(bearing);
    }
  }
};

}  // namespace

void CountReadings(const io::ScanRecord& scan, const io::ScannerPreset& preset,
                   double min_range_m, RangeCounts* counts) {
  for (const float raw : scan.ranges_m) {
    const double corrected = preset.range_scale_k * double(raw) + preset.range_offset_b_m;
    CountFate(Classify(raw, corrected, scan, preset, min_range_m), counts);
  }
}

ScanPoints ToScanPoints(const io::ScanRecord& scan, const io::ScannerPreset& preset,
                        double min_range_m, double mixed_jump_m, RangeCounts* counts) {
  ScanPoints out;
  FillScanPoints(scan, preset, min_range_m, mixed_jump_m, counts, &out);
  return out;
}

void FillScanPoints(const io::ScanRecord& scan, const io::ScannerPreset& preset,
                    double min_range_m, double mixed_jump_m, RangeCounts* counts,
                    ScanPoints* points) {
  const int n = static_cast<int>(scan.ranges_m.size());
  thread_local std::vector<double> r;
  thread_local std::vector<uint8_t> valid;
  thread_local BearingTable bearings;
  r.assign(static_cast<size_t>(n), 0.0);
  valid.assign(static_cast<size_t>(n), 0);
  bearings.For(scan);
  RangeCounts local;
  for (int i = 0; i < n; ++i) {
    const float raw = scan.ranges_m[i];
    const double corrected = preset.range_scale_k * double(raw) + preset.range_offset_b_m;
    const Fate fate = Classify(raw, corrected, scan, preset, min_range_m);
    CountFate(fate, &local);
    if (fate == Fate::kValid) {
      valid[i] = 1;
      r[i] = corrected;
    }
  }
  if (counts != nullptr) {
    counts->valid += local.valid;
    counts->error_code += local.error_code;
    counts->no_return += local.no_return;
    counts->too_close += local.too_close;
    counts->non_finite += local.non_finite;
  }

  // step_ok(i): beams i and i+1 are both valid, so the step r[i+1] − r[i] is defined.
  auto step_ok = [&](int i) { return i >= 0 && i + 1 < n && valid[i] && valid[i + 1]; };
  auto step = [&](int i) { return r[i + 1] - r[i]; };
  // A depth jump between beams i and i+1 (both valid): a large step that is not the
  // continuation of its neighbouring steps. On a plane the step changes by the range's second
  // difference (ρ(1 + sin²φ)/cos³φ · Δ², 3 cm at 8 m, 60°, 1° beams), far below a depth edge.
  auto is_jump = [&](int i) {
    const double d = step(i);
    if (std::abs(d) <= mixed_jump_m) return false;
    bool has_neighbour = false;
    for (int j : {i - 1, i + 1}) {
      if (!step_ok(j)) continue;
      has_neighbour = true;
      if (std::abs(step(j) - d) > mixed_jump_m) return true;
    }
    return !has_neighbour;
  };

  // jump[i]: a depth jump between beams i and i+1 (both valid), each step judged once.
  thread_local std::vector<uint8_t> jump;
  jump.assign(static_cast<size_t>(std::max(n, 1)), 0);
  for (int i = 0; i + 1 < n; ++i) jump[i] = step_ok(i) && is_jump(i);

  // Written by index into vectors sized once: no capacity test per point.
  ScanPoints& out = *points;
  const size_t count = static_cast<size_t>(local.valid);
  out.p_scanner_m.resize(count);
  out.range_m.resize(count);
  out.bearing_rad.resize(count);
  out.beam.resize(count);
  out.mixed_suspect.resize(count);
  size_t k = 0;
  for (int i = 0; i < n; ++i) {
    if (!valid[i]) continue;
    const bool suspect = (i > 0 && (!valid[i - 1] || jump[i - 1])) ||
                         (i + 1 < n && (!valid[i + 1] || jump[i]));
    const double bearing = scan.start_angle_rad + i * scan.angular_step_rad;
    out.p_scanner_m[k] = Eigen::Vector2d(r[i] * bearings.cos[i], r[i] * bearings.sin[i]);
    out.range_m[k] = static_cast<float>(r[i]);
    out.bearing_rad[k] = static_cast<float>(bearing);
    out.beam[k] = i;
    out.mixed_suspect[k] = suspect ? 1 : 0;
    ++k;
  }
}

}  // namespace wallcal::calib
