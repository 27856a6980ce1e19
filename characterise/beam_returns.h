// SPDX-License-Identifier: Apache-2.0
#pragma once
// Every beam of the standing scans paired with the surveyed wall it should hit: the true range
// from the station's pose, the mount and the wall line (calib/observation.h frames). Internal to
// characterise/.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "calib/observation.h"
#include "io/types.h"
#include "pipeline/calibration.h"

namespace wallcal::characterise {

// One station (a dwell): the vehicle's pose there, the mean of its scans' poses (the vehicle
// stood still, so one pose serves them all and no per-scan GNSS jitter enters the ranges).
struct StationPose {
  Eigen::Vector2d antenna_local_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;     // vehicle yaw (ccw from grid east), heading drift removed
  double time_s = 0.0;      // middle of the dwell, s since the first used scan
  double gnss_sigma_m = 0.0;  // per-axis 1σ of its position (GST or the options' default)
  double dwell_s = 0.0;       // first to last used scan of the station
};

enum class BeamKind : uint8_t {
  kOnWall,   // the beam's centre meets the wall at least a footprint from its ends
  kEdge,     // the centre meets the wall, the footprint straddles an end of the surveyed wall
};

struct BeamReturn {
  float z_m = 0.0f;          // raw reading (NaN: no valid reading: error code / no return)
  float bearing_rad = 0.0f;  // in the scanner frame
  float time_s = 0.0f;       // since the first used scan
  int32_t station = 0;       // into the StationPose vector
  int32_t scan = 0;          // 0-based scan number in the log (a scan's beams are contiguous)
  int16_t wall = 0;          // into the walls
  BeamKind kind = BeamKind::kOnWall;
  bool near_wall = false;    // a valid reading within the gate of the predicted wall range
};

struct BeamSet {
  std::vector<StationPose> stations;
  std::vector<BeamReturn> beams;
  double span_s = 0.0;  // first to last used scan
};

// Scanner origin and beam direction at a station for a mount (local frame).
struct Ray {
  Eigen::Vector2d origin, direction;
};
Ray BeamRay(const StationPose& station, const calib::Mount& mount, double bearing_rad);
// Range along `ray` to the wall line (NaN when it runs parallel or away), the incidence
// (angle to the wall normal, rad) and the along-wall position of the hit from end_a (m).
struct WallHit {
  double range_m, incidence_rad, along_m;
};
WallHit HitWall(const Ray& ray, const calib::WallGeometry& wall);

// Reads the scans again and collects the beams of the scans that gave a standing observation.
// `mount` is the start mount. Gate: |k·z + b − true| < 0.25 m + 3 % of the true range (the
// preset's correction; the fit then gates at 4σ). Throws io::InputError as the scan readers do.
BeamSet CollectBeams(const pipeline::CalibrationResult& calibration, const calib::Mount& mount);

}  // namespace wallcal::characterise
