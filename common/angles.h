// SPDX-License-Identifier: Apache-2.0
#pragma once
// Angles: the one home for π, degree/radian factors and angle normalisation. Inside wallcal every
// angle is in radians; degrees appear only at the edges (files, YAML, printed text), converted
// with these factors.

#include <cmath>

namespace wallcal {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 2.0 * kPi;
inline constexpr double kRadToDeg = 180.0 / kPi;
inline constexpr double kDegToRad = kPi / 180.0;
// A rate given in °/h (a FOG's drift) per rad/s.
inline constexpr double kDegPerHourPerRadPerS = kRadToDeg * 3600.0;

// An angle wrapped into (−π, π] (rad). Works for double and for ceres::Jet (through ADL on
// ceil, whose derivative is zero, so the Jacobian passes through unchanged).
template <typename T>
T WrapAngle(const T& angle_rad) {
  using std::ceil;
  return angle_rad - T(kTwoPi) * ceil((angle_rad - T(kPi)) / T(kTwoPi));
}

// An angle wrapped into [0, 2π) (rad): headings.
inline double WrapTwoPi(double angle_rad) {
  double a = std::fmod(angle_rad, kTwoPi);
  if (a < 0.0) a += kTwoPi;
  if (a >= kTwoPi) a = 0.0;  // fmod of a tiny negative number plus 2π can round up to 2π
  return a;
}

// A yaw (rad, counter-clockwise from east) as a heading (rad, clockwise from north of the same
// frame: grid north for a grid yaw, true north for a true one) = π/2 − yaw, not wrapped: callers
// wrap it as they show it (WrapTwoPi, WrapAngle) or take circular statistics of it.
inline double HeadingFromYaw(double yaw_rad) { return 0.5 * kPi - yaw_rad; }

// A heading (rad, clockwise from north) as a yaw (rad, counter-clockwise from east) = π/2 −
// heading, in (−π, π].
inline double YawFromHeading(double heading_rad) { return WrapAngle(0.5 * kPi - heading_rad); }

}  // namespace wallcal
