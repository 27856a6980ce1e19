// SPDX-License-Identifier: Apache-2.0
#include "calib/pose_samples.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace wallcal::calib {

std::vector<PositionSample> PositionSamples(const io::NmeaLog& gnss, int min_fix_quality,
                                            const LocalFrame& frame,
                                            std::vector<const io::GnssFix*>* used) {
  std::vector<PositionSample> positions;
  for (const io::GnssFix& fix : gnss.fixes) {
    if (!io::FixQualityAccepted(fix.quality, min_fix_quality)) continue;
    if (!positions.empty() && fix.stamp_s <= positions.back().stamp_s) continue;
    PositionSample sample;
    sample.stamp_s = fix.stamp_s;
    sample.p_local_m = ToLocal(frame, fix.lat_deg, fix.lon_deg);
    const bool has_gst = std::isfinite(fix.sigma_lat_m) && std::isfinite(fix.sigma_lon_m);
    sample.sigma_m = has_gst ? std::max(fix.sigma_lat_m, fix.sigma_lon_m) : 0.0;
    positions.push_back(sample);
    if (used != nullptr) used->push_back(&fix);
  }
  return positions;
}

std::vector<YawSample> YawSamples(const io::NmeaLog& headings, io::HeadingReference reference,
                                  const LocalFrame& frame,
                                  const std::vector<const io::GnssFix*>& used) {
  std::vector<YawSample> yaws;
  for (const io::HeadingSample& heading : headings.headings) {
    if (!yaws.empty() && heading.stamp_s <= yaws.back().stamp_s) continue;
    YawSample sample;
    sample.stamp_s = heading.stamp_s;
    if (reference == io::HeadingReference::kGridNorth) {
      sample.yaw_rad = YawFromHeading(heading.heading_rad);
    } else {
      assert(!used.empty());
      // Convergence at the vehicle: take the nearest used fix in time.
      const auto it = std::lower_bound(
          used.begin(), used.end(), heading.stamp_s,
          [](const io::GnssFix* fix, double t) { return fix->stamp_s < t; });
      const io::GnssFix* nearest = it == used.end() ? used.back() : *it;
      if (it != used.begin() && it != used.end() &&
          heading.stamp_s - (*(it - 1))->stamp_s < (*it)->stamp_s - heading.stamp_s) {
        nearest = *(it - 1);
      }
      sample.yaw_rad =
          YawFromTrueHeading(frame, heading.heading_rad, nearest->lat_deg, nearest->lon_deg);
    }
    yaws.push_back(sample);
  }
  return yaws;
}

}  // namespace wallcal::calib
