// SPDX-License-Identifier: Apache-2.0
#include "calib/geodesy.h"

#include <gtest/gtest.h>

#include <GeographicLib/Geodesic.hpp>
#include <cmath>
#include <limits>
#include <string>
#include "common/angles.h"

namespace wallcal::calib {
namespace {
// An independent UTM forward projection for reference values: the Krüger n-series to third
// order as given in "Universal Transverse Mercator coordinate system", Wikipedia, section
// "From latitude, longitude to UTM coordinates" (after Karney 2011, J. Geodesy 85:475). Its
// truncation error is well under a millimetre inside a zone. Written out here rather than
// taken from GeographicLib so that the check does not share code with what it checks.
struct Reference {
  double easting_m, northing_m, gamma_rad, k;
};
Reference KruegerUtm(double lat_deg, double lon_deg, double lon0_deg, bool north) {
  const double a = 6378137.0, f = 1.0 / 298.257223563, k0 = 0.9996;
  const double n = f / (2.0 - f);
  const double big_a = a / (1.0 + n) * (1.0 + n * n / 4.0 + n * n * n * n / 64.0);
  const double alpha[3] = {n / 2.0 - 2.0 * n * n / 3.0 + 5.0 * n * n * n / 16.0,
                           13.0 * n * n / 48.0 - 3.0 * n * n * n / 5.0, 61.0 * n * n * n / 240.0};
  const double phi = lat_deg * kDegToRad, dlambda = (lon_deg - lon0_deg) * kDegToRad;
  const double e = 2.0 * std::sqrt(n) / (1.0 + n);
  const double t = std::sinh(std::atanh(std::sin(phi)) - e * std::atanh(e * std::sin(phi)));
  const double xi = std::atan2(t, std::cos(dlambda));
  const double eta = std::atanh(std::sin(dlambda) / std::sqrt(1.0 + t * t));
  double x = eta, y = xi, sigma = 1.0, tau = 0.0;
  for (int j = 1; j <= 3; ++j) {
    const double aj = alpha[j - 1];
    x += aj * std::cos(2 * j * xi) * std::sinh(2 * j * eta);
    y += aj * std::sin(2 * j * xi) * std::cosh(2 * j * eta);
    sigma += 2 * j * aj * std::cos(2 * j * xi) * std::cosh(2 * j * eta);
    tau += 2 * j * aj * std::sin(2 * j * xi) * std::sinh(2 * j * eta);
  }
  Reference r;
  r.easting_m = 500000.0 + k0 * big_a * x;
  r.northing_m = (north ? 0.0 : 10000000.0) + k0 * big_a * y;
  const double s = std::sqrt(1.0 + t * t);
  r.gamma_rad =
      std::atan2(tau * s + sigma * t * std::tan(dlambda), sigma * s - tau * t * std::tan(dlambda));
  const double q = (1.0 - n) / (1.0 + n) * std::tan(phi);
  r.k = k0 * big_a / a *
        std::sqrt((1.0 + q * q) * (sigma * sigma + tau * tau) /
                  (t * t + std::cos(dlambda) * std::cos(dlambda)));
  return r;
}

TEST(GeodesyTest, EquatorOnCentralMeridianIsFalseOrigin) {
  // Zone 54's central meridian is 6·54 − 183 = 141° E: the point maps to the false origin,
  // with no convergence and the central scale exactly.
  const UtmPoint p = ToUtm(0.0, 141.0);
  EXPECT_EQ(p.zone, 54);
  EXPECT_TRUE(p.north);
  EXPECT_NEAR(p.easting_m, 500000.0, 1e-6);
  EXPECT_NEAR(p.northing_m, 0.0, 1e-6);
  EXPECT_NEAR(p.convergence_rad, 0.0, 1e-12);
  EXPECT_NEAR(p.scale_k, 0.9996, 1e-12);
}

TEST(GeodesyTest, MatchesIndependentKruegerSeries) {
  struct Case {
    double lat_deg, lon_deg;
    int zone;
    bool north;
  };
  // Sapporo (the Barawid 2007 site), Baghdad (GeographicLib's example point), Sydney (south),
  // Quito (just south of the equator, west).
  const Case cases[] = {{43.0712345, 141.3398765, 54, true},
                        {33.3, 44.4, 38, true},
                        {-33.8688, 151.2093, 56, false},
                        {-0.1807, -78.4678, 17, false}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.lat_deg);
    const UtmPoint p = ToUtm(c.lat_deg, c.lon_deg);
    EXPECT_EQ(p.zone, c.zone);
    EXPECT_EQ(p.north, c.north);
    const Reference r = KruegerUtm(c.lat_deg, c.lon_deg, 6.0 * c.zone - 183.0, c.north);
    EXPECT_NEAR(p.easting_m, r.easting_m, 1e-3);
    EXPECT_NEAR(p.northing_m, r.northing_m, 1e-3);
    EXPECT_NEAR(p.convergence_rad, r.gamma_rad, 1e-9);
    EXPECT_NEAR(p.scale_k, r.k, 1e-9);
  }
  // Sapporo in zone 54N is about 528 km east, 4769 km north (a sanity bound on the reference).
  const UtmPoint sapporo = ToUtm(43.0712345, 141.3398765);
  EXPECT_NEAR(sapporo.easting_m, 527.8e3, 1e3);
  EXPECT_NEAR(sapporo.northing_m, 4768.7e3, 1e3);
}

TEST(GeodesyTest, RoundTripsThroughFromUtm) {
  const UtmPoint p = ToUtm(-33.8688, 151.2093);
  double lat_deg = 0.0, lon_deg = 0.0;
  FromUtm(io::UtmZone{p.zone, p.north}, p.easting_m, p.northing_m, &lat_deg, &lon_deg);
  EXPECT_NEAR(lat_deg, -33.8688, 1e-10);
  EXPECT_NEAR(lon_deg, 151.2093, 1e-10);
}

TEST(GeodesyTest, ConvergenceSignFollowsQuadrant) {
  // γ (grid north clockwise from true north) is positive east of the central meridian in the
  // northern hemisphere: the meridians converge towards the pole, so grid north (parallel to
  // the central meridian) lies clockwise of the local meridian there. Mirror images elsewhere.
  // Zone 54: central meridian 141° E.
  EXPECT_GT(ToUtm(43.0, 142.0).convergence_rad, 0.0);   // north-east
  EXPECT_LT(ToUtm(43.0, 140.0).convergence_rad, 0.0);   // north-west
  EXPECT_LT(ToUtm(-43.0, 142.0).convergence_rad, 0.0);  // south-east
  EXPECT_GT(ToUtm(-43.0, 140.0).convergence_rad, 0.0);  // south-west
  // Magnitude: γ ≈ Δλ·sin φ to first order.
  for (double lat_deg : {-60.0, -43.0, 10.0, 43.0, 70.0}) {
    for (double dlon_deg : {-2.5, -1.0, 1.0, 2.5}) {
      const double gamma = ToUtm(lat_deg, 141.0 + dlon_deg).convergence_rad;
      EXPECT_NEAR(gamma, dlon_deg * kDegToRad * std::sin(lat_deg * kDegToRad), 0.01 * std::abs(gamma))
          << lat_deg << " " << dlon_deg;
    }
  }
}

TEST(GeodesyTest, PointScaleIsCentralOnMeridianAndGrowsAway) {
  EXPECT_NEAR(ToUtm(43.0, 141.0).scale_k, 0.9996, 1e-12);
  EXPECT_NEAR(ToUtm(-20.0, 141.0).scale_k, 0.9996, 1e-12);
  // At the equator a degree of longitude is ~111.3 km.
  EXPECT_LT(ToUtm(0.0, 141.0 + 100.0 / 111.32).scale_k, 1.0);
  EXPECT_NEAR(ToUtm(0.0, 141.0 + 180.0 / 111.32).scale_k, 1.0, 1e-4);  // the secant line
  EXPECT_GT(ToUtm(0.0, 141.0 + 250.0 / 111.32).scale_k, 1.0);
  EXPECT_GT(ToUtm(0.0, 141.0 - 250.0 / 111.32).scale_k, 1.0);
}

TEST(GeodesyTest, ForcedZoneProjectsNeighbourIntoIt) {
  // 144.2° E is zone 55 (144–150); forced into zone 54 (central 141°) it lies ~260 km east.
  const UtmPoint own = ToUtm(43.0, 144.2);
  EXPECT_EQ(own.zone, 55);
  const UtmPoint forced = ToUtm(43.0, 144.2, io::UtmZone{54, true});
  EXPECT_EQ(forced.zone, 54);
  EXPECT_GT(forced.easting_m, 500000.0 + 250e3);
  EXPECT_LT(own.easting_m, 500000.0);
  EXPECT_GT(forced.convergence_rad, 0.0);
  EXPECT_LT(own.convergence_rad, 0.0);
  const Reference r = KruegerUtm(43.0, 144.2, 141.0, true);
  EXPECT_NEAR(forced.easting_m, r.easting_m, 1e-3);
  EXPECT_NEAR(forced.northing_m, r.northing_m, 1e-3);
  double lat_deg = 0.0, lon_deg = 0.0;
  FromUtm(io::UtmZone{54, true}, forced.easting_m, forced.northing_m, &lat_deg, &lon_deg);
  EXPECT_NEAR(lat_deg, 43.0, 1e-9);
  EXPECT_NEAR(lon_deg, 144.2, 1e-9);
  // Forcing the hemisphere too: a point just south of the equator in a "north" session keeps a
  // continuous (negative) northing.
  const UtmPoint south = ToUtm(-0.001, 141.0, io::UtmZone{54, true});
  EXPECT_TRUE(south.north);
  EXPECT_NEAR(south.northing_m, -110.6, 0.5);
}

TEST(GeodesyTest, RejectsPointsOutsideUtm) {
  EXPECT_THROW(ToUtm(84.5, 10.0), io::InputError);
  EXPECT_THROW(ToUtm(-80.5, 10.0), io::InputError);
  EXPECT_THROW(ToUtm(std::nan(""), 10.0), io::InputError);
  EXPECT_THROW(ToUtm(40.0, std::numeric_limits<double>::infinity()), io::InputError);
  EXPECT_THROW(ToUtm(40.0, 10.0, io::UtmZone{0, true}), io::InputError);
  EXPECT_THROW(ToUtm(40.0, 10.0, io::UtmZone{61, true}), io::InputError);
  // Zone 54 forced onto a point in Europe.
  try {
    ToUtm(40.0, 10.0, io::UtmZone{54, true});
    FAIL() << "expected InputError";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("zone 54"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(ToUtm(84.0, 10.0));
  EXPECT_NO_THROW(ToUtm(-80.0, 10.0));
}

TEST(GeodesyTest, YawFromHeadings) {
  const LocalFrame frame = MakeLocalFrame(43.0, 142.5, io::UtmZone{54, true});
  const double gamma = ToUtm(43.1, 142.6, io::UtmZone{54, true}).convergence_rad;
  ASSERT_GT(gamma, 0.01);
  // Facing true north: the grid heading is −γ, so the yaw is π/2 + γ.
  EXPECT_NEAR(YawFromTrueHeading(frame, 0.0, 43.1, 142.6), kPi / 2 + gamma, 1e-12);
  // Facing true east.
  EXPECT_NEAR(YawFromTrueHeading(frame, kPi / 2, 43.1, 142.6), gamma, 1e-12);
  // Facing true south-west wraps into (−π, π].
  EXPECT_NEAR(YawFromTrueHeading(frame, 1.25 * kPi, 43.1, 142.6), -0.75 * kPi + gamma, 1e-12);
  // Grid headings need no convergence.
  EXPECT_NEAR(YawFromHeading(0.0), kPi / 2, 1e-15);
  EXPECT_NEAR(YawFromHeading(kPi / 2), 0.0, 1e-15);
  EXPECT_NEAR(YawFromHeading(kPi), -kPi / 2, 1e-15);
  EXPECT_NEAR(YawFromHeading(1.5 * kPi), kPi, 1e-12);  // west: +π, not −π
}

TEST(GeodesyTest, WrapAngleToHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(WrapAngle(kPi), kPi);
  EXPECT_DOUBLE_EQ(WrapAngle(-kPi), kPi);
  EXPECT_NEAR(WrapAngle(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(WrapAngle(2 * kPi + 0.1), 0.1, 1e-12);
  EXPECT_NEAR(WrapAngle(-2 * kPi - 0.1), -0.1, 1e-12);
  EXPECT_NEAR(WrapAngle(-3.0), -3.0, 1e-15);
  for (double a = -20.0; a < 20.0; a += 0.37) {
    const double w = WrapAngle(a);
    EXPECT_GT(w, -kPi);
    EXPECT_LE(w, kPi);
    EXPECT_NEAR(std::remainder(w - a, 2 * kPi), 0.0, 1e-12);
  }
}

TEST(GeodesyTest, LocalFrameKeepsGroundDistancesFarFromMeridian) {
  // Zone 54 forced at 146° E, ~400 km off the central meridian: k ≈ 1.0016 there, so grid
  // distances are 16 cm per 100 m long; the local frame must undo that.
  const io::UtmZone zone{54, true};
  const double lat0 = 43.0, lon0 = 146.0;
  const LocalFrame frame = MakeLocalFrame(lat0, lon0, zone);
  EXPECT_EQ(frame.zone, 54);
  EXPECT_GT(frame.scale_k0, 1.0015);
  EXPECT_NEAR(ToLocal(frame, lat0, lon0).norm(), 0.0, 1e-9);
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  // Start 300 m from the origin, then 100 m in several directions.
  double lat1 = 0.0, lon1 = 0.0;
  geod.Direct(lat0, lon0, 30.0, 300.0, lat1, lon1);
  const Eigen::Vector2d p1 = ToLocal(frame, lat1, lon1);
  EXPECT_NEAR(p1.norm(), 300.0, 1e-3);
  for (double azimuth_deg = 0.0; azimuth_deg < 360.0; azimuth_deg += 45.0) {
    SCOPED_TRACE(azimuth_deg);
    double lat2 = 0.0, lon2 = 0.0, azimuth2_deg = 0.0;
    geod.Direct(lat1, lon1, azimuth_deg, 100.0, lat2, lon2, azimuth2_deg);
    const Eigen::Vector2d d = ToLocal(frame, lat2, lon2) - p1;
    EXPECT_NEAR(d.norm(), 100.0, 1e-3);
    // A vehicle driving along the geodesic with that true heading: its yaw is the direction
    // of the displacement in the local frame (the projection is conformal).
    const double mean_heading_rad =
        (azimuth_deg + 0.5 * std::remainder(azimuth2_deg - azimuth_deg, 360.0)) * kDegToRad;
    const double lat_mid = 0.5 * (lat1 + lat2), lon_mid = 0.5 * (lon1 + lon2);
    const double yaw = YawFromTrueHeading(frame, mean_heading_rad, lat_mid, lon_mid);
    EXPECT_NEAR(WrapAngle(yaw - std::atan2(d.y(), d.x())), 0.0, 2e-6);
  }
}

}  // namespace
}  // namespace wallcal::calib
