// SPDX-License-Identifier: Apache-2.0
// Beams paired with their true ranges (characterise/beam_returns.h).

#include "characterise/beam_returns.h"

#include <cmath>
#include <limits>
#include <map>
#include <memory>

#include "common/angles.h"
#include "common/circular.h"
#include "io/scan_source.h"
#include "recording/recording_streams.h"

namespace wallcal::characterise {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The raw reading when it is a range (range_model.h's rules), NaN for an error code, a
// no-return or a reading below the sensor's floor.
double ValidReading(float raw, const io::ScanRecord& scan, const io::ScannerPreset& preset) {
  const double z = raw;
  if (!std::isfinite(z) || z < 0.0) return kNaN;
  if (z < preset.error_codes_below_m) return kNaN;
  if (preset.max_range_is_no_return && z >= static_cast<float>(preset.max_range_m)) return kNaN;
  if (scan.max_range_m > 0.0 && z >= static_cast<float>(scan.max_range_m)) return kNaN;
  if (z < preset.min_range_m || z <= 0.0) return kNaN;
  return z;
}

}  // namespace

Ray BeamRay(const StationPose& station, const calib::Mount& mount, double bearing_rad) {
  const double c = std::cos(station.yaw_rad), s = std::sin(station.yaw_rad);
  const Eigen::Vector2d origin =
      station.antenna_local_m + Eigen::Vector2d(c * mount.x_m - s * mount.y_m,
                                                s * mount.x_m + c * mount.y_m);
  const double a = station.yaw_rad + mount.yaw_rad + bearing_rad;
  return {origin, Eigen::Vector2d(std::cos(a), std::sin(a))};
}

WallHit HitWall(const Ray& ray, const calib::WallGeometry& wall) {
  const double cos_in = wall.normal_local.dot(ray.direction);
  const double range_m =
      std::abs(cos_in) < 1e-9 ? kNaN : (wall.offset_m - wall.normal_local.dot(ray.origin)) / cos_in;
  if (!(range_m > 0.0)) return {kNaN, kNaN, kNaN};
  const Eigen::Vector2d span = wall.end_b_local - wall.end_a_local;
  const double length_m = span.norm();
  const Eigen::Vector2d hit = ray.origin + range_m * ray.direction;
  const double along_m = length_m > 0.0 ? (hit - wall.end_a_local).dot(span / length_m) : kNaN;
  return {range_m, std::acos(std::min(1.0, std::abs(cos_in))), along_m};
}

BeamSet CollectBeams(const pipeline::CalibrationResult& calibration, const calib::Mount& mount) {
  const io::ScannerPreset& preset = calibration.loaded.preset;
  const solvers::MountEstimate& estimate = calibration.solve.estimate;
  BeamSet set;

  // Stations: the dwells with standing observations, their mean pose. Scans → station.
  std::map<int, int> station_of_segment;
  std::map<int, std::pair<int, double>> scan_station;  // scan index -> (station, stamp)
  struct Sum {
    Eigen::Vector2d p = Eigen::Vector2d::Zero();
    std::vector<double> yaws;
    double dwell_yaw = 0.0;
    int dwell_samples = 0;
    double t0 = 0.0, t1 = 0.0, sigma = 0.0;
    int n = 0;
  };
  std::vector<Sum> sums;
  double first_s = std::numeric_limits<double>::infinity(), last_s = -first_s;
  for (const calib::WallObservation& o : calibration.solve.observations) {
    if (!o.pose.stationary || o.pose.segment < 0) continue;
    auto [it, added] = station_of_segment.emplace(o.pose.segment, static_cast<int>(sums.size()));
    if (added) sums.push_back(Sum{});
    Sum& sum = sums[it->second];
    // The pose the heading sensor's drift is removed from (true yaw = used − r·(t − t_ref)).
    const double drift_rad = estimate.heading_drift_estimated
                                 ? estimate.heading_drift_rad_per_s *
                                       (o.pose.stamp_s - estimate.heading_reference_s)
                                 : 0.0;
    if (sum.n == 0) sum.t0 = o.pose.stamp_s;
    sum.t1 = o.pose.stamp_s;
    sum.p += o.pose.antenna_local_m;
    sum.yaws.push_back(o.pose.yaw_rad - drift_rad);
    if (o.pose.dwell_yaw_samples > 0) {
      sum.dwell_yaw = o.pose.dwell_yaw_rad - drift_rad;
      sum.dwell_samples = o.pose.dwell_yaw_samples;
    }
    sum.sigma += o.pose.gnss_sigma_m;
    ++sum.n;
    scan_station[o.scan_index] = {it->second, o.pose.stamp_s};
    first_s = std::min(first_s, o.pose.stamp_s);
    last_s = std::max(last_s, o.pose.stamp_s);
  }
  if (sums.empty()) return set;
  set.span_s = last_s - first_s;
  for (const Sum& sum : sums) {
    StationPose station;
    station.antenna_local_m = sum.p / sum.n;
    station.yaw_rad = sum.dwell_samples > 0 ? sum.dwell_yaw : CircularMean(sum.yaws);
    station.time_s = 0.5 * (sum.t0 + sum.t1) - first_s;
    station.dwell_s = sum.t1 - sum.t0;
    const double sigma = sum.sigma / sum.n;
    station.gnss_sigma_m = sigma > 0.0 && calibration.loaded.options.solver.use_gst_sigma
                               ? sigma
                               : std::hypot(calibration.loaded.options.solver.gnss_bias_sigma_m,
                                            calibration.SolverInUse().gnss_white_sigma_m);
    set.stations.push_back(station);
  }

  // The scans again, in file order: the index is the detection pass's scan_index.
  const recording::ScanOpener open =
      recording::MakeScanOpener(calibration.loaded.session, &calibration.loaded.preset);
  std::unique_ptr<io::ScanSource> source = open();
  io::ScanRecord scan;
  int index = -1;
  const double half_step = 0.5 * std::abs(preset.angular_step_rad);
  while (source->Next(&scan)) {
    ++index;
    const auto found = scan_station.find(index);
    if (found == scan_station.end()) continue;
    const StationPose& station = set.stations[found->second.first];
    const float time_s = static_cast<float>(found->second.second - first_s);
    for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
      const double bearing = scan.start_angle_rad + static_cast<double>(i) * scan.angular_step_rad;
      const Ray ray = BeamRay(station, mount, bearing);
      // The nearest surveyed wall this beam meets within (or straddling) its surveyed extent.
      int best = -1;
      WallHit best_hit{kNaN, kNaN, kNaN};
      BeamKind kind = BeamKind::kOnWall;
      for (size_t w = 0; w < calibration.survey.walls.size(); ++w) {
        const calib::WallGeometry& wall = calibration.survey.walls[w];
        const WallHit hit = HitWall(ray, wall);
        if (!std::isfinite(hit.range_m) || hit.range_m >= preset.max_range_m) continue;
        const double length_m = (wall.end_b_local - wall.end_a_local).norm();
        // The footprint's half-width along the wall (at least 5 cm).
        const double half_m =
            std::max(0.05, hit.range_m * half_step / std::max(0.05, std::cos(hit.incidence_rad)));
        BeamKind this_kind;
        if (hit.along_m >= half_m + 0.2 && hit.along_m <= length_m - half_m - 0.2) {
          this_kind = BeamKind::kOnWall;
        } else if ((hit.along_m >= 0.0 && hit.along_m < half_m) ||
                   (hit.along_m <= length_m && hit.along_m > length_m - half_m)) {
          // The centre meets the wall, the footprint's edge the space beyond its end.
          this_kind = BeamKind::kEdge;
        } else {
          continue;
        }
        if (best < 0 || hit.range_m < best_hit.range_m) {
          best = static_cast<int>(w);
          best_hit = hit;
          kind = this_kind;
        }
      }
      if (best < 0) continue;
      BeamReturn beam;
      const double z = ValidReading(scan.ranges_m[i], scan, preset);
      beam.z_m = static_cast<float>(z);
      beam.bearing_rad = static_cast<float>(bearing);
      beam.time_s = time_s;
      beam.station = found->second.first;
      beam.scan = index;
      beam.wall = static_cast<int16_t>(best);
      beam.kind = kind;
      beam.near_wall =
          std::isfinite(z) && std::abs(preset.range_scale_k * z + preset.range_offset_b_m -
                                       best_hit.range_m) < 0.25 + 0.03 * best_hit.range_m;
      set.beams.push_back(beam);
    }
  }
  return set;
}

}  // namespace wallcal::characterise
