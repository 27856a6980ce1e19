// SPDX-License-Identifier: Apache-2.0
#pragma once
// The scanner's range model (Ye & Borenstein 2002; Okubo, Ye & Borenstein 2009:
// z = Int(n·y + c + ξ)) over the site's surfaces (sim/site_geometry.h). Internal to sim/.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "common/angles.h"
#include "sim/simulation_config.h"
#include "sim/site_geometry.h"
#include "io/types.h"

#include "sim/trajectory.h"

namespace wallcal::sim::detail {

// ---- Scanner model ----------------------------------------------------------------------------
// A footprint's two edges on one surface: one wall (seen obliquely) or the ground. Anything else
// with their ranges apart is a depth jump.
inline bool OneSurface(const Hit& a, const Hit& b) {
  if (a.surface == Surface::kGround) return b.surface == Surface::kGround;
  return a.wall_index >= 0 && a.wall_index == b.wall_index;
}

class ScannerModel {
 public:
  ScannerModel(const sim::SimulationConfig& config, const io::ScannerPreset& preset, uint64_t seed)
      : config_(config),
        preset_(preset),
        scene_(config),
        range_noise_(seed, Stream::kScanNoise),
        mixed_noise_(seed, Stream::kMixedPixel),
        cos_max_incidence_(std::cos(preset.max_incidence_rad)) {
    // Beam directions in the scanner frame, computed once: each scan then only rotates them
    // (the trigonometry per beam dominated the run time of hour-long sessions).
    const double half_rad = 0.4 * preset.angular_step_rad;
    for (int i = 0; i < preset.num_beams; ++i) {
      const double bearing_rad = preset.start_angle_rad + i * preset.angular_step_rad;
      beams_.push_back({Direction(bearing_rad), Direction(bearing_rad - half_rad),
                        Direction(bearing_rad + half_rad)});
    }
  }

  // A range offset added to every return of the following scans (warm-up drift, m).
  void set_drift_m(double drift_m) { drift_m_ = drift_m; }

  // Beams of the written scans whose return came from the ground (a 3-D site's yard).
  int64_t ground_returns() const { return ground_returns_; }

  io::ScanRecord Scan(const SimScannerPose& pose, double stamp_s) {
    io::ScanRecord scan;
    scan.stamp_s = stamp_s;
    scan.start_angle_rad = preset_.start_angle_rad;
    scan.angular_step_rad = preset_.angular_step_rad;
    scan.max_range_m = preset_.max_range_m;
    scan.ranges_m.resize(preset_.num_beams);
    const double c = std::cos(pose.yaw_enu_rad), s = std::sin(pose.yaw_enu_rad);
    // Level (the 2-D model's case): the beam turned by the scanner's yaw, z = 0; tilted: the
    // tilt first, then the yaw.
    const auto to_enu = [c, s, &pose](const Eigen::Vector2d& v) {
      if (!pose.tilted) return Eigen::Vector3d(c * v.x() - s * v.y(), s * v.x() + c * v.y(), 0.0);
      const Eigen::Vector3d t = pose.tilt * Eigen::Vector3d(v.x(), v.y(), 0.0);
      return Eigen::Vector3d(c * t.x() - s * t.y(), s * t.x() + c * t.y(), t.z());
    };
    for (int i = 0; i < preset_.num_beams; ++i) {
      const BeamDirections& b = beams_[i];
      scan.ranges_m[i] = static_cast<float>(
          Beam(pose.origin_enu_m, to_enu(b.centre), to_enu(b.lower), to_enu(b.upper)));
    }
    return scan;
  }

 private:
  enum class NoReturn { kNoEcho, kTooOblique, kOutOfRange };

