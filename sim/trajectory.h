// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulator's random streams and the vehicle's planned trajectory (stations facing the wall,
// drives and turns between them). Internal to sim/.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "common/angles.h"
#include "sim/simulation_config.h"
#include "io/types.h"

namespace wallcal::sim::detail {

constexpr double kTruthPeriodDivisor = 10.0;  // truth poses every 1/10 s

// ---- Random streams ---------------------------------------------------------------------------
// One generator per noise source, each seeded from (seed, stream id) through a seed_seq, so that
// e.g. switching mixed pixels off leaves the GNSS noise unchanged. Normal draws are standard
// normal scaled by σ: std::normal_distribution requires σ > 0, and a σ of 0 must still consume
// the same draws to keep the stream aligned.
enum class Stream : uint32_t {
  kScanNoise = 1,
  kMixedPixel = 2,
  kLostScan = 3,
  kGnssBias = 4,
  kGnssWhite = 5,
  kFloatPeriods = 6,
  kHeading = 7,
  kSurvey = 8,
  kControl = 9,
  kGnssJitter = 10,
  kGnssVerticalBias = 11,   // drawn only in a 3-D site
  kGnssVerticalWhite = 12,  // drawn only in a 3-D site
  kAttitude = 13,
  kUnitRangeModel = 14,  // a scanner unit's own range scale and offset errors
  kScanJitter = 15,      // the logger's arrival jitter on scan stamps
};

class Noise {
 public:
  Noise(uint64_t seed, Stream stream) {
    std::seed_seq seq{static_cast<uint32_t>(seed & 0xffffffffu), static_cast<uint32_t>(seed >> 32),
                      static_cast<uint32_t>(stream), 0x77616c6cu /* "wall" */};
    rng_.seed(seq);
  }
  double Normal(double sigma) { return sigma * normal_(rng_); }
  double Uniform() { return uniform_(rng_); }  // [0, 1)

 private:
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

inline Eigen::Vector2d Direction(double angle_rad) {
  return {std::cos(angle_rad), std::sin(angle_rad)};
}

inline double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

inline Eigen::Vector2d Rotate(double angle_rad, const Eigen::Vector2d& v) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

// No file or line to name here: the caller (simulate's main) knows which file the config came
// from; the message names the key, as SimulationConfig::Validate() does.
inline void Require(bool ok, const std::string& message) {
  if (!ok) throw io::InputError(message);
}

// ---- Trajectory -------------------------------------------------------------------------------
struct Segment {
  double t0_s = 0.0, t1_s = 0.0;
  Eigen::Vector2d p0_enu_m = Eigen::Vector2d::Zero(), p1_enu_m = Eigen::Vector2d::Zero();
  double yaw0_rad = 0.0, yaw1_rad = 0.0;
  bool stationary = true;
  // A drive that reverses (drive_reverse_m > 0): two cubic Bézier curves, backing out from p0
  // to a cusp and driving forward from it to p1, the second starting at cusp_s.
  bool reverses = false;
  std::array<Eigen::Vector2d, 4> back_out, drive_in;
  double cusp_s = 0.0;
};

// A cubic Bézier curve's point and derivative (per unit of u) at u in [0, 1].
inline Eigen::Vector2d BezierAt(const std::array<Eigen::Vector2d, 4>& c, double u) {
  const double v = 1.0 - u;
  return v * v * v * c[0] + 3.0 * v * v * u * c[1] + 3.0 * v * u * u * c[2] + u * u * u * c[3];
}
inline Eigen::Vector2d BezierTangent(const std::array<Eigen::Vector2d, 4>& c, double u) {
  const double v = 1.0 - u;
  return 3.0 * v * v * (c[1] - c[0]) + 6.0 * v * u * (c[2] - c[1]) + 3.0 * u * u * (c[3] - c[2]);
}
// The length of a cubic Bézier curve (a 64-chord polyline: well within a millimetre here).
inline double BezierLength(const std::array<Eigen::Vector2d, 4>& c) {
  double length_m = 0.0;
  for (int k = 0; k < 64; ++k)
    length_m += (BezierAt(c, (k + 1) / 64.0) - BezierAt(c, k / 64.0)).norm();
  return length_m;
}

struct Pose {
  Eigen::Vector2d antenna_enu_m;
  double yaw_rad;
  bool stationary;
};

// Continuous driving: one smooth sweep from the first station's pose to the last one's, with a
// forward/back weave along the wall normal on top (see PlanTrajectory).
struct Weave {
  double duration_s = 0.0;
  Eigen::Vector2d p0_enu_m = Eigen::Vector2d::Zero(), p1_enu_m = Eigen::Vector2d::Zero();
  double yaw0_rad = 0.0, yaw1_rad = 0.0;
  Eigen::Vector2d out_normal = Eigen::Vector2d::UnitY();  // away from the wall
  double amplitude_m = 0.0;
  double period_s = 1.0;
  // > 0: the weave is driven along the vehicle's own axis, on an arc whose heading turns by
  // curvature × distance (rad/m): forward and back on a circle, as a car-like vehicle weaves.
  // 0: along the wall normal whatever the heading.
  double curvature_rad_per_m = 0.0;
};

class Trajectory {
 public:
  explicit Trajectory(std::vector<Segment> segments) : segments_(std::move(segments)) {}
  explicit Trajectory(const Weave& weave) : weave_(weave) {}
  double duration_s() const { return weave_ ? weave_->duration_s : segments_.back().t1_s; }

