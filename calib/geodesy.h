// SPDX-License-Identifier: Apache-2.0
#pragma once
// WGS84 <-> UTM and the session's local ground frame (see LocalFrame in calib/observation.h).
//
// Angles: geodetic latitude/longitude in degrees (as the logs and GeographicLib give them);
// every other angle in radians. Headings are clockwise from north; yaws are counter-clockwise
// from grid east. Lengths in metres: "grid" metres on the UTM projection plane, "ground" metres
// on the ellipsoid (grid = ground × point scale k).

#include <Eigen/Core>
#include <optional>

#include "calib/observation.h"
#include "io/types.h"

namespace wallcal::calib {

struct UtmPoint {
  double easting_m = 0, northing_m = 0;  // grid metres (false easting 500 km; +10 000 km south)
  int zone = 0;                          // 1..60
  bool north = true;                     // hemisphere of the northing's false origin
  // γ: the bearing of grid north clockwise from true north at the point (GeographicLib's gamma),
  // radians. Positive east of the central meridian in the northern hemisphere.
  double convergence_rad = 0;
  double scale_k = 1;  // point scale: grid distance per ground distance (0.9996 on the meridian)
};

// WGS84 -> UTM. zone: force this zone and hemisphere (a point in a neighbouring zone is
// projected into it, as the whole session shares one grid); nullopt: the point's own standard
// zone (Norway/Svalbard exceptions included) and hemisphere.
// Throws io::InputError on non-finite input, on latitudes outside UTM (above 84° N or below
// 80° S), on a forced zone outside 1..60, or on a point more than 15° of longitude from the
// forced zone's central meridian (not a neighbouring zone: the projection is meaningless there).
UtmPoint ToUtm(double lat_deg, double lon_deg, std::optional<io::UtmZone> zone = std::nullopt);

// UTM -> WGS84 (lat in [-90, 90], lon in [-180, 180] degrees). Throws io::InputError on a zone
// outside 1..60.
void FromUtm(const io::UtmZone& zone, double easting_m, double northing_m, double* lat_deg,
             double* lon_deg);

// The session's local ground frame: origin at (lat0, lon0), UTM zone `zone` (nullopt: the
// origin's standard zone), p_local = (p_utm - origin_utm) / k0 with k0 the point scale at the
// origin. Throws io::InputError as ToUtm.
LocalFrame MakeLocalFrame(double lat0_deg, double lon0_deg, std::optional<io::UtmZone> zone);

// A WGS84 point in the local frame: ground metres, x = grid east, y = grid north.
// Throws io::InputError as ToUtm.
Eigen::Vector2d ToLocal(const LocalFrame& frame, double lat_deg, double lon_deg);

// True heading (rad, clockwise from true north) of the vehicle at (lat, lon) -> vehicle yaw in
// the local frame (rad, counter-clockwise from grid east, in (-π, π]):
//   grid heading = true heading − γ(point);  yaw = π/2 − grid heading.
// Throws io::InputError as ToUtm.
double YawFromTrueHeading(const LocalFrame& frame, double heading_true_rad, double lat_deg,
                          double lon_deg);

// A vehicle yaw (rad, counter-clockwise from grid east) as a grid heading (clockwise from grid
// north, HeadingFromYaw of common/angles.h) wrapped to (−180°, 180°] (deg), for reports: sessions circle a wall, so headings
// straddle north as often as not.
double GridHeadingDeg(double yaw_rad);

}  // namespace wallcal::calib
