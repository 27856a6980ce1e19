#include "sim/simulator.h"

#include <GeographicLib/LocalCartesian.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include "common/angles.h"

namespace wallcal::sim {
namespace {
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

double WrapTwoPi(double angle_rad) {
  double a = std::fmod(angle_rad, kTwoPi);
  if (a < 0.0) a += kTwoPi;
  if (a >= kTwoPi) a = 0.0;  // fmod of a tiny negative number plus 2π can round up to 2π
  return a;
}

Eigen::Vector2d Direction(double angle_rad) { return {std::cos(angle_rad), std::sin(angle_rad)}; }

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

Eigen::Vector2d Rotate(double angle_rad, const Eigen::Vector2d& v) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

// No file or line to name here: the caller (simulate's main) knows which file the config came
// from; the message names the key, as SimulationConfig::Validate() does.
void Require(bool ok, const std::string& message) {
  if (!ok) throw io::InputError(message);
}

// ---- Trajectory -------------------------------------------------------------------------------
struct Segment {
  double t0_s = 0.0, t1_s = 0.0;
  Eigen::Vector2d p0_enu_m = Eigen::Vector2d::Zero(), p1_enu_m = Eigen::Vector2d::Zero();
  double yaw0_rad = 0.0, yaw1_rad = 0.0;
  bool stationary = true;
};

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
  Pose At(double t_s) const {
    const double t = std::clamp(t_s, 0.0, duration_s());
    if (weave_) return WeaveAt(t);
    auto it = std::upper_bound(segments_.begin(), segments_.end(), t,
                               [](double v, const Segment& s) { return v < s.t0_s; });
    const Segment& seg = it == segments_.begin() ? *it : *std::prev(it);  // t >= 0 = first t0
    double s = 0.0;
    if (!seg.stationary && seg.t1_s > seg.t0_s) {
      const double tau = std::clamp((t - seg.t0_s) / (seg.t1_s - seg.t0_s), 0.0, 1.0);
      s = 0.5 * (1.0 - std::cos(kPi * tau));
    }
    return {seg.p0_enu_m + s * (seg.p1_enu_m - seg.p0_enu_m),
            seg.yaw0_rad + s * (seg.yaw1_rad - seg.yaw0_rad), seg.stationary};
  }

 private:
  // The sweep follows the same cosine profile as a drive, over the whole run, so heading and
  // lateral position pass every station's values once; the weave r(t) = A·sin(2πt/T) moves the
  // vehicle towards and away from the wall (forward/reverse for a vehicle facing it) and never
  // stops it: the speed along the normal is zero only where the sweep is moving.
  Pose WeaveAt(double t) const {
    const Weave& w = *weave_;
    const double tau = w.duration_s > 0.0 ? t / w.duration_s : 0.0;
    const double s = 0.5 * (1.0 - std::cos(kPi * tau));
    const double r_m = w.amplitude_m * std::sin(kTwoPi * t / w.period_s);
    return {w.p0_enu_m + s * (w.p1_enu_m - w.p0_enu_m) + r_m * w.out_normal,
            w.yaw0_rad + s * (w.yaw1_rad - w.yaw0_rad), false};
  }