  // Pose at true time t (clamped to the run). Drives follow a cosine profile
  // s(τ) = (1 − cos πτ)/2 in both position and yaw, so speed and yaw rate are zero at both
  // stations and the vehicle never jerks; position moves on the straight line between the
  // stations, which all lie on one line parallel to the wall, so the vehicle never nears it.
  // With drive_reverse_m > 0 a drive reverses out and drives in instead (ReversingAt).
  Pose At(double t_s) const {
    const double t = std::clamp(t_s, 0.0, duration_s());
    if (weave_) return WeaveAt(t);
    auto it = std::upper_bound(segments_.begin(), segments_.end(), t,
                               [](double v, const Segment& s) { return v < s.t0_s; });
    const Segment& seg = it == segments_.begin() ? *it : *std::prev(it);  // t >= 0 = first t0
    if (seg.reverses) return ReversingAt(seg, t);
    double s = 0.0;
    if (!seg.stationary && seg.t1_s > seg.t0_s) {
      const double tau = std::clamp((t - seg.t0_s) / (seg.t1_s - seg.t0_s), 0.0, 1.0);
      s = 0.5 * (1.0 - std::cos(kPi * tau));
    }
    return {seg.p0_enu_m + s * (seg.p1_enu_m - seg.p0_enu_m),
            seg.yaw0_rad + s * (seg.yaw1_rad - seg.yaw0_rad), seg.stationary};
  }

 private:
  // A reversing drive: along each curve the parameter follows the cosine profile in time, so the
  // vehicle is at rest at both stations and at the cusp; the heading is the direction of
  // travel (backwards on the first curve): no sideways motion, as for a car-like vehicle.
  static Pose ReversingAt(const Segment& seg, double t) {
    const bool out = t < seg.cusp_s;
    const double a = out ? seg.t0_s : seg.cusp_s, b = out ? seg.cusp_s : seg.t1_s;
    const double tau = b > a ? std::clamp((t - a) / (b - a), 0.0, 1.0) : 1.0;
    const double u = 0.5 * (1.0 - std::cos(kPi * tau));
    const auto& curve = out ? seg.back_out : seg.drive_in;
    const Eigen::Vector2d heading =
        out ? Eigen::Vector2d(-BezierTangent(curve, u)) : BezierTangent(curve, u);
    const double yaw_rad =
        seg.yaw0_rad + WrapAngle(std::atan2(heading.y(), heading.x()) - seg.yaw0_rad);
    return {BezierAt(curve, u), yaw_rad, false};
  }

  // The sweep follows the same cosine profile as a drive, over the whole run, so heading and
  // lateral position pass every station's values once; the weave r(t) = A·sin(2πt/T) moves the
  // vehicle towards and away from the wall (forward/reverse for a vehicle facing it) and never
  // stops it: the speed along the normal is zero only where the sweep is moving. Along the
  // heading, r is the distance driven on an arc of curvature κ from the sweep's pose (heading
  // ψ₀ + κ r), so the velocity stays on the vehicle's axis but for the sweep's slow drift.
  Pose WeaveAt(double t) const {
    const Weave& w = *weave_;
    const double tau = w.duration_s > 0.0 ? t / w.duration_s : 0.0;
    const double s = 0.5 * (1.0 - std::cos(kPi * tau));
    const double r_m = w.amplitude_m * std::sin(kTwoPi * t / w.period_s);
    const Eigen::Vector2d sweep = w.p0_enu_m + s * (w.p1_enu_m - w.p0_enu_m);
    const double yaw0 = w.yaw0_rad + s * (w.yaw1_rad - w.yaw0_rad);
    if (w.curvature_rad_per_m == 0.0) return {sweep + r_m * w.out_normal, yaw0, false};
    const double turn = w.curvature_rad_per_m * r_m;
    // The arc from yaw0 over r_m: r_m·(cos, sin)(yaw0) when straight.
    const Eigen::Vector2d arc =
        std::abs(turn) < 1e-9
            ? Eigen::Vector2d(r_m * Direction(yaw0))
            : Eigen::Vector2d((std::sin(yaw0 + turn) - std::sin(yaw0)) / w.curvature_rad_per_m,
                              (std::cos(yaw0) - std::cos(yaw0 + turn)) / w.curvature_rad_per_m);
    return {sweep + arc, yaw0 + turn, false};
  }