  // What the scanner logs when nothing usable came back. SICK scanners report their maximum
  // range (Ye & Borenstein 2002); the URG reports an error code below 20 mm instead of a range (Okubo, Ye & Borenstein 2009).
  // The code values are this simulator's choice (1, 2, 3 mm): the tool only needs them to be
  // below error_codes_below_m. A preset with neither convention gets its maximum range.
  double NoReturnValue(NoReturn why) const {
    if (preset_.max_range_is_no_return) return preset_.max_range_m;
    const double code_m = why == NoReturn::kNoEcho       ? 0.001
                          : why == NoReturn::kTooOblique ? 0.002
                                                         : 0.003;
    if (code_m < preset_.error_codes_below_m) return code_m;
    if (preset_.error_codes_below_m > 0.0) return 0.0;
    return preset_.max_range_m;
  }

  double Quantise(double range_m) const {
    const double res = preset_.range_resolution_m;
    return res > 0.0 ? std::round(range_m / res) * res : range_m;
  }

  // One beam along `dir`; `lower`, `upper`: the edges of its footprint (±0.4 angular step).
  double Beam(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
              const Eigen::Vector3d& lower, const Eigen::Vector3d& upper) {
    const std::optional<Hit> hit = scene_.Cast(origin, dir);
    // One draw per beam whatever happens, so the noise of a beam does not depend on the others.
    const double xi_m = range_noise_.Normal(preset_.range_sigma_m);

    // Mixed pixels (Ye & Borenstein 2002 §4.5, Okubo, Ye & Borenstein 2009): a beam whose footprint straddles a depth jump
    // returns a range between the foreground and the background. Two sub-rays at ±0.4 of the
    // angular step stand in for the footprint's edges. A jump is two surfaces: both edges on
    // one wall is that wall seen obliquely (its edges' ranges differ by r·tan i·0.8 step, over
    // 0.1 m beyond about 37° at 8 m), whose return is the surface's, not a mixed one; so are
    // both edges on the ground.
    std::optional<double> true_range_m;
    if (config_.mixed_pixel_probability > 0.0) {
      const auto lo = scene_.Cast(origin, lower);
      const auto hi = scene_.Cast(origin, upper);
      if (lo && hi && !OneSurface(*lo, *hi) && std::abs(lo->range_m - hi->range_m) > 0.1) {
        const double u = mixed_noise_.Uniform();
        const double v = mixed_noise_.Uniform();
        if (u < config_.mixed_pixel_probability)
          true_range_m = lo->range_m + v * (hi->range_m - lo->range_m);
      }
    }
    bool from_ground = false;
    if (!true_range_m) {
      if (!hit) return NoReturnValue(NoReturn::kNoEcho);
      // Too oblique a surface sends too little light back (Okubo et al. 2009; Ye & Borenstein 2002: incidence limits).
      if (hit->cos_incidence < cos_max_incidence_) {
        return NoReturnValue(NoReturn::kTooOblique);
      }
      true_range_m = hit->range_m;
      from_ground = hit->surface == Surface::kGround;
    }
    if (*true_range_m >= preset_.max_range_m) return NoReturnValue(NoReturn::kOutOfRange);
    // Seeds 000/001 simulation model: z = Int(n·y + c + ξ), Int the range resolution.
    const double z_m =
        Quantise(preset_.sim_scale_n * *true_range_m + preset_.sim_offset_c_m + drift_m_ + xi_m);
    if (z_m >= preset_.max_range_m) return NoReturnValue(NoReturn::kOutOfRange);
    if (z_m < std::max(preset_.min_range_m, preset_.error_codes_below_m))
      return NoReturnValue(NoReturn::kNoEcho);
    ground_returns_ += from_ground;
    return z_m;
  }

  const sim::SimulationConfig& config_;
  const io::ScannerPreset& preset_;
  int64_t ground_returns_ = 0;
  Scene scene_;
  Noise range_noise_;
  Noise mixed_noise_;
  double cos_max_incidence_;
  double drift_m_ = 0.0;
  struct BeamDirections {
    Eigen::Vector2d centre, lower, upper;  // unit vectors in the scanner frame
  };
  std::vector<BeamDirections> beams_;
};


}  // namespace wallcal::sim::detail
