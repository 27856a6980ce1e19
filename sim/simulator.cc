// SPDX-License-Identifier: Apache-2.0
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
#include "sim/scanner_scene.h"
#include "sim/trajectory.h"

namespace wallcal::sim {
namespace {

// Samples at 0, 1/rate, 2/rate, ... up to and including the end of a duration_s run.
int64_t SampleCount(double duration_s, double rate_hz) {
  return static_cast<int64_t>(std::floor(duration_s * rate_hz + 1e-9)) + 1;
}

using namespace detail;  // NOLINT: the simulator's own building blocks

// ---- GNSS ----------------------------------------------------------------------------------
// Float periods: float_fraction of the run in up to three contiguous blocks (one per 20 s of
// float time, at least one), each at a random place inside its own third of the run.
std::vector<std::pair<double, double>> FloatPeriods(const sim::SimulationConfig& config,
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

std::vector<io::GnssFix> SimulateGnss(const sim::SimulationConfig& config,
                                      const Trajectory& trajectory, const Site& site,
                                      const GeographicLib::LocalCartesian& enu, uint64_t seed) {
  const auto float_periods = FloatPeriods(config, trajectory.duration_s(), seed);
  Noise bias_noise(seed, Stream::kGnssBias);
  Noise white_noise(seed, Stream::kGnssWhite);
  const double dt_s = 1.0 / config.gnss_rate_hz;
  const double sigma_b = config.gnss_bias_sigma_m;
  // First-order Gauss–Markov bias, discretised exactly: b' = φ·b + σ·sqrt(1 − φ²)·w,
  // φ = exp(−Δt/τ); started from its stationary distribution N(0, σ²). The RTK error of
  // Barawid 2007 (±2 cm) is slowly varying (multipath, residual atmosphere), hence the correlation.
  const double phi = config.gnss_bias_tau_s > 0.0 ? std::exp(-dt_s / config.gnss_bias_tau_s) : 0.0;
  const double drive = std::sqrt(std::max(0.0, 1.0 - phi * phi));
  Noise jitter_noise(seed, Stream::kGnssJitter);  // its own stream: other draws unchanged
  Eigen::Vector2d bias(bias_noise.Normal(sigma_b), bias_noise.Normal(sigma_b));
  // GST σ per horizontal axis: the bias and white parts are independent.
  const double sigma_fixed_m = std::hypot(sigma_b, config.gnss_white_sigma_m);
  // Vertical RTK scatter is typically about twice the horizontal (assumption). The 2-D model
  // draws it from the horizontal white stream; a 3-D site draws (and discards) that number, so
  // that its horizontal noise is its level twin's, and takes its vertical bias and white noise
  // from streams of their own, gnss_vertical_factor times the horizontal ones.
  const double sigma_up_m = 2.0 * config.gnss_white_sigma_m;
  const bool three_d = site.has_ground;
  const double factor = config.GnssVerticalFactor();
  std::optional<Noise> vertical_bias_noise, vertical_white_noise;
  double vertical_bias_m = 0.0;
  if (three_d) {
    vertical_bias_noise.emplace(seed, Stream::kGnssVerticalBias);
    vertical_white_noise.emplace(seed, Stream::kGnssVerticalWhite);
    vertical_bias_m = vertical_bias_noise->Normal(factor * sigma_b);
  }

  std::vector<io::GnssFix> fixes;
  const int64_t count = SampleCount(trajectory.duration_s(), config.gnss_rate_hz);
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
    if (three_d && j > 0) {
      vertical_bias_m =
          phi * vertical_bias_m + vertical_bias_noise->Normal(factor * sigma_b * drive);
    }
    const double vertical_white_m =
        three_d ? vertical_white_noise->Normal(factor * config.gnss_white_sigma_m) : 0.0;
    const bool is_float =
        std::any_of(float_periods.begin(), float_periods.end(),
                    [t_s](const auto& p) { return t_s >= p.first && t_s < p.second; });
    // An RTK float solution is roughly ten times worse than fixed (brief's assumption).
    const double scale = is_float ? 10.0 : 1.0;
    const Pose pose = trajectory.At(t_s);
    const Eigen::Vector2d p = pose.antenna_enu_m + scale * (bias + white);

    io::GnssFix fix;
    fix.stamp_s = config.start_time_s + t_s;
    if (config.gnss_latency_s > 0.0 || config.gnss_jitter_s > 0.0) {
      // The sentence keeps its epoch; the logger stamps its arrival.
      fix.utc_epoch_s = fix.stamp_s;
      fix.stamp_s += config.gnss_latency_s + config.gnss_jitter_s * jitter_noise.Uniform();
    }
    const double height_m = three_d ? site.AntennaUpM(pose.antenna_enu_m) +
                                          scale * (vertical_bias_m + vertical_white_m)
                                    : scale * up_m;
    enu.Reverse(p.x(), p.y(), height_m, fix.lat_deg, fix.lon_deg, fix.height_m);
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
// configured rate and a sign drawn from the seed (Barawid 2007: FOG drift ±0.5°/h).
std::vector<io::HeadingSample> SimulateHeadings(const sim::SimulationConfig& config,
                                                const Trajectory& trajectory, uint64_t seed) {
  Noise noise(seed, Stream::kHeading);
  const double drift_rad_per_s =
      (noise.Uniform() < 0.5 ? -1.0 : 1.0) * config.heading_drift_rad_per_s;
  std::vector<io::HeadingSample> headings;
  const int64_t count = SampleCount(trajectory.duration_s(), config.heading_rate_hz);
  headings.reserve(count);
  for (int64_t j = 0; j < count; ++j) {
    const double t_s = j / config.heading_rate_hz;
    const double true_heading_rad = HeadingFromYaw(trajectory.At(t_s).yaw_rad);  // cw from true north
    io::HeadingSample sample;
    sample.stamp_s = config.start_time_s + t_s + config.heading_latency_s;
    sample.heading_rad =
        WrapTwoPi(true_heading_rad + config.heading_bias_rad + drift_rad_per_s * t_s +
                  noise.Normal(config.heading_white_sigma_rad));
    headings.push_back(sample);
  }
  return headings;
}

// ---- Attitude -------------------------------------------------------------------------------
// The vehicle's true roll and pitch on the ground (Site::AttitudeAt) plus white noise of
// attitude_white_sigma_rad on each, roll then pitch drawn per sample.
std::vector<io::AttitudeSample> SimulateAttitudes(const sim::SimulationConfig& config,
                                                  const Trajectory& trajectory, const Site& site,
                                                  uint64_t seed) {
  std::vector<io::AttitudeSample> attitudes;
  if (!(config.attitude_rate_hz > 0.0)) return attitudes;
  Noise noise(seed, Stream::kAttitude);
  const double sigma_rad = config.attitude_white_sigma_rad;
  const int64_t count = SampleCount(trajectory.duration_s(), config.attitude_rate_hz);
  attitudes.reserve(count);
  for (int64_t j = 0; j < count; ++j) {
    const double t_s = j / config.attitude_rate_hz;
    const VehicleAttitude truth = site.AttitudeAt(trajectory.At(t_s).yaw_rad);
    io::AttitudeSample sample;
    sample.stamp_s = config.start_time_s + t_s + config.heading_latency_s;
    sample.roll_rad = truth.roll_rad + noise.Normal(sigma_rad);
    sample.pitch_rad = truth.pitch_rad + noise.Normal(sigma_rad);
    sample.roll_sigma_rad = sigma_rad;
    sample.pitch_sigma_rad = sigma_rad;
    attitudes.push_back(sample);
  }
  return attitudes;
}

// The true pose at true time t_s: the planned (horizontal) pose on the site's ground.
SimTruthPose TruthAt(const sim::SimulationConfig& config, const Site& site,
                     const Trajectory& trajectory, double t_s) {
  const Pose pose = trajectory.At(t_s);
  SimTruthPose truth;
  truth.stamp_s = config.start_time_s + t_s;
  truth.antenna_enu_m = pose.antenna_enu_m;
  truth.yaw_enu_rad = pose.yaw_rad;
  truth.stationary = pose.stationary;
  const VehicleAttitude attitude = site.AttitudeAt(pose.yaw_rad);
  truth.roll_rad = attitude.roll_rad;
  truth.pitch_rad = attitude.pitch_rad;
  truth.antenna_up_m = site.AntennaUpM(pose.antenna_enu_m);
  return truth;
}

SimScannerPose ScannerPoseAt(const ScannerMount& mount, const SimTruthPose& pose) {
  return ScannerPoseOf(mount, pose.antenna_enu_m, pose.antenna_up_m, pose.yaw_enu_rad,
                       {pose.roll_rad, pose.pitch_rad});
}

// ---- Survey ---------------------------------------------------------------------------------
// Total-station frame: x axis rotated survey_rotation_rad ccw from true east, origin at
// (survey_origin_x_m, survey_origin_y_m) ENU; z the ENU up from the site origin (the 2-D
// model's ground and wall foot: z = 0).
struct SurveyFrame {
  Eigen::Vector2d origin_enu_m;
  double rotation_rad;
  Eigen::Vector2d ToStation(const Eigen::Vector2d& p_enu) const {
    return Rotate(-rotation_rad, p_enu - origin_enu_m);
  }
};

}  // namespace

std::vector<Eigen::Vector2d> SurveyStationsAlong(const SimWall& w) {
  const Eigen::Vector2d w0(w.x0_m, w.y0_m), w1(w.x1_m, w.y1_m);
  const double length_m = (w1 - w0).norm();
  if (!(length_m > 0.0)) return {w0};
  const double spacing_m = w.survey_spacing_m > 0.0 ? w.survey_spacing_m : 1.0;
  const int steps = static_cast<int>(std::floor(length_m / spacing_m + 1e-9));
  std::vector<Eigen::Vector2d> stations;
  for (int k = 0; k <= steps; ++k) stations.push_back(w0 + (k * spacing_m / length_m) * (w1 - w0));
  return stations;
}

std::vector<double> SurveyHeightsM(const SimWall& w, SurveyMode mode) {
  if (!w.survey_heights_m.empty()) return w.survey_heights_m;
  if (mode == SurveyMode::kRover) return {0.0};
  return {0.5, w.height_m - 0.5};
}

io::ScannerPreset TrueScannerPreset(const sim::SimulationConfig& config,
                                    const io::ScannerPreset& preset) {
  io::ScannerPreset truth = preset;
  if (!std::isnan(config.truth_scale_n)) truth.sim_scale_n = config.truth_scale_n;
  if (!std::isnan(config.truth_offset_c_m)) truth.sim_offset_c_m = config.truth_offset_c_m;
  if (!std::isnan(config.truth_sigma_m)) truth.range_sigma_m = config.truth_sigma_m;
  if (!std::isnan(config.truth_resolution_m)) truth.range_resolution_m = config.truth_resolution_m;
  if (!std::isnan(config.truth_max_incidence_rad)) {
    truth.max_incidence_rad = config.truth_max_incidence_rad;
  }
  // The unit's own errors on top: the tool's corrected range k·z + b moves by e_k·k·n·y + e_b.
  if (!std::isnan(config.range_scale_error)) {
    truth.sim_scale_n *= 1.0 + config.range_scale_error;
  }
  if (!std::isnan(config.range_offset_error_m)) {
    truth.sim_offset_c_m += config.range_offset_error_m / preset.range_scale_k;
  }
  return truth;
}

namespace {

// The seed of one scanner's own draws: the k-th scanner of a multi-scanner session draws from
// streams of its own (k = 0 leaves the seed as it is: a one-scanner session is unchanged).
uint64_t ScannerSeed(const sim::SimulationConfig& config, uint64_t seed) {
  return seed ^ (static_cast<uint64_t>(config.scanner_noise_stream) * 0x9E3779B97F4A7C15ull);
}

}  // namespace

sim::SimulationConfig UnitRangeErrors(const sim::SimulationConfig& config,
                                      const io::ScannerPreset& preset, uint64_t seed) {
  if (!config.draw_unit_range_models) return config;
  sim::SimulationConfig resolved = config;
  Noise noise(ScannerSeed(config, seed), Stream::kUnitRangeModel);
  const double scale_error = std::clamp(noise.Normal(preset.range_scale_sigma), -0.5, 0.5);
  const double offset_error_m = std::clamp(noise.Normal(preset.range_offset_sigma_m), -1.0, 1.0);
  if (std::isnan(resolved.range_scale_error)) resolved.range_scale_error = scale_error;
  if (std::isnan(resolved.range_offset_error_m)) resolved.range_offset_error_m = offset_error_m;
  return resolved;
}

double RangeDriftM(const sim::SimulationConfig& config, double t_s) {
  if (config.truth_drift_amplitude_m == 0.0) return 0.0;
  if (config.truth_drift_time_constant_s <= 0.0) return config.truth_drift_amplitude_m;
  return config.truth_drift_amplitude_m * (1.0 - std::exp(-t_s / config.truth_drift_time_constant_s));
}

sim::SimulationConfig WithDefaultWalls(sim::SimulationConfig config) {
  if (!config.walls.empty()) return config;
  sim::SimWall wall;
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
const sim::SimWall& CheckTrajectoryConfig(const sim::SimulationConfig& config) {
  config.Validate();
  const auto first_surveyed = std::find_if(config.walls.begin(), config.walls.end(),
                                           [](const sim::SimWall& w) { return !w.code.empty(); });
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
  Require(config.station_distance_far_m == 0.0 || config.station_distance_far_m > reach_m,
          "simulation.station_distance_far_m must be 0 or exceed the mount's distance from the "
          "antenna + 0.1 m, got " + std::to_string(config.station_distance_far_m));
  for (const sim::SimStop& stop : config.stops) {
    Require(stop.distance_m > reach_m && stop.dwell_s >= 0.0 && stop.wait_s >= 0.0 &&
                !config.continuous,
            "simulation stops: each distance must exceed the mount's reach + 0.1 m, dwell and "
            "wait must be >= 0, and the plan stop and go");
  }
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

double RunDurationS(const sim::SimulationConfig& config) {
  return PlanTrajectory(config, CheckTrajectoryConfig(config)).duration_s();
}

std::vector<SimTruthPose> TruePosesAt(const sim::SimulationConfig& config,
                                      const std::vector<double>& t_s) {
  const Trajectory trajectory = PlanTrajectory(config, CheckTrajectoryConfig(config));
  const Site site = SiteOf(config);
  std::vector<SimTruthPose> poses;
  poses.reserve(t_s.size());
  for (double t : t_s) poses.push_back(TruthAt(config, site, trajectory, t));
  return poses;
}

SimScannerPose TrueScannerPose(const sim::SimulationConfig& config, const SimTruthPose& pose) {
  return ScannerPoseAt(MountOf(config), pose);
}

std::vector<SimBeamHit> TrueBeamHits(const sim::SimulationConfig& config,
                                     const io::ScannerPreset& preset, const SimTruthPose& pose) {
  const Scene scene(config);
  const SimScannerPose scanner = TrueScannerPose(config, pose);
  const Eigen::Vector3d& origin = scanner.origin_enu_m;
  const double cos_max_incidence = std::cos(preset.max_incidence_rad);
  const double half_rad = 0.4 * preset.angular_step_rad;  // footprint edges, as in ScannerModel
  std::vector<SimBeamHit> hits;
  hits.reserve(std::max(0, preset.num_beams));
  for (int i = 0; i < preset.num_beams; ++i) {
    SimBeamHit hit;
    hit.bearing_rad = preset.start_angle_rad + i * preset.angular_step_rad;
    const std::optional<Hit> centre = scene.Cast(origin, scanner.BeamEnu(hit.bearing_rad));
    if (centre) {
      hit.range_m = centre->range_m;
      hit.wall_index = centre->wall_index;
      hit.ground = centre->surface == Surface::kGround;
      hit.cos_incidence = centre->cos_incidence;
      hit.returned = centre->cos_incidence >= cos_max_incidence &&
                     centre->range_m < preset.max_range_m;
    }
    const auto lo = scene.Cast(origin, scanner.BeamEnu(hit.bearing_rad - half_rad));
    const auto hi = scene.Cast(origin, scanner.BeamEnu(hit.bearing_rad + half_rad));
    // As in ScannerModel: a jump needs two surfaces (one wall seen obliquely is none, nor is
    // the ground).
    hit.footprint_edge =
        lo && hi && !OneSurface(*lo, *hi) && std::abs(lo->range_m - hi->range_m) > 0.1;
    hits.push_back(hit);
  }
  return hits;
}

SimulatedSession Simulate(const sim::SimulationConfig& config, const io::ScannerPreset& preset,
                          uint64_t seed, const ScanSink& sink) {
  const sim::SimWall* first_surveyed = &CheckTrajectoryConfig(config);
  Require(config.gnss_rate_hz > 0.0 && config.heading_rate_hz > 0.0,
          "simulation.gnss_rate_hz and simulation.heading_rate_hz must be > 0");
  Require(preset.num_beams > 0 && preset.rate_hz > 0.0 && preset.angular_step_rad != 0.0,
          "scanner preset '" + preset.name +
              "' must have num_beams > 0, rate_hz > 0 and a non-zero angular step");
  Require(preset.max_range_m > 0.0,
          "scanner preset '" + preset.name + "' must have max_range_m > 0");

  SimulatedSession session;
  const Trajectory trajectory = PlanTrajectory(config, *first_surveyed);
  const Site site = SiteOf(config);
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
    session.truth_poses.push_back(TruthAt(config, site, trajectory, k / kTruthPeriodDivisor));
  }

  session.fixes = SimulateGnss(config, trajectory, site, enu, seed);
  session.headings = SimulateHeadings(config, trajectory, seed);
  session.attitudes = SimulateAttitudes(config, trajectory, site, seed);

  // Rover survey: the pole's tip at the foot of the wall (or on its face at survey_heights_m)
  // every survey_spacing_m, measured straight in the GNSS's frame (the simulator's WGS84); no
  // control points.
  if (config.survey_mode == SurveyMode::kRover) {
    Noise rover_noise(seed, Stream::kSurvey);
    int number = 0;
    for (const auto& w : config.walls) {
      if (w.code.empty()) continue;
      for (const Eigen::Vector2d& p_enu : SurveyStationsAlong(w)) {
        for (double h_m : SurveyHeightsM(w, config.survey_mode)) {
          const Eigen::Vector3d q = WallFacePoint(site, w, p_enu, h_m);
          io::SurveyPoint point;
          char id[16];
          std::snprintf(id, sizeof(id), "R%03d", ++number);
          point.id = id;
          point.code = w.code;
          point.frame = io::SurveyFrame::kGeodetic;
          const double e = q.x() + rover_noise.Normal(config.rover_sigma_m);
          const double n = q.y() + rover_noise.Normal(config.rover_sigma_m);
          const double u = q.z() + rover_noise.Normal(2.0 * config.rover_sigma_m);
          enu.Reverse(e, n, u, point.lat_deg, point.lon_deg, point.z_m);
          session.survey.push_back(point);
        }
      }
    }
  }

  // Survey: control points first (as a crew would set them up), then the walls.
  if (config.survey_mode == SurveyMode::kTotalStation) {
    const SurveyFrame frame{{config.survey_origin_x_m, config.survey_origin_y_m},
                            config.survey_rotation_rad};
    Noise survey_noise(seed, Stream::kSurvey);
    Noise control_noise(seed, Stream::kControl);
    const double sigma_ts = config.total_station_sigma_m;
    auto add_point = [&](const std::string& id, const std::string& code,
                         const Eigen::Vector2d& p_enu, double z_m) {
      // The total station is levelled, its z the ENU up.
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
      // On the ground: a 3-D site's graded yard, the 2-D model's z = 0.
      const double ground_m = site.has_ground ? site.GroundUpM(p_enu) : 0.0;
      add_point(id, "CTRL", p_enu, ground_m);
      io::ControlPoint control;
      control.id = id;
      const double e = p_enu.x() + control_noise.Normal(config.control_sigma_m);
      const double n = p_enu.y() + control_noise.Normal(config.control_sigma_m);
      const double u_noise_m = control_noise.Normal(config.control_sigma_m);
      const double u = site.has_ground ? ground_m + u_noise_m : u_noise_m;
      enu.Reverse(e, n, u, control.lat_deg, control.lon_deg, control.h_m);
      session.control.push_back(control);
    }

    // Wall points every survey_spacing_m from the first end, on the face at each survey height
    // above the foot (0.5 m and height − 0.5 m unless the wall says): with a lean, the points
    // at two heights give it.
    int number = 0;
    for (const auto& w : config.walls) {
      if (w.code.empty()) continue;
      for (const Eigen::Vector2d& p_enu : SurveyStationsAlong(w)) {
        for (double h_m : SurveyHeightsM(w, config.survey_mode)) {
          const Eigen::Vector3d q = WallFacePoint(site, w, p_enu, h_m);
          char id[16];
          std::snprintf(id, sizeof(id), "W%03d", ++number);
          add_point(id, w.code, {q.x(), q.y()}, q.z());
        }
      }
    }
  }

  // Scans: k/rate true time; the logger stamps them scanner_time_offset_s early,
  // scanner_latency_s late and, with scanner_jitter_s, a further U(0, jitter) late. The
  // scanner measures with the scenario's scanner_truth where it overrides the preset and with
  // its unit's own errors (drawn here when asked for and not given).
  const io::ScannerPreset true_preset =
      TrueScannerPreset(UnitRangeErrors(config, preset, seed), preset);
  const uint64_t scanner_seed = ScannerSeed(config, seed);
  ScannerModel scanner(config, true_preset, scanner_seed);
  const ScannerMount mount = MountOf(config);
  Noise lost_noise(scanner_seed, Stream::kLostScan);
  Noise jitter_noise(scanner_seed, Stream::kScanJitter);  // its own stream: other draws unchanged
  const int64_t log_every = std::max<int64_t>(1, std::llround(config.log_every_n));
  const int64_t scan_count =
      static_cast<int64_t>(std::floor(duration_s * preset.rate_hz + 1e-9)) + 1;
  for (int64_t k = 0; k < scan_count; ++k) {
    ++session.scans_generated;
    if (k % log_every != 0) continue;
    // Lost packets on the serial link (Ye & Borenstein 2002: ≤ 0.08 % at 500 kbaud).
    if (lost_noise.Uniform() < config.lost_scan_fraction) {
      ++session.scans_lost;
      continue;
    }
    const double t_s = k / preset.rate_hz;
    // The whole scan is taken at one instant: at ≤ 1 m/s and 13 ms per sweep the vehicle moves
    // ≤ 13 mm during a sweep. At the stations that is exact; in continuous mode it leaves out
    // the sweep's motion skew (the tool treats scans as instantaneous too).
    scanner.set_drift_m(RangeDriftM(config, t_s));
    double stamp_s =
        config.start_time_s + t_s - config.scanner_time_offset_s + config.scanner_latency_s;
    if (config.scanner_jitter_s > 0.0) stamp_s += config.scanner_jitter_s * jitter_noise.Uniform();
    const io::ScanRecord scan =
        scanner.Scan(ScannerPoseAt(mount, TruthAt(config, site, trajectory, t_s)), stamp_s);
    ++session.scans_written;
    if (sink) sink(scan);
  }
  session.ground_returns = scanner.ground_returns();
  return session;
}

}  // namespace wallcal::sim
