// SPDX-License-Identifier: Apache-2.0
// The pre-flight check of a whole session (InspectSession): preset, logs (session_logs.cc),
// survey, stations, wall detection by the calibration pipeline itself, and the verdict.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <future>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "calib/attitude_model.h"
#include "calib/geodesy.h"
#include "calib/pose_samples.h"
#include "calib/rover_survey.h"
#include "calib/survey_tie.h"
#include "calib/time_alignment.h"
#include "common/angles.h"
#include "io/config/session_reader.h"
#include "io/survey/survey_reader.h"
#include "io/version.h"
#include "pipeline/calibration.h"
#include "pipeline/config_dirs.h"
#include "preflight/internal/inspect_internal.h"

namespace wallcal::preflight {

using namespace internal;  // the helpers shared by the inspect files

namespace {

// The yard the antenna's RTK heights show, as calibrate fits it (calib::FitYard, the noise's
// shape from the solver options): its grade, where it rises towards, and what to do about it.
std::string YardLine(const io::SessionSpec& spec, const solvers::SolverOptions& solver,
                     const std::vector<calib::PositionSample>& positions,
                     const std::vector<const io::GnssFix*>& used) {
  std::vector<calib::HeightSample> heights;
  for (size_t i = 0; i < positions.size() && i < used.size(); ++i) {
    heights.push_back({positions[i].p_local_m, used[i]->height_m, positions[i].stamp_s});
  }
  calib::HeightNoise noise;
  noise.bias_sigma_m = solver.gnss_bias_sigma_m;
  noise.bias_tau_s = solver.gnss_bias_tau_s;
  noise.white_sigma_m = solver.gnss_white_sigma_m;
  const calib::YardPlane yard = calib::FitYard(heights, noise);
  if (heights.size() < 3) return "not measured: fewer than 3 fixes";
  if (!yard.fitted) {
    return "not measured: the antenna's positions lie along one line (where the yard is not "
           "level, stand at two distances from the wall or log an attitude stream)";
  }
  std::string line = Fmt("%.1f", yard.GradePercent()) + " ± " +
                     Fmt("%.1f", 100.0 * yard.GradeSigma()) +
                     " % rising towards " + Fmt("%.0f", yard.RiseDirectionDeg(1.0)) + "° (" +
                     std::to_string(yard.samples) + " antenna heights, " +
                     Fmt("%.3f", yard.residual_rms_m) + " m RMS about the plane)";
  if (!yard.ToldFromLevel()) return line + "; level within its σ";
  if (spec.scanner_z_m) return line + "; not level: scanner.z_m is given";
  return line + "; not level: give scanner.z_m (the scanner's height relative to the antenna; "
                "--suggest-session writes its line)";
}

// One scanner's inspection: the session itself (scanner_index -1) or its scanners[index].
SessionInspection InspectOneScanner(const std::string& session_path,
                                    const std::string& config_path, int scanner_index) {
  SessionInspection result;
  const io::SessionSpec spec =
      scanner_index < 0 ? io::ReadSession(session_path)
                        : io::SessionForScanner(io::ReadSession(session_path),
                                                static_cast<size_t>(scanner_index));
  pipeline::CalibrateOptions options;
  if (!config_path.empty()) options = pipeline::ReadCalibrateOptions(config_path);
  options.Validate();
  auto block = [&](const std::string& text) { result.blockers.push_back(text); };
  auto warn = [&](const std::string& text) { result.warnings.push_back(text); };

  std::ostringstream out;
  out << "wallcal inspect " << io::kToolVersion << ": session '" << spec.name << "' ("
      << spec.file << ")\n";

  // --- Scanner preset ------------------------------------------------------------------
  std::optional<io::ScannerPreset> preset;
  try {
    preset = pipeline::LoadSessionPreset(spec.scanner_model, spec.dir);
    out << "  scanner   " << preset->name << ": " << preset->num_beams << " beams, "
        << Fmt("%.2f", preset->rate_hz) << " Hz, max range " << Fmt("%.1f", preset->max_range_m)
        << " m\n";
  } catch (const io::InputError& e) {
    block(std::string("scanner preset: ") + e.what());
    out << "  scanner   preset '" << spec.scanner_model << "' not found\n";
  }


  // --- Wall detection starts now, on its own thread: the calibrate pipeline itself (its
  // preview: no repeatability, no error budget) reads the scan log while the logs are
  // inspected here. Its outcome is used below only when nothing blocks it.
  std::future<pipeline::CalibrationResult> preview;
  if (preset) {
    pipeline::CalibrateRequest request;
    request.session_path = session_path;
    request.config_path = config_path;
    request.preview = true;
    request.scanner_index = scanner_index;
    preview = std::async(std::launch::async,
                         [request]() { return pipeline::RunCalibration(request); });
  }

  // The preview's outcome, taken once: by the logs section, for the tally of the scan log its
  // second pass read (the log is then not read a second time), or at the detection section.
  const bool preview_started = preview.valid();
  std::optional<pipeline::CalibrationResult> preview_result;
  std::exception_ptr preview_failure;
  auto take_preview = [&]() {
    if (!preview.valid()) return;
    try {
      preview_result = preview.get();
    } catch (...) {
      preview_failure = std::current_exception();
    }
  };
  auto shared_scan_log = [&]() -> std::optional<ScanLogSummary> {
    take_preview();
    if (!preview_result || !preview_result->detection.scan_log) return std::nullopt;
    return SummaryFromTally(spec.scanner_log, std::move(*preview_result->detection.scan_log),
                            preview_result->detection.scan_lines_skipped);
  };

  // --- Logs ------------------------------------------------------------------------------
  SessionLogs logs = InspectSessionLogs(spec, options, preset ? &*preset : nullptr,
                                        shared_scan_log, &result, out);
  std::optional<ScanLogSummary>& scans = logs.scans;
  std::optional<io::NmeaLog>& gnss = logs.gnss;
  std::optional<io::NmeaLog>& heading_log = logs.heading_log;
  const int64_t accepted_fixes = logs.accepted_fixes;

  // --- Survey and control points ------------------------------------------------------------
  out << "\nsurvey\n";
  std::optional<calib::LocalFrame> frame;
  if (!spec.control.empty()) {
    frame = calib::MakeLocalFrame(spec.control.front().lat_deg, spec.control.front().lon_deg,
                                  spec.utm_zone);
  }
  try {
    std::vector<io::SurveyPoint> observations =
        io::ReadSurvey(spec.survey_points, spec.survey_columns);
    const bool rover = calib::IsRoverSurvey(observations);
    if (rover) {
      // Rover points are where the GNSS is: no tie (calib/rover_survey.h).
      if (!spec.control.empty()) {
        throw io::InputError(io::Where(spec.file, spec.control.front().line,
                                       "survey.control given for a rover survey (latitude, "
                                       "longitude); expected no survey.control"));
      }
      frame = calib::RoverSurveyFrame(observations, spec.survey_points, spec.utm_zone);
      observations = calib::PlaceRoverPoints(
          observations, spec.survey_points, *frame,
          spec.survey_point_sigma_m.value_or(io::kDefaultRoverPointSigmaM));
    }
    const std::vector<io::SurveyPoint> survey =
        io::CombineSurveyObservations(observations).points;
    out << "  points    " << survey.size() << " in " << FileName(spec.survey_points)
        << (rover ? " (rover: latitude, longitude)" : "") << "\n";
    if (!frame) throw io::InputError(io::Where(spec.file, 0, "no survey.control points"));
    const calib::SurveyTie tie =
        rover ? calib::RoverTie()
              : calib::TieSurvey(survey, spec.survey_points, spec, *frame, options.solver.survey());
    out << "  control   " << tie.num_control << " points";
    if (rover) {
      out << " (rover points need no tie)\n";
    } else if (tie.num_control >= 2) {
      out << ", fit RMS " << Fmt("%.1f", 1000.0 * tie.control_rms_m) << " mm\n";
      for (const calib::ControlResidual& r : tie.control_residuals) {
        out << "    " << r.id << "  residual east " << Fmt("%+.1f", 1000.0 * r.residual_m.x())
            << " mm, north " << Fmt("%+.1f", 1000.0 * r.residual_m.y()) << " mm ("
            << Fmt("%.1f", 1000.0 * r.residual_m.norm()) << " mm)\n";
      }
      const double expected_m =
          std::hypot(options.solver.control_sigma_m, options.solver.total_station_sigma_m);
      if (tie.control_rms_m > 3.0 * expected_m) {
        warn("control points fit the survey with RMS " + Fmt("%.1f", 1000.0 * tie.control_rms_m) +
             " mm, more than 3x the expected " + Fmt("%.1f", 1000.0 * expected_m) +
             " mm: check the control ids and their RTK positions");
      }
    } else {
      out << " (rotation given: no residuals to check)\n";
    }
    const std::vector<calib::WallGeometry> walls =
        calib::FitWalls(survey, spec.survey_points, spec, tie, options.solver.survey());
    for (size_t w = 0; w < walls.size(); ++w) {
      out << "  wall      " << walls[w].id << " (" << spec.walls[w].code << "): "
          << walls[w].num_points << " points over "
          << Fmt("%.2f", (walls[w].end_b_local - walls[w].end_a_local).norm()) << " m, fit RMS "
          << Fmt("%.1f", 1000.0 * walls[w].rms_m) << " mm\n";
    }
  } catch (const io::InputError& e) {
    block(std::string("survey: ") + e.what());
    out << "  unusable: " << e.what() << "\n";
  }

  // --- Stations from GNSS + heading (as calibrate finds them) -------------------------------
  std::vector<calib::Dwell> dwells;
  std::string yard_line;
  std::vector<double> logged_grid_headings_rad;
  bool have_poses = false;
  if (gnss && heading_log && accepted_fixes >= 2 && heading_log->headings.size() >= 2) {
    std::vector<calib::PositionSample> positions;
    std::vector<const io::GnssFix*> used;
    if (!frame) {
      const io::GnssFix* first = nullptr;
      for (const io::GnssFix& fix : gnss->fixes) {
        if (io::FixQualityAccepted(fix.quality, spec.min_fix_quality)) {
          first = &fix;
          break;
        }
      }
      frame = calib::MakeLocalFrame(first->lat_deg, first->lon_deg, spec.utm_zone);
    }
    positions = calib::PositionSamples(*gnss, spec.min_fix_quality, *frame, &used);
    yard_line = YardLine(spec, options.solver, positions, used);
    const std::vector<calib::YawSample> yaws =
        calib::YawSamples(*heading_log, spec.heading_reference, *frame, used);
    for (const calib::YawSample& sample : yaws) {
      logged_grid_headings_rad.push_back(HeadingFromYaw(sample.yaw_rad));
    }
    if (positions.size() >= 2 && yaws.size() >= 2) {
      try {
        const calib::PoseInterpolator poses(positions, yaws, options.alignment);
        dwells = poses.dwells();
        have_poses = poses.start_s() < poses.end_s();
      } catch (const std::exception& e) {
        block(std::string("poses: ") + e.what());
      }
    }
  } else if (heading_log) {
    for (const io::HeadingSample& h : heading_log->headings) {
      logged_grid_headings_rad.push_back(h.heading_rad);
    }
  }

  // --- Wall detection: the calibrate pipeline itself -------------------------------------
  std::optional<pipeline::CalibrationResult> calibration;
  std::string detection_note;
  take_preview();
  if (result.blockers.empty() && preview_started) {
    try {
      if (preview_failure) std::rethrow_exception(preview_failure);
      calibration = std::move(preview_result);
    } catch (const io::InputError& e) {
      block(e.what());
      detection_note = "not run to the end: " + std::string(e.what());
    }
  } else {
    // Its outcome is not used (an error in it neither).
    detection_note = "not run: the problems listed in the verdict come first";
  }

  // The pipeline stops after the first (subsampled, wide-gate) pass when that pass finds no
  // wall or its estimate is refused; only in the first case are the detections complete.
  bool detections_complete = false;
  bool wall_never_seen = false;
  if (calibration) {
    const bool first_pass_refused = !calibration->detection.first_pass.usable;
    wall_never_seen = first_pass_refused && calibration->detection.first_pass.failure ==
                                                solvers::EstimateFailure::kWallNotDetected;
    detections_complete = !first_pass_refused || wall_never_seen;
    if (!detections_complete) {
      detection_note = "stopped after the first pass (estimate refused: " +
                       calibration->detection.first_pass.message + ")";
    }
  }

  if (calibration && !calibration->detection.scanner_from_data.empty()) {
    out << "  scanner   " << calibration->loaded.preset.name
        << "'s range model; from the data: " << calibration->detection.scanner_from_data << "\n";
  }
  if (!yard_line.empty()) out << "  yard      " << yard_line << "\n";
  out << "\nstations (stops of at least " << Fmt("%.1f", options.alignment.min_dwell_s)
      << " s): " << dwells.size() << "\n";
  std::vector<double> seen_headings_rad;
  int stations_with_wall = 0;
  int64_t station_scans_total = 0, station_detections_total = 0;
  if (!dwells.empty()) {
    out << "     #  start       dur  heading   scans  wall seen        inliers  fit rms\n";
    // Each scan's observations (one per wall it saw), in scan order: scan k's are
    // sorted_obs[scan_obs[k]] .. sorted_obs[scan_obs[k + 1] - 1], and its time is its first
    // observation's. (A map of lists here took 0.4 s on an hour-long session.)
    std::vector<const calib::WallObservation*> sorted_obs;
    std::vector<size_t> scan_obs;
    std::vector<double> scan_stamp_s;  // scan k's time, side by side for the stations' scans
    if (calibration) {
      for (const calib::WallObservation& o : calibration->solve.observations)
        sorted_obs.push_back(&o);
      std::stable_sort(sorted_obs.begin(), sorted_obs.end(),
                       [](const calib::WallObservation* a, const calib::WallObservation* b) {
                         return a->scan_index < b->scan_index;
                       });
      for (size_t k = 0; k < sorted_obs.size(); ++k) {
        if (k == 0 || sorted_obs[k]->scan_index != sorted_obs[k - 1]->scan_index) {
          scan_obs.push_back(k);
          scan_stamp_s.push_back(sorted_obs[k]->pose.stamp_s);
        }
      }
      scan_obs.push_back(sorted_obs.size());
    }
    const double t0 = scans && scans->stats.records > 0 ? scans->stats.start_s : dwells.front().start_s;
    for (size_t d = 0; d < dwells.size(); ++d) {
      const calib::Dwell& dwell = dwells[d];
      int64_t n_scans = 0;
      if (scans) {
        for (double t : scans->stamps_s) n_scans += (t >= dwell.start_s && t <= dwell.end_s);
      }
      const double heading_deg = WrapTwoPi(HeadingFromYaw(dwell.mean_yaw_rad)) * kRadToDeg;
      char row[256];
      std::snprintf(row, sizeof(row), "  %4zu  %+8.1f s %5.1f s %6.1f° %7lld", d + 1,
                    dwell.start_s - t0, dwell.end_s - dwell.start_s, heading_deg,
                    static_cast<long long>(n_scans));
      out << row;
      station_scans_total += n_scans;
      if (!detections_complete) {
        out << "  -\n";
        continue;
      }
      int64_t detected = 0, inliers = 0, fits = 0;
      double rms_sum = 0.0;
      for (size_t k = 0; k + 1 < scan_obs.size(); ++k) {
        const double t = scan_stamp_s[k];
        if (t < dwell.start_s || t > dwell.end_s) continue;
        ++detected;
        for (size_t i = scan_obs[k]; i < scan_obs[k + 1]; ++i) {
          inliers += sorted_obs[i]->num_inliers;
          rms_sum += sorted_obs[i]->residual_rms_m;
          ++fits;
        }
      }
      station_detections_total += detected;
      if (detected > 0) ++stations_with_wall;
      const double share = n_scans > 0 ? 100.0 * static_cast<double>(detected) / static_cast<double>(n_scans) : 0.0;
      if (fits > 0) {
        std::snprintf(row, sizeof(row), "  %6lld (%3.0f%%)   %7.0f  %5.1f mm\n",
                      static_cast<long long>(detected), share,
                      static_cast<double>(inliers) / static_cast<double>(fits),
                      1000.0 * rms_sum / static_cast<double>(fits));
      } else {
        std::snprintf(row, sizeof(row), "  %6lld (%3.0f%%)         -        -\n",
                      static_cast<long long>(detected), share);
      }
      out << row;
    }
  }
  if (calibration) {
    // One heading per scan, its first observation's, in observation order.
    int max_scan = -1;
    for (const calib::WallObservation& o : calibration->solve.observations) {
      max_scan = std::max(max_scan, o.scan_index);
    }
    std::vector<uint8_t> seen(static_cast<size_t>(max_scan + 1), 0);
    for (const calib::WallObservation& o : calibration->solve.observations) {
      if (o.scan_index < 0 || seen[o.scan_index]) continue;
      seen[o.scan_index] = 1;
      seen_headings_rad.push_back(HeadingFromYaw(o.pose.yaw_rad));
    }
  }

  // --- Wall detection and heading coverage ------------------------------------------------
  out << "\nwall detection\n";
  if (calibration && detections_complete) {
    const pipeline::CalibrationResult& c = *calibration;
    out << "  scans     " << c.detection.scans_total << " in the log, wall seen in "
        << c.finish.coverage.scans_used;
    for (const auto& [reason, count] : c.ScansSkipped()) {
      out << "; " << count << " " << calib::ScanSkipName(reason);
    }
    out << "\n";
    out << "  observations " << c.solve.observations.size();
    if (!c.solve.observations.empty()) {
      double inl = 0.0, rms = 0.0;
      for (const calib::WallObservation& o : c.solve.observations) {
        inl += o.num_inliers;
        rms += o.residual_rms_m;
      }
      const double n = static_cast<double>(c.solve.observations.size());
      out << ", mean " << Fmt("%.0f", inl / n) << " inliers, mean fit RMS "
          << Fmt("%.1f", 1000.0 * rms / n) << " mm";
    }
    out << "\n";
  } else {
    out << "  " << detection_note << "\n";
  }
  out << "  headings (grid, clockwise from grid north)\n";
  out << "              " << HistogramAxis() << "\n";
  if (!logged_grid_headings_rad.empty()) {
    out << "    logged    " << Histogram(logged_grid_headings_rad) << "\n";
  }
  const AngleExtent seen = Extent(seen_headings_rad);
  if (calibration && detections_complete) {
    out << "    wall seen " << Histogram(seen_headings_rad);
    if (seen.any) {
      out << "  " << OccupiedBins(seen_headings_rad) << " bins, " << Fmt("%.1f", seen.min_deg)
          << "°.." << Fmt("%.1f", seen.max_deg) << "° (" << Fmt("%.1f", seen.width_deg) << "° wide)";
    }
    out << "\n";
  }

  // --- Verdict --------------------------------------------------------------------------------
  const solvers::SolverOptions& so = options.solver;
  const double min_spread_deg = so.min_heading_spread_rad * kRadToDeg;
  bool geometry_named = false;
  if (!dwells.empty() && !options.alignment.use_moving_scans) {
    std::vector<double> station_headings_rad;
    for (const calib::Dwell& dwell : dwells) {
      station_headings_rad.push_back(HeadingFromYaw(dwell.mean_yaw_rad));
    }
    const AngleExtent stations = Extent(station_headings_rad);
    out << "  stations  at grid headings " << Fmt("%.1f", stations.min_deg) << "°.."
        << Fmt("%.1f", stations.max_deg) << "° (" << Fmt("%.1f", stations.width_deg) << "° wide)\n";
    if (stations.width_deg < min_spread_deg) {
      block("narrow heading spread: the stations' grid headings span " +
            Fmt("%.1f", stations.min_deg) + "°.." + Fmt("%.1f", stations.max_deg) + "° only (" +
            Fmt("%.1f", stations.width_deg) + "° wide; at least " + Fmt("%.0f", min_spread_deg) +
            "° needed): stop at more varied headings to the wall");
      geometry_named = true;
    }
  }
  if (dwells.empty() && have_poses && !options.alignment.use_moving_scans) {
    block("too few stations: the vehicle never stood still for " +
          Fmt("%.1f", options.alignment.min_dwell_s) + " s (scans taken while moving are not used)");
    geometry_named = true;
  }
  if (calibration) {
    const pipeline::CalibrationResult& c = *calibration;
    if (wall_never_seen) {
      block("wall never detected: " + c.detection.first_pass.message);
      geometry_named = true;
    } else if (detections_complete) {
      if (stations_with_wall < so.min_stations && !dwells.empty() &&
          !options.alignment.use_moving_scans) {
        block("too few stations: the wall was seen at " + std::to_string(stations_with_wall) +
              " stops (at least " + std::to_string(so.min_stations) +
              " needed): stop at more places and headings in front of the wall");
        geometry_named = true;
      }
      if (seen.any && seen.width_deg < min_spread_deg && !geometry_named) {
        block("narrow heading spread: the wall was seen at grid headings " +
              Fmt("%.1f", seen.min_deg) + "°.." + Fmt("%.1f", seen.max_deg) + "° only (" +
              Fmt("%.1f", seen.width_deg) + "° wide; at least " + Fmt("%.0f", min_spread_deg) +
              "° needed): stop at more varied headings to the wall");
        geometry_named = true;
      }
      if (static_cast<int64_t>(c.solve.observations.size()) < so.min_observations) {
        block("too few observations: " + std::to_string(c.solve.observations.size()) +
              " (at least " + std::to_string(so.min_observations) + " needed)");
        geometry_named = true;
      }
      if (station_scans_total > 0 && 2 * station_detections_total < station_scans_total) {
        warn("wall rarely detected: in " + std::to_string(station_detections_total) + " of " +
             std::to_string(station_scans_total) +
             " scans at stations (check the wall is in range and unobstructed)");
      }
    }
    if (!c.solve.estimate.usable && !wall_never_seen) {
      block("calibrate refuses the estimate: " + c.Why());
    }
    for (const pipeline::Warning& w : c.AllWarnings()) {
      if (std::find(result.warnings.begin(), result.warnings.end(), w.message) ==
          result.warnings.end()) {
        warn(w.message);
      }
    }
    if (c.solve.estimate.usable) {
      out << "  preview   a calibration now gives x = " << Fmt("%.3f", c.solve.estimate.mount.x_m)
          << " m, y = " << Fmt("%.3f", c.solve.estimate.mount.y_m)
          << " m, yaw = " << Fmt("%.2f", c.solve.estimate.mount.yaw_rad * kRadToDeg) << "°";
      if (c.solve.preview_observations_solved < static_cast<int64_t>(c.solve.observations.size())) {
        // Thinned (pipeline/calibration.h): its residuals are not the session's.
        out << " (solved on " << c.solve.preview_observations_solved << " of "
            << c.solve.observations.size()
            << " observations, evenly spaced, each weighted to stand for the rest)\n";
      } else {
        out << " (residual RMS " << Fmt("%.1f", 1000.0 * c.solve.estimate.residual_rms_m)
            << " mm)\n";
      }
    }
  }

  result.enough = result.blockers.empty();
  out << "\nverdict\n";
  for (const std::string& w : result.warnings) out << "  warning: " << w << "\n";
  if (result.enough) {
    out << "  VERDICT: enough data for a calibration\n";
  } else {
    out << "  VERDICT: NOT enough data for a calibration:\n";
    for (const std::string& b : result.blockers) out << "    - " << b << "\n";
  }
  result.report = out.str();
  return result;
}

}  // namespace

SessionInspection InspectSession(const std::string& session_path, const std::string& config_path) {
  const io::SessionSpec spec = io::ReadSession(session_path);
  if (spec.scanners.empty()) return InspectOneScanner(session_path, config_path, -1);
  // Several scanners: each inspected as its own session (its scan log, its stations and
  // headings, whether it sees the wall); the GNSS, heading and survey sections repeat for each.
  SessionInspection all;
  all.enough = true;
  for (size_t k = 0; k < spec.scanners.size(); ++k) {
    const std::string& id = spec.scanners[k].id;
    const SessionInspection one =
        InspectOneScanner(session_path, config_path, static_cast<int>(k));
    all.report += "=== scanner '" + id + "' (" + std::to_string(k + 1) + " of " +
                  std::to_string(spec.scanners.size()) + ")\n" + one.report;
    all.enough = all.enough && one.enough;
    for (const std::string& b : one.blockers) all.blockers.push_back("scanner '" + id + "': " + b);
    for (const std::string& w : one.warnings) all.warnings.push_back("scanner '" + id + "': " + w);
  }
  all.report += all.blockers.empty()
                    ? "every scanner: enough to calibrate (calibrate adjusts them jointly)\n"
                    : "not every scanner can be calibrated (calibrate fails unless "
                      "--allow-partial): " + std::to_string(all.blockers.size()) + " blocker(s)\n";
  return all;
}

}  // namespace wallcal::preflight
