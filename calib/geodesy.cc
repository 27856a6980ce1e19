// SPDX-License-Identifier: Apache-2.0
#include "calib/geodesy.h"

#include <GeographicLib/Math.hpp>
#include <GeographicLib/TransverseMercator.hpp>
#include <GeographicLib/UTMUPS.hpp>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include "common/angles.h"

namespace wallcal::calib {
namespace {
constexpr double kFalseEastingM = 500000.0;
constexpr double kFalseNorthingSouthM = 10000000.0;
// A forced zone must be at most a neighbour: beyond a zone and a half the transverse Mercator
// series still converges, but the grid no longer means anything to anyone. The Svalbard zones
// are 12° wide, so a neighbour of one can put a point up to 6° + 9° from the central meridian.
constexpr double kMaxForcedZoneDeltaLonDeg = 15.0;

std::string Number(double value, int precision) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(precision);
  out << value;
  return out.str();
}

void CheckZone(int zone) {
  if (zone < 1 || zone > 60) {
    throw io::InputError("UTM zone " + std::to_string(zone) + " is out of range; expected 1..60");
  }
}

double CentralMeridianDeg(int zone) { return 6.0 * zone - 183.0; }

}  // namespace

UtmPoint ToUtm(double lat_deg, double lon_deg, std::optional<io::UtmZone> zone) {
  if (!std::isfinite(lat_deg) || !std::isfinite(lon_deg)) {
    throw io::InputError("latitude/longitude is not a finite number (" + Number(lat_deg, 9) + ", " +
                         Number(lon_deg, 9) + "); expected degrees");
  }
  // UTM proper ends at 84° N and 80° S; beyond lies UPS, which this tool does not use.
  if (lat_deg > 84.0 || lat_deg < -80.0) {
    throw io::InputError("latitude " + Number(lat_deg, 7) +
                         "° is outside the UTM grid; expected between -80° and 84°");
  }
  UtmPoint out;
  if (zone) {
    CheckZone(zone->zone);
    out.zone = zone->zone;
    out.north = zone->north;
  } else {
    // GeographicLib hands 84° N exactly to UPS; UTM's own limit includes it.
    out.zone = GeographicLib::UTMUPS::StandardZone(std::min(lat_deg, 83.9999999), lon_deg);
    out.north = lat_deg >= 0.0;
  }
  const double lon0_deg = CentralMeridianDeg(out.zone);
  const double delta_lon_deg = GeographicLib::Math::AngDiff(lon0_deg, lon_deg);
  if (std::abs(delta_lon_deg) > kMaxForcedZoneDeltaLonDeg) {
    throw io::InputError("longitude " + Number(lon_deg, 7) + "° is " +
                         Number(std::abs(delta_lon_deg), 1) +
                         "° from the central meridian of UTM zone " + std::to_string(out.zone) +
                         "; expected a point in that zone or a neighbouring one");
  }
  // The projection is called directly (not through UTMUPS::Forward) so that a forced zone also
  // forces the hemisphere: a session straddling the equator keeps one continuous northing.
  double x_m = 0.0, y_m = 0.0, gamma_deg = 0.0, k = 1.0;
  GeographicLib::TransverseMercator::UTM().Forward(lon0_deg, lat_deg, lon_deg, x_m, y_m, gamma_deg,
                                                   k);
  out.easting_m = x_m + kFalseEastingM;
  out.northing_m = y_m + (out.north ? 0.0 : kFalseNorthingSouthM);
  out.convergence_rad = gamma_deg * kDegToRad;
  out.scale_k = k;
  return out;
}

void FromUtm(const io::UtmZone& zone, double easting_m, double northing_m, double* lat_deg,
             double* lon_deg) {
  CheckZone(zone.zone);
  double gamma_deg = 0.0, k = 1.0;
  GeographicLib::TransverseMercator::UTM().Reverse(
      CentralMeridianDeg(zone.zone), easting_m - kFalseEastingM,
      northing_m - (zone.north ? 0.0 : kFalseNorthingSouthM), *lat_deg, *lon_deg, gamma_deg, k);
}

LocalFrame MakeLocalFrame(double lat0_deg, double lon0_deg, std::optional<io::UtmZone> zone) {
  const UtmPoint origin = ToUtm(lat0_deg, lon0_deg, zone);
  LocalFrame frame;
  frame.zone = origin.zone;
  frame.north = origin.north;
  frame.origin_e_m = origin.easting_m;
  frame.origin_n_m = origin.northing_m;
  frame.scale_k0 = origin.scale_k;
  frame.convergence_rad = origin.convergence_rad;
  return frame;
}

Eigen::Vector2d ToLocal(const LocalFrame& frame, double lat_deg, double lon_deg) {
  const UtmPoint p = ToUtm(lat_deg, lon_deg, io::UtmZone{frame.zone, frame.north});
  // One scale for the whole site: k varies by ~1e-8 per metre even 200 km off the meridian,
  // so over a calibration site (< 1 km) dividing by k0 keeps local distances ground distances
  // to well under a millimetre per 100 m.
  return Eigen::Vector2d((p.easting_m - frame.origin_e_m) / frame.scale_k0,
                         (p.northing_m - frame.origin_n_m) / frame.scale_k0);
}

double YawFromTrueHeading(const LocalFrame& frame, double heading_true_rad, double lat_deg,
                          double lon_deg) {
  // γ at the vehicle, not at the origin: it changes by ~1e-5 rad per 100 m east-west at
  // mid-latitudes, small but free to get right.
  const UtmPoint p = ToUtm(lat_deg, lon_deg, io::UtmZone{frame.zone, frame.north});
  return YawFromHeading(heading_true_rad - p.convergence_rad);
}

double GridHeadingDeg(double yaw_rad) { return WrapAngle(HeadingFromYaw(yaw_rad)) * kRadToDeg; }

}  // namespace wallcal::calib