  std::vector<Segment> segments_;
  std::optional<Weave> weave_;
};

// Stations in front of the first surveyed wall (see simulator.h / brief): headings spread evenly
// over ±spread/2 about facing the wall along its normal, antenna station_distance_m from the wall
// line, positions spread over lateral_spread_m along it. Heading and lateral position increase
// together so that a vehicle turned left stands to the right and keeps looking at the wall's
// middle, and consecutive stations are neighbours.
inline Trajectory PlanTrajectory(const sim::SimulationConfig& config, const sim::SimWall& wall) {
  const Eigen::Vector2d a(wall.x0_m, wall.y0_m), b(wall.x1_m, wall.y1_m);
  const Eigen::Vector2d along = (b - a).normalized();
  const Eigen::Vector2d left_normal(-along.y(), along.x());
  // The vehicle works on the side of the wall that holds the site origin (the default wall is
  // 12 m north of it); for a wall through the origin, on the left of x0,y0 -> x1,y1.
  const double origin_side = -left_normal.dot(a);
  const Eigen::Vector2d out_normal =
      origin_side < 0.0 ? Eigen::Vector2d(-left_normal) : left_normal;
  const Eigen::Vector2d facing = -out_normal;
  const Eigen::Vector2d right(facing.y(), -facing.x());
  const double facing_yaw_rad = std::atan2(facing.y(), facing.x());
  const Eigen::Vector2d middle = 0.5 * (a + b);

  if (!config.stops.empty()) {
    std::vector<Segment> segments;
    double t = 0.0;
    auto add = [&](const Eigen::Vector2d& p0, double yaw0, const Eigen::Vector2d& p1, double yaw1,
                   double duration_s, bool stationary) {
      Segment s;
      s.t0_s = t;
      s.t1_s = t + duration_s;
      s.p0_enu_m = p0;
      s.p1_enu_m = p1;
      s.yaw0_rad = yaw0;
      s.yaw1_rad = yaw1;
      s.stationary = stationary;
      segments.push_back(s);
      t = s.t1_s;
    };
    // As the even plan's drives: the turn counts as the path of a point 2 m from the antenna.
    auto drive_time = [&](const Eigen::Vector2d& p0, double yaw0, const Eigen::Vector2d& p1,
                          double yaw1) {
      return std::max(0.5, std::max((p1 - p0).norm(), 2.0 * std::abs(yaw1 - yaw0)) /
                               config.drive_speed_mps);
    };
    bool first = true;
    Eigen::Vector2d at = Eigen::Vector2d::Zero();
    double yaw = facing_yaw_rad;
    for (const sim::SimStop& stop : config.stops) {
      const double stop_yaw = facing_yaw_rad - stop.vehicle_to_wall_rad;
      const double lateral_m = config.heading_spread_rad > 0.0
                                   ? config.lateral_spread_m * (stop_yaw - facing_yaw_rad) /
                                         config.heading_spread_rad
                                   : 0.0;
      const Eigen::Vector2d place = middle + stop.distance_m * out_normal + lateral_m * right;
      if (!first) {
        // The wait beyond the drive is spent standing where the vehicle is.
        const double drive_s = drive_time(at, yaw, place, stop_yaw);
        if (stop.wait_s > drive_s) add(at, yaw, at, yaw, stop.wait_s - drive_s, true);
        add(at, yaw, place, stop_yaw, drive_s, false);
      }
      add(place, stop_yaw, place, stop_yaw, stop.dwell_s, true);
      at = place;
      yaw = stop_yaw;
      first = false;
    }
    return Trajectory(std::move(segments));
  }

  const int n = config.num_stations;
  // station_distance_far_m > 0: distances from near to far in the order i·p mod n (p the first
  // of 3, 5, 7, 11 prime to n), so that distance does not follow heading.
  int stride = 1;
  for (int p : {3, 5, 7, 11}) {
    if (n % p != 0) {
      stride = p;
      break;
    }
  }
  std::vector<Eigen::Vector2d> positions;
  std::vector<double> yaws;
  for (int i = 0; i < n; ++i) {
    const double frac = static_cast<double>(i) / (n - 1);
    const double distance_m =
        config.station_distance_far_m > 0.0
            ? config.station_distance_m +
                  (config.station_distance_far_m - config.station_distance_m) *
                      static_cast<double>((static_cast<int64_t>(i) * stride) % n) / (n - 1)
            : config.station_distance_m;
    yaws.push_back(facing_yaw_rad + config.heading_spread_rad * (frac - 0.5));
    positions.push_back(middle + distance_m * out_normal +
                        config.lateral_spread_m * (frac - 0.5) * right);
  }

  std::vector<Segment> segments;
  double t = 0.0;
  for (int i = 0; i < n; ++i) {
    Segment dwell;
    dwell.t0_s = t;
    dwell.t1_s = t + config.dwell_s;
    dwell.p0_enu_m = dwell.p1_enu_m = positions[i];
    dwell.yaw0_rad = dwell.yaw1_rad = yaws[i];
    dwell.stationary = true;
    segments.push_back(dwell);
    t = dwell.t1_s;
    if (i + 1 == n) break;
    // drive_speed_mps is the mean speed over the drive. The turn counts as the path swept by a
    // point 2 m from the antenna (roughly the scanner's lever arm), and no drive is shorter than
    // 0.5 s, so a pure turn still takes a plausible time.
    const double path_m =
        std::max((positions[i + 1] - positions[i]).norm(), 2.0 * std::abs(yaws[i + 1] - yaws[i]));
    const double drive_s = std::max(0.5, path_m / config.drive_speed_mps);
    Segment drive;
    drive.t0_s = t;
    drive.t1_s = t + drive_s;
    drive.p0_enu_m = positions[i];
    drive.p1_enu_m = positions[i + 1];
    drive.yaw0_rad = yaws[i];
    drive.yaw1_rad = yaws[i + 1];
    drive.stationary = false;
    if (config.drive_reverse_m > 0.0) {
      // Back out to a cusp drive_reverse_m behind the two stations' midpoint, facing the mean
      // heading, then drive in. Each curve leaves and meets its ends along the vehicle's axis
      // (control points a third of the chord away); each half takes its length over the speed.
      const double cusp_yaw = yaws[i] + 0.5 * (yaws[i + 1] - yaws[i]);
      const Eigen::Vector2d cusp =
          0.5 * (positions[i] + positions[i + 1]) - config.drive_reverse_m * Direction(cusp_yaw);
      const double l_out = (cusp - positions[i]).norm() / 3.0;
      const double l_in = (positions[i + 1] - cusp).norm() / 3.0;
      drive.reverses = true;
      drive.back_out = {positions[i], positions[i] - l_out * Direction(yaws[i]),
                        cusp + l_out * Direction(cusp_yaw), cusp};
      drive.drive_in = {cusp, cusp + l_in * Direction(cusp_yaw),
                        positions[i + 1] - l_in * Direction(yaws[i + 1]), positions[i + 1]};
      drive.cusp_s = t + std::max(0.5, BezierLength(drive.back_out) / config.drive_speed_mps);
      drive.t1_s =
          drive.cusp_s + std::max(0.5, BezierLength(drive.drive_in) / config.drive_speed_mps);
    }
    segments.push_back(drive);
    t = drive.t1_s;
  }
  if (!config.continuous) return Trajectory(std::move(segments));

  // Continuous driving: as long as the stop-and-go plan unless told otherwise; the weave's
  // period makes its mean speed along the normal (4A per period) drive_speed_mps.
  Weave weave;
  weave.duration_s =
      config.continuous_duration_s > 0.0 ? config.continuous_duration_s : segments.back().t1_s;
  weave.p0_enu_m = positions.front();
  weave.p1_enu_m = positions.back();
  weave.yaw0_rad = yaws.front();
  weave.yaw1_rad = yaws.back();
  weave.out_normal = out_normal;
  weave.amplitude_m = config.weave_amplitude_m;
  weave.curvature_rad_per_m =
      config.weave_amplitude_m > 0.0 ? config.weave_turn_rad / config.weave_amplitude_m : 0.0;
  weave.period_s = config.weave_amplitude_m > 0.0
                       ? 4.0 * config.weave_amplitude_m / config.drive_speed_mps
                       : 1.0;
  return Trajectory(weave);
}

}  // namespace wallcal::sim::detail
