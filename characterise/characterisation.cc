// SPDX-License-Identifier: Apache-2.0
// The characterisation run (characterise/characterisation.h): calibrate's steps, the beams, the
// fit, the statistics, the refusals and the measured preset.

#include "characterise/characterisation.h"

#include <algorithm>
#include <cmath>
#include <ctime>

#include "characterise/beam_returns.h"
#include "characterise/range_fit.h"
#include "characterise/scanner_stats.h"
#include "common/angles.h"
#include "common/format.h"
#include "io/config/offsets_reader.h"
#include "io/version.h"

namespace wallcal::characterise {
namespace {

// Where to stand for the range scale: near and far within the scanner's reach.
std::string DistanceAdvice(const io::ScannerPreset& preset) {
  if (preset.max_range_m >= 20.0) return "stations from 3 m to 15 m from the wall";
  return Format("stations from %.1f m to %.1f m from the wall", 0.15 * preset.max_range_m,
                0.85 * preset.max_range_m);
}

void Refuse(Characterisation* result, Undetermined why, const std::string& reason) {
  result->undetermined = why;
  result->reason = reason;
}

}  // namespace

Characterisation Characterise(const CharacteriseRequest& request) {
  Characterisation result;
  // A bad --mount file fails before the work.
  std::optional<io::PreviousOffsets> given_mount;
  if (!request.mount_path.empty()) given_mount = io::ReadPreviousOffsets(request.mount_path);

  pipeline::CalibrateRequest calibrate;
  calibrate.session_path = request.session_path;
  calibrate.scanner_id = request.scanner_id;
  calibrate.config_path = request.config_path;
  calibrate.threads = request.threads;
  calibrate.command_line = request.command_line;
  // With a given mount the calibration only has to find the walls: a refusal of its own
  // estimate (σ, gross-error check) does not stop the characterisation.
  calibrate.force = given_mount.has_value();
  result.calibration = pipeline::RunCalibration(calibrate);
  const pipeline::CalibrationResult& calibration = result.calibration;
  const io::ScannerPreset& preset = calibration.loaded.preset;
  result.warnings = pipeline::Messages(calibration.AllWarnings());

  if (calibration.solve.observations.empty() ||
      (!given_mount && !calibration.solve.estimate.usable)) {
    Refuse(&result, Undetermined::kCalibrationFailed,
           "the session did not give " +
               std::string(given_mount ? "wall observations" : "a mount") + ": " +
               (calibration.Why().empty() ? std::string("no wall found in the scans")
                                          : calibration.Why()) +
               (given_mount ? "" : " (or pass a calibrated mount with --mount OFFSETS.yaml)"));
    return result;
  }

  FitSetup setup;
  if (given_mount) {
    setup.mount_prior = {given_mount->x_m, given_mount->y_m, given_mount->yaw_rad};
    setup.mount_given = true;
    setup.mount_sigma_given = given_mount->sigma_known;
    if (given_mount->sigma_known) {
      setup.mount_prior_covariance = Eigen::Map<const Eigen::Matrix3d>(given_mount->covariance);
      setup.mount_prior_covariance.diagonal().array() += 1e-12;
    } else {
      // No covariance in the file: the mount is taken as exact (0.1 mm, 0.001°).
      setup.mount_prior_covariance = Eigen::Vector3d(1e-8, 1e-8, 3e-10).asDiagonal();
      result.warnings.push_back(request.mount_path +
                                " has no covariance: its mount is taken as exact, so the σ of "
                                "k and b leave out the mount's error");
    }
  } else {
    // Estimated here, jointly with the range model: start at calibrate's mount (found with the
    // preset's range correction), loose prior (10 cm, 1°) so that the beams decide.
    setup.mount_prior = calibration.solve.estimate.mount;
    setup.mount_prior_covariance = Eigen::Vector3d(0.01, 0.01, std::pow(kDegToRad, 2)).asDiagonal();
  }

  const BeamSet beams = CollectBeams(calibration, setup.mount_prior);
  result.session_span_s = beams.span_s;
  if (static_cast<int>(beams.stations.size()) < kMinStations) {
    Refuse(&result, Undetermined::kNoStations,
           Format("%d stop-and-go stations found, at least %d needed: stop for 4 s or more at ",
                  static_cast<int>(beams.stations.size()), kMinStations) +
               DistanceAdvice(preset) + ", turning the vehicle between them");
    return result;
  }
  double quantum_share = 0.0;
  const double quantum_m = RangeQuantum(beams, &quantum_share);

  setup.beams = &beams;
  setup.walls = &calibration.survey.walls;
  setup.gnss_tau_s = calibration.loaded.options.solver.gnss_bias_tau_s;
  setup.heading_sigma_rad = calibration.SolverInUse().heading_sigma_rad;
  setup.gnss_white_sigma_m = calibration.SolverInUse().gnss_white_sigma_m;
  setup.gnss_bias_sigma_m = calibration.loaded.options.solver.gnss_bias_sigma_m;
  setup.quantum_m = quantum_m;
  setup.angular_step_rad = std::abs(preset.angular_step_rad);
  setup.start_n = 1.0 / preset.range_scale_k;
  setup.start_c_m = -preset.range_offset_b_m / preset.range_scale_k;
  setup.start_sigma_m = std::max(0.002, preset.range_sigma_m);
  const FitOutput fit = FitRangeModel(setup);
  result.model = fit.model;
  result.stats = MeasureStats(beams, fit, quantum_m, quantum_share);

  // Coverage: station distances (scanner to the wall its beams hit) and fitted incidences.
  {
    const calib::Mount mount{result.model.mount_x_m.value, result.model.mount_y_m.value,
                             result.model.mount_yaw_rad.value};
    std::vector<int> wall_of_station(beams.stations.size(), -1);
    for (const BeamReturn& beam : beams.beams) wall_of_station[beam.station] = beam.wall;
    bool first = true;
    for (size_t s = 0; s < beams.stations.size(); ++s) {
      if (wall_of_station[s] < 0) continue;
      const calib::WallGeometry& wall = calibration.survey.walls[wall_of_station[s]];
      const Ray ray = BeamRay(beams.stations[s], mount, 0.0);
      const double d = std::abs(wall.offset_m - wall.normal_local.dot(ray.origin));
      result.distance_min_m = first ? d : std::min(result.distance_min_m, d);
      result.distance_max_m = first ? d : std::max(result.distance_max_m, d);
      first = false;
    }
    first = true;
    const double gate_m = std::max(4.0 * fit.robust_sigma_m, 1e-3);
    size_t fitted = 0;
    for (size_t b = 0; b < beams.beams.size(); ++b) fitted += std::isfinite(fit.residual_m[b]);
    const size_t every = std::max<size_t>(1, fitted / 4000);
    size_t seen = 0;
    for (size_t b = 0; b < beams.beams.size(); ++b) {
      const double r = fit.residual_m[b];
      if (!std::isfinite(r) || std::abs(r) > gate_m) continue;
      const double inc = fit.incidence_rad[b];
      result.incidence_min_rad = first ? inc : std::min(result.incidence_min_rad, inc);
      result.incidence_max_rad = first ? inc : std::max(result.incidence_max_rad, inc);
      first = false;
      if (seen++ % every != 0) continue;
      // The raw reading's error against the true range (Ye & Borenstein 2002's plots).
      const double t = fit.true_range_m[b];
      result.plot.push_back({t, inc, beams.beams[b].time_s, beams.beams[b].z_m - t});
    }
  }

  const RangeModel& model = result.model;
  if (model.beams_used < kMinWallReturns) {
    Refuse(&result, Undetermined::kTooFewRanges,
           Format("only %d wall returns, at least %d needed: log longer at each station (or "
                  "more stations: ",
                  model.beams_used, kMinWallReturns) +
               DistanceAdvice(preset) + ")");
  } else if (const double max_sigma_k =
                 kMaxScaleErrorM / std::min(kMaxWorkingRangeM, preset.max_range_m);
             !(model.k.sigma <= max_sigma_k)) {
    Refuse(&result, Undetermined::kScaleK,
           Format("range scale k not determined (sigma %.4f > %.4f): the stations stood "
                  "%.1f-%.1f m from the wall; collect ",
                  model.k.sigma, max_sigma_k, result.distance_min_m, result.distance_max_m) +
               DistanceAdvice(preset));
  } else if (!(model.b_m.sigma <= kMaxSigmaB)) {
    Refuse(&result, Undetermined::kOffsetB,
           Format("range offset b not determined (sigma %.1f mm > %.1f mm): the wall was seen "
                  "at incidences %.0f-%.0f deg; collect returns from 0 to 60 deg (turn the "
                  "vehicle at each station) and ",
                  1e3 * model.b_m.sigma, 1e3 * kMaxSigmaB, result.incidence_min_rad * kRadToDeg,
                  result.incidence_max_rad * kRadToDeg) +
               DistanceAdvice(preset));
  }

  // What the data fix and what they cannot separate.
  result.notes.push_back(Format(
      "k is fixed by the stations' distances (%.1f-%.1f m); b by the incidences within each scan "
      "(%.0f-%.0f deg), which tell a range offset from a shift of the wall or the vehicle",
      result.distance_min_m, result.distance_max_m, result.incidence_min_rad * kRadToDeg,
      result.incidence_max_rad * kRadToDeg));
  if (model.k.known() && model.b_m.known()) {
    // σ of the correction k·z + b at a reading z: the range error the preset may add there.
    auto sigma_at = [&model](double z_m) {
      const double var = z_m * z_m * model.k.sigma * model.k.sigma +
                         model.b_m.sigma * model.b_m.sigma +
                         2.0 * z_m * model.corr_k_b * model.k.sigma * model.b_m.sigma;
      return std::sqrt(std::max(0.0, var));
    };
    result.notes.push_back(Format(
        "the correction k*z + b is known to +- %.1f mm at %.1f m and +- %.1f mm at %.1f m: the "
        "range error this preset may add there; it corrects a range offset only when that is "
        "well above these (sigma falls as 1/sqrt(stations))",
        1e3 * sigma_at(result.distance_min_m), result.distance_min_m,
        1e3 * sigma_at(result.distance_max_m), result.distance_max_m));
  }
  if (std::abs(model.corr_b_mount_x) > 0.9) {
    result.notes.push_back(Format(
        "b and the mount's x are not separable here (correlation %.2f): the wall was seen "
        "head-on; pass a mount calibrated on another session with --mount, or turn the vehicle",
        model.corr_b_mount_x));
  } else {
    result.notes.push_back(Format("b and the mount's x: correlation %.2f", model.corr_b_mount_x));
  }
  if (!model.drift_fitted) {
    result.notes.push_back(Format(
        "drift not measured: the session spans %.0f min; log an hour from power-on for the "
        "warm-up (Okubo et al. 2009)",
        result.session_span_s / 60.0));
  }

  // The measured preset: the session's preset's geometry with the measured range model.
  result.preset = preset;
  result.preset.name = request.preset_name.empty() ? preset.name + "_measured" : request.preset_name;
  result.preset.source = "measured by wallcal characterise " + std::string(io::kToolVersion) +
                         " on session '" + calibration.loaded.session.name + "' (" +
                         calibration.loaded.session.file + ") at " + NowUtcIso8601();
  result.preset.range_scale_k = model.k.value;
  result.preset.range_offset_b_m = model.b_m.value;
  // This unit's model is now known to the fit's σ, not to the family's spread.
  if (model.k.known() && model.b_m.known()) {
    result.preset.range_scale_sigma = model.k.sigma / model.k.value;
    result.preset.range_offset_sigma_m = model.b_m.sigma;
  }
  result.preset.sim_scale_n = model.n.value;
  result.preset.sim_offset_c_m = model.c_m.value;
  result.preset.range_sigma_m = model.sigma_m.value;
  if (result.stats.quantum_m > 0.0) result.preset.range_resolution_m = result.stats.quantum_m;
  if (result.stats.incidence_limit_reached) {
    result.preset.max_incidence_rad = result.stats.incidence_limit_rad.value;
  }
  return result;
}

}  // namespace wallcal::characterise