  std::vector<Segment> segments_;
  std::optional<Weave> weave_;
};

// Stations in front of the first surveyed wall (see simulator.h / brief): headings spread evenly
// over ±spread/2 about facing the wall along its normal, antenna station_distance_m from the wall
// line, positions spread over lateral_spread_m along it. Heading and lateral position increase
// together so that a vehicle turned left stands to the right and keeps looking at the wall's
// middle, and consecutive stations are neighbours.
Trajectory PlanTrajectory(const io::SimulationConfig& config, const io::SimWall& wall) {
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

  const int n = config.num_stations;
  std::vector<Eigen::Vector2d> positions;
  std::vector<double> yaws;
  for (int i = 0; i < n; ++i) {
    const double frac = static_cast<double>(i) / (n - 1);
    yaws.push_back(facing_yaw_rad + config.heading_spread_rad * (frac - 0.5));
    positions.push_back(middle + config.station_distance_m * out_normal +
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
  weave.period_s = config.weave_amplitude_m > 0.0
                       ? 4.0 * config.weave_amplitude_m / config.drive_speed_mps
                       : 1.0;
  return Trajectory(weave);
}

// ---- Scene and ray casting -------------------------------------------------------------------
struct Hit {
  double range_m;
  double cos_incidence;  // |cos| of the angle between the beam and the surface normal
  int wall_index;        // into config.walls; -1 for an obstacle
};

class Scene {
 public:
  explicit Scene(const io::SimulationConfig& config) {
    for (const auto& w : config.walls) walls_.push_back({{w.x0_m, w.y0_m}, {w.x1_m, w.y1_m}});
    for (const auto& o : config.obstacles) circles_.push_back({{o.x_m, o.y_m}, o.radius_m});
  }

  // Nearest surface along the ray origin + t·dir, t > 0 (dir a unit vector).
  std::optional<Hit> Cast(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir) const {
    constexpr double kMinT = 1e-9;
    std::optional<Hit> best;
    auto offer = [&best](double t, double cos_inc, int wall_index) {
      if (!best || t < best->range_m) best = Hit{t, cos_inc, wall_index};
    };
    int wall_index = -1;
    for (const auto& [p0, p1] : walls_) {
      ++wall_index;
      // origin + t·dir = p0 + s·e  =>  t = (w×e)/(dir×e), s = (w×dir)/(dir×e), w = p0 − origin.
      const Eigen::Vector2d e = p1 - p0;
      const double denom = Cross(dir, e);
      const double length = e.norm();
      if (length <= 0.0 || std::abs(denom) < 1e-12 * length) continue;  // parallel
      const Eigen::Vector2d w = p0 - origin;
      const double t = Cross(w, e) / denom;
      const double s = Cross(w, dir) / denom;
      if (t > kMinT && s >= 0.0 && s <= 1.0) offer(t, std::abs(denom) / length, wall_index);
    }
    for (const auto& [centre, radius] : circles_) {
      const Eigen::Vector2d f = origin - centre;
      const double half_b = f.dot(dir);
      const double disc = half_b * half_b - (f.squaredNorm() - radius * radius);
      if (disc < 0.0) continue;
      const double root = std::sqrt(disc);
      double t = -half_b - root;
      if (t <= kMinT) t = -half_b + root;  // the scanner inside the obstacle: its far side
      if (t <= kMinT) continue;
      const Eigen::Vector2d normal = (origin + t * dir - centre) / radius;
      offer(t, std::abs(normal.dot(dir)), -1);
    }
    return best;
  }

 private:
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> walls_;
  std::vector<std::pair<Eigen::Vector2d, double>> circles_;
};

// ---- Scanner model ----------------------------------------------------------------------------
class ScannerModel {
 public:
  ScannerModel(const io::SimulationConfig& config, const io::ScannerPreset& preset, uint64_t seed)
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

  io::ScanRecord Scan(const Pose& pose, double stamp_s) {
    io::ScanRecord scan;
    scan.stamp_s = stamp_s;
    scan.start_angle_rad = preset_.start_angle_rad;
    scan.angular_step_rad = preset_.angular_step_rad;
    scan.max_range_m = preset_.max_range_m;
    scan.ranges_m.resize(preset_.num_beams);
    const Eigen::Vector2d origin =
        pose.antenna_enu_m + Rotate(pose.yaw_rad, {config_.mount_x_m, config_.mount_y_m});
    const double scanner_yaw_rad = pose.yaw_rad + config_.mount_yaw_rad;
    const double c = std::cos(scanner_yaw_rad), s = std::sin(scanner_yaw_rad);
    const auto to_enu = [c, s](const Eigen::Vector2d& v) {
      return Eigen::Vector2d(c * v.x() - s * v.y(), s * v.x() + c * v.y());
    };
    for (int i = 0; i < preset_.num_beams; ++i) {
      const BeamDirections& b = beams_[i];
      scan.ranges_m[i] =
          static_cast<float>(Beam(origin, to_enu(b.centre), to_enu(b.lower), to_enu(b.upper)));
    }
    return scan;
  }

 private:
  enum class NoReturn { kNoEcho, kTooOblique, kOutOfRange };

  // What the scanner logs when nothing usable came back. SICK scanners report their maximum
  // range (seed 001); the URG reports an error code below 20 mm instead of a range (seed 000).
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
  double Beam(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir,
              const Eigen::Vector2d& lower, const Eigen::Vector2d& upper) {
    const std::optional<Hit> hit = scene_.Cast(origin, dir);
    // One draw per beam whatever happens, so the noise of a beam does not depend on the others.
    const double xi_m = range_noise_.Normal(preset_.range_sigma_m);

    // Mixed pixels (seed 001 §4.5, seed 000): a beam whose footprint straddles a depth jump
    // returns a range between the foreground and the background. Two sub-rays at ±0.4 of the
    // angular step stand in for the footprint's edges.
    std::optional<double> true_range_m;
    if (config_.mixed_pixel_probability > 0.0) {
      const auto lo = scene_.Cast(origin, lower);
      const auto hi = scene_.Cast(origin, upper);
      if (lo && hi && std::abs(lo->range_m - hi->range_m) > 0.1) {
        const double u = mixed_noise_.Uniform();
        const double v = mixed_noise_.Uniform();
        if (u < config_.mixed_pixel_probability)
          true_range_m = lo->range_m + v * (hi->range_m - lo->range_m);
      }
    }
    if (!true_range_m) {
      if (!hit) return NoReturnValue(NoReturn::kNoEcho);
      // Too oblique a surface sends too little light back (seeds 000, 001: incidence limits).
      if (hit->cos_incidence < cos_max_incidence_) {
        return NoReturnValue(NoReturn::kTooOblique);
      }
      true_range_m = hit->range_m;
    }
    if (*true_range_m >= preset_.max_range_m) return NoReturnValue(NoReturn::kOutOfRange);
    // Seeds 000/001 simulation model: z = Int(n·y + c + ξ), Int the range resolution.
    const double z_m =
        Quantise(preset_.sim_scale_n * *true_range_m + preset_.sim_offset_c_m + xi_m);
    if (z_m >= preset_.max_range_m) return NoReturnValue(NoReturn::kOutOfRange);
    if (z_m < std::max(preset_.min_range_m, preset_.error_codes_below_m))
      return NoReturnValue(NoReturn::kNoEcho);
    return z_m;
  }

  const io::SimulationConfig& config_;
  const io::ScannerPreset& preset_;
  Scene scene_;
  Noise range_noise_;
  Noise mixed_noise_;
  double cos_max_incidence_;
  struct BeamDirections {
    Eigen::Vector2d centre, lower, upper;  // unit vectors in the scanner frame
  };
  std::vector<BeamDirections> beams_;
};

// ---- GNSS ----------------------------------------------------------------------------------
// Float periods: float_fraction of the run in up to three contiguous blocks (one per 20 s of
// float time, at least one), each at a random place inside its own third of the run.
std::vector<std::pair<double, double>> FloatPeriods(const io::SimulationConfig& config,
                                                    double duration_s, uint64_t seed) {
  std::vector<std::pair<double, double>> periods;
  const double fraction = std::clamp(config.float_fraction, 0.0, 1.0);
  if (fraction <= 0.0) return periods;
  Noise noise(seed, Stream::kFloatPeriods);
  const double float_s = fraction * duration_s;
  const int blocks = std::clamp(static_cast<int>(std::ceil(float_s / 20.0)), 1, 3);
  const double block_s = float_s / blocks;
  const double slot_s = duration_s / blocks;
  for (int i = 0; i < blocks; ++i) {
    const double start_s = i * slot_s + noise.Uniform() * (slot_s - block_s);
    periods.emplace_back(start_s, start_s + block_s);
  }
  return periods;
}

std::vector<io::GnssFix> SimulateGnss(const io::SimulationConfig& config,
                                      const Trajectory& trajectory,
                                      const GeographicLib::LocalCartesian& enu, uint64_t seed) {
  const auto float_periods = FloatPeriods(config, trajectory.duration_s(), seed);
  Noise bias_noise(seed, Stream::kGnssBias);
  Noise white_noise(seed, Stream::kGnssWhite);
  const double dt_s = 1.0 / config.gnss_rate_hz;
  const double sigma_b = config.gnss_bias_sigma_m;
  // First-order Gauss–Markov bias, discretised exactly: b' = φ·b + σ·sqrt(1 − φ²)·w,
  // φ = exp(−Δt/τ); started from its stationary distribution N(0, σ²). The RTK error of
  // seed 002 (±2 cm) is slowly varying (multipath, residual atmosphere), hence the correlation.
  const double phi = config.gnss_bias_tau_s > 0.0 ? std::exp(-dt_s / config.gnss_bias_tau_s) : 0.0;
  const double drive = std::sqrt(std::max(0.0, 1.0 - phi * phi));
  Eigen::Vector2d bias(bias_noise.Normal(sigma_b), bias_noise.Normal(sigma_b));
  // GST σ per horizontal axis: the bias and white parts are independent.
  const double sigma_fixed_m = std::hypot(sigma_b, config.gnss_white_sigma_m);
  // Vertical RTK scatter is typically about twice the horizontal (assumption; 2-D model only).
  const double sigma_up_m = 2.0 * config.gnss_white_sigma_m;

  std::vector<io::GnssFix> fixes;
  const int64_t count =
      static_cast<int64_t>(std::floor(trajectory.duration_s() * config.gnss_rate_hz + 1e-9)) + 1;
  fixes.reserve(count);
  for (int64_t j = 0; j < count; ++j) {
    const double t_s = j / config.gnss_rate_hz;
    if (j > 0) {
      bias = phi * bias + Eigen::Vector2d(bias_noise.Normal(sigma_b * drive),
                                          bias_noise.Normal(sigma_b * drive));
    }
    const Eigen::Vector2d white(white_noise.Normal(config.gnss_white_sigma_m),
                                white_noise.Normal(config.gnss_white_sigma_m));
    const double up_m = white_noise.Normal(sigma_up_m);
    const bool is_float =
        std::any_of(float_periods.begin(), float_periods.end(),
                    [t_s](const auto& p) { return t_s >= p.first && t_s < p.second; });
    // An RTK float solution is roughly ten times worse than fixed (brief's assumption).
    const double scale = is_float ? 10.0 : 1.0;
    const Pose pose = trajectory.At(t_s);
    const Eigen::Vector2d p = pose.antenna_enu_m + scale * (bias + white);

    io::GnssFix fix;
    fix.stamp_s = config.start_time_s + t_s;
    enu.Reverse(p.x(), p.y(), scale * up_m, fix.lat_deg, fix.lon_deg, fix.height_m);
    fix.quality = is_float ? 5 : 4;
    fix.satellites = 14;
    fix.hdop = 0.7;
    if (config.write_gst) {
      fix.sigma_lat_m = scale * sigma_fixed_m;
      fix.sigma_lon_m = scale * sigma_fixed_m;
    }
    fixes.push_back(fix);
  }
  return fixes;
}

// ---- Heading --------------------------------------------------------------------------------
// Measured heading = true heading + bias + drift·t + white. The drift is linear with the
// configured rate and a sign drawn from the seed (seed 002: FOG drift ±0.5°/h).
std::vector<io::HeadingSample> SimulateHeadings(const io::SimulationConfig& config,
                                                const Trajectory& trajectory, uint64_t seed) {
  Noise noise(seed, Stream::kHeading);
  const double drift_rad_per_s =
      (noise.Uniform() < 0.5 ? -1.0 : 1.0) * config.heading_drift_rad_per_s;
  std::vector<io::HeadingSample> headings;
  const int64_t count =
      static_cast<int64_t>(std::floor(trajectory.duration_s() * config.heading_rate_hz + 1e-9)) + 1;
  headings.reserve(count);
  for (int64_t j = 0; j < count; ++j) {
    const double t_s = j / config.heading_rate_hz;
    const double true_heading_rad = kPi / 2.0 - trajectory.At(t_s).yaw_rad;  // cw from true north
    io::HeadingSample sample;
    sample.stamp_s = config.start_time_s + t_s;
    sample.heading_rad =
        WrapTwoPi(true_heading_rad + config.heading_bias_rad + drift_rad_per_s * t_s +
                  noise.Normal(config.heading_white_sigma_rad));
    headings.push_back(sample);
  }
  return headings;
}

// ---- Survey ---------------------------------------------------------------------------------
// Total-station frame: x axis rotated survey_rotation_rad ccw from true east, origin at
// (survey_origin_x_m, survey_origin_y_m) ENU; z up from the ground at the wall foot (z = 0).
struct SurveyFrame {
  Eigen::Vector2d origin_enu_m;
  double rotation_rad;
  Eigen::Vector2d ToStation(const Eigen::Vector2d& p_enu) const {
    return Rotate(-rotation_rad, p_enu - origin_enu_m);
  }
};

}  // namespace

io::SimulationConfig WithDefaultWalls(io::SimulationConfig config) {
  if (!config.walls.empty()) return config;
  io::SimWall wall;
  wall.id = "north_wall";
  wall.code = "WALL1";
  wall.x0_m = -15.0;
  wall.y0_m = 12.0;
  wall.x1_m = 15.0;
  wall.y1_m = 12.0;
  config.walls.push_back(wall);
  return config;
}

namespace {

// What the trajectory needs beyond config.Validate(); returns the first surveyed wall. Messages
// in Validate()'s form: the YAML key first, so the user knows what to change.
const io::SimWall& CheckTrajectoryConfig(const io::SimulationConfig& config) {
  config.Validate();
  const auto first_surveyed = std::find_if(config.walls.begin(), config.walls.end(),
                                           [](const io::SimWall& w) { return !w.code.empty(); });
  Require(first_surveyed != config.walls.end(),
          "simulation.walls must hold at least one wall with a survey code, got none (see "
          "WithDefaultWalls)");
  Require(std::hypot(first_surveyed->x1_m - first_surveyed->x0_m,
                     first_surveyed->y1_m - first_surveyed->y0_m) > 0.0,
          "simulation.walls: wall '" + first_surveyed->id + "' must have two different ends");
  Require(config.num_stations >= 3,
          "simulation.num_stations must be >= 3, got " + std::to_string(config.num_stations));
  Require(config.dwell_s >= 0.0 && config.drive_speed_mps > 0.0,
          "simulation.dwell_s must be >= 0 and simulation.drive_speed_mps > 0");
  const double reach_m = std::hypot(config.mount_x_m, config.mount_y_m) + 0.1;
  Require(config.station_distance_m > reach_m,
          "simulation.station_distance_m must exceed the mount's distance from the antenna + 0.1 m "
          "(else the "
          "scanner would stand at or behind the wall), got " +
              std::to_string(config.station_distance_m));
  if (config.continuous) {
    Require(std::isfinite(config.weave_amplitude_m) && config.weave_amplitude_m >= 0.0,
            "simulation.weave_amplitude_m must be >= 0, got " +
                std::to_string(config.weave_amplitude_m));
    Require(std::isfinite(config.continuous_duration_s) && config.continuous_duration_s >= 0.0,
            "simulation.continuous_duration_s must be >= 0 (0: as long as the stop-and-go plan), "
            "got " + std::to_string(config.continuous_duration_s));
    Require(config.station_distance_m - config.weave_amplitude_m > reach_m,
            "simulation.station_distance_m - weave_amplitude_m must exceed the mount's distance "
            "from the antenna + 0.1 m (else the weave would take the scanner to the wall), got " +
                std::to_string(config.station_distance_m - config.weave_amplitude_m));
  }
  return *first_surveyed;
}

}  // namespace

double RunDurationS(const io::SimulationConfig& config) {
  return PlanTrajectory(config, CheckTrajectoryConfig(config)).duration_s();
}

std::vector<SimTruthPose> TruePosesAt(const io::SimulationConfig& config,
                                      const std::vector<double>& t_s) {
  const Trajectory trajectory = PlanTrajectory(config, CheckTrajectoryConfig(config));
  std::vector<SimTruthPose> poses;
  poses.reserve(t_s.size());
  for (double t : t_s) {
    const Pose pose = trajectory.At(t);
    poses.push_back({config.start_time_s + t, pose.antenna_enu_m, pose.yaw_rad, pose.stationary});
  }
  return poses;
}

std::vector<SimBeamHit> TrueBeamHits(const io::SimulationConfig& config,
                                     const io::ScannerPreset& preset, const SimTruthPose& pose) {
  const Scene scene(config);
  const Eigen::Vector2d origin =
      pose.antenna_enu_m + Rotate(pose.yaw_enu_rad, {config.mount_x_m, config.mount_y_m});
  const double scanner_yaw_rad = pose.yaw_enu_rad + config.mount_yaw_rad;
  const double cos_max_incidence = std::cos(preset.max_incidence_rad);
  const double half_rad = 0.4 * preset.angular_step_rad;  // footprint edges, as in ScannerModel
  std::vector<SimBeamHit> hits;
  hits.reserve(std::max(0, preset.num_beams));
  for (int i = 0; i < preset.num_beams; ++i) {
    SimBeamHit hit;
    hit.bearing_rad = preset.start_angle_rad + i * preset.angular_step_rad;
    const double enu_rad = scanner_yaw_rad + hit.bearing_rad;
    const std::optional<Hit> centre = scene.Cast(origin, Direction(enu_rad));
    if (centre) {
      hit.range_m = centre->range_m;
      hit.wall_index = centre->wall_index;
      hit.cos_incidence = centre->cos_incidence;
      hit.returned = centre->cos_incidence >= cos_max_incidence &&
                     centre->range_m < preset.max_range_m;
    }
    const auto lo = scene.Cast(origin, Direction(enu_rad - half_rad));
    const auto hi = scene.Cast(origin, Direction(enu_rad + half_rad));
    hit.footprint_edge = lo && hi && std::abs(lo->range_m - hi->range_m) > 0.1;
    hits.push_back(hit);
  }
  return hits;
}

SimulatedSession Simulate(const io::SimulationConfig& config, const io::ScannerPreset& preset,
                          uint64_t seed, const ScanSink& sink) {
  const io::SimWall* first_surveyed = &CheckTrajectoryConfig(config);
  Require(config.gnss_rate_hz > 0.0 && config.heading_rate_hz > 0.0,
          "simulation.gnss_rate_hz and simulation.heading_rate_hz must be > 0");
  Require(preset.num_beams > 0 && preset.rate_hz > 0.0 && preset.angular_step_rad != 0.0,
          "scanner preset '" + preset.name +
              "' must have num_beams > 0, rate_hz > 0 and a non-zero angular step");
  Require(preset.max_range_m > 0.0,
          "scanner preset '" + preset.name + "' must have max_range_m > 0");

  SimulatedSession session;
  const Trajectory trajectory = PlanTrajectory(config, *first_surveyed);
  const double duration_s = trajectory.duration_s();
  // The site's tangent plane: ENU axes are TRUE east/north, not the UTM grid.
  const GeographicLib::LocalCartesian enu(config.site_lat_deg, config.site_lon_deg,
                                          config.site_height_m);

  for (const auto& w : config.walls) {
    if (!w.code.empty()) session.walls.push_back({w.id, w.code});
  }

  // Truth every 0.1 s (index/10 so that it coincides exactly with 10 Hz GNSS epochs).
  const int64_t truth_count =
      static_cast<int64_t>(std::floor(duration_s * kTruthPeriodDivisor + 1e-9)) + 1;
  session.truth_poses.reserve(truth_count);
  for (int64_t k = 0; k < truth_count; ++k) {
    const double t_s = k / kTruthPeriodDivisor;
    const Pose pose = trajectory.At(t_s);
    session.truth_poses.push_back(
        {config.start_time_s + t_s, pose.antenna_enu_m, pose.yaw_rad, pose.stationary});
  }

  session.fixes = SimulateGnss(config, trajectory, enu, seed);
  session.headings = SimulateHeadings(config, trajectory, seed);

  // Survey: control points first (as a crew would set them up), then the walls.
  {
    const SurveyFrame frame{{config.survey_origin_x_m, config.survey_origin_y_m},
                            config.survey_rotation_rad};
    Noise survey_noise(seed, Stream::kSurvey);
    Noise control_noise(seed, Stream::kControl);
    const double sigma_ts = config.total_station_sigma_m;
    auto add_point = [&](const std::string& id, const std::string& code,
                         const Eigen::Vector2d& p_enu, double z_m) {
      const Eigen::Vector2d p_station = frame.ToStation(p_enu);
      io::SurveyPoint point;
      point.id = id;
      point.code = code;
      point.x_m = p_station.x() + survey_noise.Normal(sigma_ts);
      point.y_m = p_station.y() + survey_noise.Normal(sigma_ts);
      point.z_m = z_m + survey_noise.Normal(sigma_ts);
      session.survey.push_back(point);
    };

    // C1, C2: 2 m in front of the first surveyed wall (vehicle side), at 5 % and 95 % of it.
    const Eigen::Vector2d a(first_surveyed->x0_m, first_surveyed->y0_m);
    const Eigen::Vector2d b(first_surveyed->x1_m, first_surveyed->y1_m);
    const Eigen::Vector2d along = (b - a).normalized();
    Eigen::Vector2d out_normal(-along.y(), along.x());
    if (-out_normal.dot(a) < 0.0) out_normal = -out_normal;  // same side rule as PlanTrajectory
    const double fractions[2] = {0.05, 0.95};
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector2d p_enu = a + fractions[i] * (b - a) + 2.0 * out_normal;
      const std::string id = "C" + std::to_string(i + 1);
      add_point(id, "CTRL", p_enu, 0.0);
      io::ControlPoint control;
      control.id = id;
      const double e = p_enu.x() + control_noise.Normal(config.control_sigma_m);
      const double n = p_enu.y() + control_noise.Normal(config.control_sigma_m);
      const double u = control_noise.Normal(config.control_sigma_m);
      enu.Reverse(e, n, u, control.lat_deg, control.lon_deg, control.h_m);
      session.control.push_back(control);
    }

    // Wall points every survey_spacing_m from the first end, at 0.5 m and height − 0.5 m.
    int number = 0;
    for (const auto& w : config.walls) {
      if (w.code.empty()) continue;
      const Eigen::Vector2d w0(w.x0_m, w.y0_m), w1(w.x1_m, w.y1_m);
      const double length_m = (w1 - w0).norm();
      const double spacing_m = w.survey_spacing_m > 0.0 ? w.survey_spacing_m : 1.0;
      const int steps = static_cast<int>(std::floor(length_m / spacing_m + 1e-9));
      for (int k = 0; k <= steps; ++k) {
        const Eigen::Vector2d p_enu =
            length_m > 0.0 ? Eigen::Vector2d(w0 + (k * spacing_m / length_m) * (w1 - w0)) : w0;
        for (double z_m : {0.5, w.height_m - 0.5}) {
          char id[16];
          std::snprintf(id, sizeof(id), "W%03d", ++number);
          add_point(id, w.code, p_enu, z_m);
        }
      }
    }
  }

  // Scans: k/rate true time; the logger stamps them scanner_time_offset_s early.
  ScannerModel scanner(config, preset, seed);
  Noise lost_noise(seed, Stream::kLostScan);
  const int64_t log_every = std::max<int64_t>(1, std::llround(config.log_every_n));
  const int64_t scan_count =
      static_cast<int64_t>(std::floor(duration_s * preset.rate_hz + 1e-9)) + 1;
  for (int64_t k = 0; k < scan_count; ++k) {
    ++session.scans_generated;
    if (k % log_every != 0) continue;
    // Lost packets on the serial link (seed 001: ≤ 0.08 % at 500 kbaud).
    if (lost_noise.Uniform() < config.lost_scan_fraction) {
      ++session.scans_lost;
      continue;
    }
    const double t_s = k / preset.rate_hz;
    // The whole scan is taken at one instant: at ≤ 1 m/s and 13 ms per sweep the vehicle moves
    // ≤ 13 mm during a sweep. At the stations that is exact; in continuous mode it leaves out
    // the sweep's motion skew (the tool treats scans as instantaneous too).
    const io::ScanRecord scan =
        scanner.Scan(trajectory.At(t_s), config.start_time_s + t_s - config.scanner_time_offset_s);
    ++session.scans_written;
    if (sink) sink(scan);
  }
  return session;
}

}  // namespace wallcal::sim
