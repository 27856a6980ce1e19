#include "apps/pipeline.h"

#include <unistd.h>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include <Eigen/Geometry>

#include "apps/repeatability.h"
#include "apps/residual_analysis.h"
#include "calib/geodesy.h"
#include "calib/range_model.h"
#include "calib/simulator.h"
#include "calib/survey_tie.h"
#include "calib/time_alignment.h"
#include "calib/wall_detector.h"
#include "io/carmen_reader.h"
#include "io/nmea_reader.h"
#include "io/session_reader.h"
#include "io/survey_reader.h"
#include "io/version.h"
#include "io/writers.h"

#ifndef WALLCAL_SOURCE_CONFIG_DIR
#define WALLCAL_SOURCE_CONFIG_DIR ""
#endif

namespace wallcal::app {
namespace {

// Clock offset (moving scans): at most this many re-interpolations of the poses at the
// estimated scan times, stopping when the offset left over is below the tolerance.
constexpr int kClockOffsetRounds = 3;
constexpr double kClockOffsetToleranceS = 2e-4;

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;
constexpr double kRadToDeg = 180.0 / kPi;

std::string Fmt(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

std::string ExecutableDir() {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  return error ? std::string() : exe.parent_path().string();
}

// Lines a healthy log has too (other NMEA sentences, comments, CARMEN PARAM/ODOM lines): they
// are counted but are no reason for a warning.
bool IsInformational(const std::string& reason) {
  return reason == "not NMEA" || reason == "comment" || reason == "blank line" ||
         reason.rfind("other sentence", 0) == 0 || reason.rfind("not a scan", 0) == 0;
}

// Malformed scan lines: the reasons a CARMEN scan line itself was skipped.
int64_t MalformedScans(const io::SkipCounts& skips) {
  int64_t n = 0;
  for (const auto& [reason, count] : skips.by_reason) {
    if (!IsInformational(reason)) n += count;
  }
  return n;
}

// "file: N lines skipped (reason: n, first at line L; ...)" for the reasons worth a warning;
// empty when there are none.
std::string DescribeSkips(const std::string& file, const io::SkipCounts& skips) {
  int64_t total = 0;
  for (const auto& [reason, count] : skips.by_reason) {
    if (!IsInformational(reason)) total += count;
  }
  if (total == 0) return std::string();
  std::ostringstream out;
  out << fs::path(file).filename().string() << ": " << total << " lines skipped (";
  bool first = true;
  for (const auto& [reason, count] : skips.by_reason) {
    if (IsInformational(reason)) continue;
    if (!first) out << "; ";
    first = false;
    out << reason << ": " << count;
    const auto line = skips.first_line.find(reason);
    if (line != skips.first_line.end() && line->second > 0) out << ", first at line " << line->second;
  }
  out << ")";
  return out.str();
}

// Everything the two detection passes share.
struct PassContext {
  const io::SessionSpec* session = nullptr;
  const io::ScannerPreset* preset = nullptr;
  const io::CalibrateOptions* options = nullptr;
  const std::vector<calib::WallGeometry>* walls = nullptr;
  const calib::PoseInterpolator* poses = nullptr;
  bool use_moving = false;  // moving scans are used (option, or too few dwells)
};

struct PassOutcome {
  std::vector<calib::WallObservation> observations;
  std::map<std::string, int64_t> skipped;  // per scan, why it gave no observation
  int64_t scans_read = 0;
  int64_t scans_examined = 0;
  io::SkipCounts line_skips;
  calib::RangeCounts range_counts;
  int64_t beam_count_mismatch = 0;
  int64_t not_increasing = 0;        // scans stamped at or before the scan before them
  int first_not_increasing_line = 0;
  double first_stamp_s = 0.0, last_stamp_s = 0.0;  // the scan log's time span (all scans)
  int first_mismatch_beams = 0;
};

struct Gates {
  double angle_rad;
  double offset_m;
  bool use_segment;
};

// Moves every observation to its scan's time + dt_s, with the pose interpolated anew at that
// time (the scanner clock offset the solver estimated; the wall line is the scan's and does not
// change). The solver's own p + v·dt, ψ + ω·dt is a linearisation, poor where the vehicle
// accelerates: a simulated 150 ms offset came back as 135 ± 2 ms from it alone. Observations
// whose shifted time has no pose (outside the logs, in a gap) are dropped; returns how many.
int ShiftObservations(const calib::PoseInterpolator& poses, double dt_s,
                      std::vector<calib::WallObservation>* observations) {
  std::vector<calib::WallObservation> kept;
  kept.reserve(observations->size());
  int dropped = 0;
  for (calib::WallObservation& o : *observations) {
    calib::VehiclePose pose;
    if (poses.At(o.pose.stamp_s + dt_s, &pose) != calib::PoseStatus::kOk) {
      ++dropped;
      continue;
    }
    o.pose = pose;
    kept.push_back(o);
  }
  *observations = std::move(kept);
  return dropped;
}

// Streams the scan log once. With min_interval_s > 0 only scans at least that far apart in time
// are examined (the first, wide-gate pass samples the session evenly).
PassOutcome DetectionPass(const PassContext& context, const solvers::Mount& mount,
                          const Gates& gates, double min_interval_s, const std::string& stage,
                          int64_t expected_scans, const ProgressFn& progress,
                          double gate_time_offset_s = 0.0) {
  PassOutcome outcome;
  io::CarmenReader reader(context.session->scanner_log);
  io::ScanRecord scan;
  double last_examined_s = -1e300;
  int scan_index = -1;
  const io::DetectorOptions& detector = context.options->detector;
  const bool use_moving = context.use_moving;
  while (reader.Next(&scan)) {
    ++scan_index;
    {
      // Every scan, sampled or not: the log's time span and its order.
      const double t = scan.stamp_s + context.session->scanner_time_offset_s;
      if (scan_index == 0) {
        outcome.first_stamp_s = outcome.last_stamp_s = t;
      } else {
        if (!(t > outcome.last_stamp_s) && outcome.not_increasing++ == 0) {
          outcome.first_not_increasing_line = scan.line;
        }
        outcome.first_stamp_s = std::min(outcome.first_stamp_s, t);
        outcome.last_stamp_s = std::max(outcome.last_stamp_s, t);
      }
    }
    if (progress && scan_index % 2000 == 0) progress(Progress{stage, scan_index, expected_scans});
    const double stamp_s = scan.stamp_s + context.session->scanner_time_offset_s;
    if (min_interval_s > 0.0) {
      if (stamp_s - last_examined_s < min_interval_s) continue;
      last_examined_s = stamp_s;
    }
    ++outcome.scans_examined;
    if (static_cast<int>(scan.ranges_m.size()) != context.preset->num_beams) {
      if (outcome.beam_count_mismatch++ == 0) {
        outcome.first_mismatch_beams = static_cast<int>(scan.ranges_m.size());
      }
    }
    calib::VehiclePose pose;
    const calib::PoseStatus status = context.poses->At(stamp_s, &pose);
    if (status != calib::PoseStatus::kOk) {
      ++outcome.skipped[std::string("no pose: ") + calib::PoseStatusName(status)];
      continue;
    }
    if (!pose.stationary && !use_moving) {
      ++outcome.skipped["vehicle moving"];
      continue;
    }
    const calib::ScanPoints points =
        calib::ToScanPoints(scan, *context.preset, detector.min_range_m,
                            detector.mixed_pixel_jump_m, &outcome.range_counts);
    bool any = false;
    std::string why_not = "wall not detected";
    for (size_t w = 0; w < context.walls->size(); ++w) {
      const calib::WallGeometry& wall = (*context.walls)[w];
      calib::WallObservation observation;
      observation.scan_index = scan_index;
      observation.wall_index = static_cast<int>(w);
      observation.pose = pose;
      // The gates are predicted at the scan's true time (the clock offset of the first pass
      // moves a moving vehicle's pose); the observation keeps the pose at the stamp, since
      // the solver applies the offset itself.
      calib::WallObservation gate_at = observation;
      gate_at.pose.antenna_local_m += gate_time_offset_s * pose.velocity_local_mps;
      gate_at.pose.yaw_rad += gate_time_offset_s * pose.yaw_rate_rps;
      const double rho_pred_m = solvers::PredictRho(gate_at, wall, mount);
      const double theta_pred_rad = solvers::PredictTheta(gate_at, wall, mount);
      if (rho_pred_m + gates.offset_m <= detector.min_range_m) {
        why_not = "scanner at or behind the wall";
        continue;
      }
      calib::LineGate gate;
      gate.theta_rad = theta_pred_rad;
      gate.theta_halfwidth_rad = gates.angle_rad;
      gate.rho_m = rho_pred_m;
      gate.rho_halfwidth_m = gates.offset_m;
      if (gates.use_segment) {
        // The surveyed wall's ends seen from the scanner (current mount estimate).
        const calib::VehiclePose& at = gate_at.pose;
        const double scanner_yaw = at.yaw_rad + mount.yaw_rad;
        const Eigen::Rotation2Dd vehicle_R(at.yaw_rad);
        const Eigen::Vector2d scanner_local =
            at.antenna_local_m + vehicle_R * Eigen::Vector2d(mount.x_m, mount.y_m);
        const Eigen::Rotation2Dd scanner_R_local(-scanner_yaw);
        gate.has_segment = true;
        gate.segment_a_scanner = scanner_R_local * (wall.end_a_local - scanner_local);
        gate.segment_b_scanner = scanner_R_local * (wall.end_b_local - scanner_local);
      }
      const calib::WallDetection detection =
          calib::DetectWall(points, gate, detector, context.preset->range_sigma_m);
      if (!detection.found) {
        why_not = "wall not detected";
        continue;
      }
      observation.rho_m = detection.rho_m;
      observation.theta_rad = detection.theta_rad;
      observation.sigma_rho_m = detection.sigma_rho_m;
      observation.sigma_theta_rad = detection.sigma_theta_rad;
      observation.cov_rho_theta = detection.cov_rho_theta;
      observation.num_inliers = detection.num_inliers;
      observation.range_min_m = detection.range_min_m;
      observation.range_max_m = detection.range_max_m;
      observation.residual_rms_m = detection.residual_rms_m;
      outcome.observations.push_back(observation);
      any = true;
    }
    if (!any) ++outcome.skipped[why_not];
  }
  outcome.scans_read = reader.scans_read();
  outcome.line_skips = reader.skipped();
  return outcome;
}

// Min and max of angles (rad) around their circular mean, returned in degrees in [0, 360)
// for headings or (−180, 180] for relative angles.
void AngleRange(const std::vector<double>& angles_rad, bool as_heading, double* min_deg,
                double* max_deg) {
  if (angles_rad.empty()) {
    *min_deg = *max_deg = 0.0;
    return;
  }
  double sx = 0.0, sy = 0.0;
  for (double a : angles_rad) {
    sx += std::cos(a);
    sy += std::sin(a);
  }
  const double mean = std::atan2(sy, sx);
  double lo = 0.0, hi = 0.0;
  for (double a : angles_rad) {
    const double d = calib::WrapAngle(a - mean);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  double a_min = (mean + lo) * kRadToDeg, a_max = (mean + hi) * kRadToDeg;
  if (as_heading) {
    a_min = std::fmod(a_min + 720.0, 360.0);
    a_max = std::fmod(a_max + 720.0, 360.0);
  } else {
    a_min = calib::WrapAngle(mean + lo) * kRadToDeg;
    a_max = calib::WrapAngle(mean + hi) * kRadToDeg;
  }
  *min_deg = a_min;
  *max_deg = a_max;
}

}  // namespace

std::vector<std::string> ConfigDirs() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("WALLCAL_CONFIG_DIR"); env != nullptr && *env != '\0') {
    dirs.push_back(env);
  }
  const std::string exe_dir = ExecutableDir();
  if (!exe_dir.empty()) {
    dirs.push_back((fs::path(exe_dir) / ".." / "configs").lexically_normal().string());
    dirs.push_back((fs::path(exe_dir) / "configs").string());
  }
  if (std::string(WALLCAL_SOURCE_CONFIG_DIR).size() > 0) dirs.push_back(WALLCAL_SOURCE_CONFIG_DIR);
  return dirs;
}

std::vector<std::string> PresetDirs() {
  std::vector<std::string> dirs;
  for (const std::string& dir : ConfigDirs()) dirs.push_back((fs::path(dir) / "scanners").string());
  return dirs;
}

std::string DefaultOutputPath(const io::SessionSpec& session) {
  return (fs::path(session.dir) / "offsets.yaml").string();
}

std::vector<calib::PositionSample> PositionSamples(const io::NmeaLog& gnss, int min_fix_quality,
                                                   const calib::LocalFrame& frame,
                                                   std::vector<const io::GnssFix*>* used) {
  std::vector<calib::PositionSample> positions;
  for (const io::GnssFix& fix : gnss.fixes) {
    if (!io::FixQualityAccepted(fix.quality, min_fix_quality)) continue;
    if (!positions.empty() && fix.stamp_s <= positions.back().stamp_s) continue;
    calib::PositionSample sample;
    sample.stamp_s = fix.stamp_s;
    sample.p_local_m = calib::ToLocal(frame, fix.lat_deg, fix.lon_deg);
    const bool has_gst = std::isfinite(fix.sigma_lat_m) && std::isfinite(fix.sigma_lon_m);
    sample.sigma_m = has_gst ? std::max(fix.sigma_lat_m, fix.sigma_lon_m) : 0.0;
    positions.push_back(sample);
    if (used != nullptr) used->push_back(&fix);
  }
  return positions;
}

std::vector<calib::YawSample> YawSamples(const io::NmeaLog& headings,
                                         io::HeadingReference reference,
                                         const calib::LocalFrame& frame,
                                         const std::vector<const io::GnssFix*>& used) {
  std::vector<calib::YawSample> yaws;
  for (const io::HeadingSample& heading : headings.headings) {
    if (!yaws.empty() && heading.stamp_s <= yaws.back().stamp_s) continue;
    calib::YawSample sample;
    sample.stamp_s = heading.stamp_s;
    if (reference == io::HeadingReference::kGridNorth) {
      sample.yaw_rad = calib::YawFromGridHeading(heading.heading_rad);
    } else {
      assert(!used.empty());
      // Convergence at the vehicle: take the nearest used fix in time.
      const auto it = std::lower_bound(
          used.begin(), used.end(), heading.stamp_s,
          [](const io::GnssFix* fix, double t) { return fix->stamp_s < t; });
      const io::GnssFix* nearest = it == used.end() ? used.back() : *it;
      if (it != used.begin() && it != used.end() &&
          heading.stamp_s - (*(it - 1))->stamp_s < (*it)->stamp_s - heading.stamp_s) {
        nearest = *(it - 1);
      }
      sample.yaw_rad = calib::YawFromTrueHeading(frame, heading.heading_rad, nearest->lat_deg,
                                                 nearest->lon_deg);
    }
    yaws.push_back(sample);
  }
  return yaws;
}

CalibrationResult RunCalibration(const CalibrateRequest& request, const ProgressFn& progress) {
  const auto t_start = std::chrono::steady_clock::now();
  auto say = [&](const std::string& stage) {
    if (progress) progress(Progress{stage, 0, 0});
  };
  if (request.method != "ceres" && request.method != "barawid") {
    throw io::InputError("--method: unknown method '" + request.method +
                         "'; expected ceres or barawid");
  }
  CalibrationResult result;
  result.session = io::ReadSession(request.session_path);
  const io::SessionSpec& session = result.session;
  io::CalibrateOptions options;
  if (!request.config_path.empty()) options = io::ReadCalibrateOptions(request.config_path);
  options.Validate();
  result.preset = io::LoadScannerPreset(session.scanner_model, PresetDirs());
  const io::ScannerPreset& preset = result.preset;

  // --- Survey and its tie to UTM ---------------------------------------------------------
  say("reading survey " + session.survey_points);
  const std::vector<io::SurveyPoint> survey = io::ReadSurvey(session.survey_points);
  const io::ControlPoint& first_control = session.control.front();
  result.frame =
      calib::MakeLocalFrame(first_control.lat_deg, first_control.lon_deg, session.utm_zone);
  const calib::SurveyTie tie =
      calib::TieSurvey(survey, session.survey_points, session, result.frame, options.solver);
  result.control_rms_m = tie.control_rms_m;
  result.num_control = tie.num_control;
  result.walls = calib::FitWalls(survey, session.survey_points, session, tie, options.solver);
  if (tie.num_control >= 2 &&
      tie.control_rms_m > 3.0 * std::hypot(options.solver.control_sigma_m,
                                           options.solver.total_station_sigma_m)) {
    result.warnings.push_back("control points fit the survey with RMS " +
                              Fmt("%.3f", tie.control_rms_m) +
                              " m, more than 3x the expected RTK + total-station error");
  }

  // --- GNSS and heading ---------------------------------------------------------------
  say("reading GNSS " + session.gnss_log);
  const io::NmeaLog gnss = io::ReadNmea(session.gnss_log);
  const io::NmeaLog heading_log =
      session.heading_log == session.gnss_log ? gnss : io::ReadNmea(session.heading_log);
  if (session.heading_log != session.gnss_log) say("reading heading " + session.heading_log);
  result.fixes_by_quality = gnss.fixes_by_quality;
  result.gnss_skipped = gnss.skipped;
  result.heading_skipped = heading_log.skipped;
  if (const std::string w = DescribeSkips(session.gnss_log, gnss.skipped); !w.empty()) {
    result.warnings.push_back(w);
  }
  if (session.heading_log != session.gnss_log) {
    if (const std::string w = DescribeSkips(session.heading_log, heading_log.skipped); !w.empty()) {
      result.warnings.push_back(w);
    }
  }

  std::vector<const io::GnssFix*> used_fixes;
  const std::vector<calib::PositionSample> positions =
      PositionSamples(gnss, session.min_fix_quality, result.frame, &used_fixes);
  result.fixes_used = static_cast<int64_t>(positions.size());
  if (positions.size() < 2) {
    std::ostringstream found;
    for (const auto& [quality, count] : gnss.fixes_by_quality) {
      found << " quality " << quality << ": " << count << ";";
    }
    throw io::InputError(io::Where(session.gnss_log, 0,
                                   "fewer than 2 GGA fixes of accepted quality (gnss.min_fix_quality " +
                                       std::to_string(session.min_fix_quality) + "); found" +
                                       (found.str().empty() ? std::string(" none") : found.str())));
  }
  const int64_t rejected_fixes = static_cast<int64_t>(gnss.fixes.size()) - result.fixes_used;
  if (rejected_fixes > 0) {
    result.warnings.push_back(std::to_string(rejected_fixes) +
                              " GGA fixes below gnss.min_fix_quality (or out of time order) not used");
  }

  const std::vector<calib::YawSample> yaws =
      YawSamples(heading_log, session.heading_reference, result.frame, used_fixes);
  result.headings_used = static_cast<int64_t>(yaws.size());
  if (yaws.size() < 2) {
    throw io::InputError(io::Where(session.heading_log, 0,
                                   "fewer than 2 usable HDT/THS headings; expected a heading log"));
  }
  const calib::PoseInterpolator poses(positions, yaws, options.alignment);
  if (options.solver.gnss_bias_tau_s > 0.0 &&
      options.alignment.segment_max_s > options.solver.gnss_bias_tau_s / 60.0) {
    // The solver holds the RTK error constant within a slice; over a long slice it wanders and
    // the σ is no longer honest (docs/method.md, "GNSS error").
    result.warnings.push_back(
        "alignment.segment_max_s = " + Fmt("%.2f", options.alignment.segment_max_s) +
        " s is long against the RTK error's correlation time (solver.gnss_bias_tau_s = " +
        Fmt("%.0f", options.solver.gnss_bias_tau_s) +
        " s): the error wanders within a slice and the σ may be too small; use at most " +
        Fmt("%.2f", options.solver.gnss_bias_tau_s / 240.0) + " s");
  }
  if (!(poses.start_s() < poses.end_s())) {
    throw io::InputError(session.gnss_log + " and " + session.heading_log +
                         ": the GNSS and heading logs do not overlap in time");
  }
  result.num_dwells = static_cast<int>(poses.dwells().size());

  PassContext context;
  context.session = &session;
  context.preset = &preset;
  context.options = &options;
  context.walls = &result.walls;
  context.poses = &poses;
  // Moving scans: when asked for, or when the engineer drove continuously (too few dwells to
  // calibrate from stations alone). The solver then estimates the scanner clock offset too.
  context.use_moving = options.alignment.use_moving_scans ||
                       (options.alignment.moving_scans_if_few_stations &&
                        result.num_dwells < options.solver.min_stations);
  if (context.use_moving && !options.alignment.use_moving_scans) {
    result.warnings.push_back("only " + std::to_string(result.num_dwells) +
                              " stations (dwells) found: scans taken while moving are used, with "
                              "an estimated scanner clock offset (stop-and-go is more accurate)");
  }

  // --- First pass: wide gates around the rough mount, on an even subsample -------------
  solvers::Mount guess;
  if (session.mount_guess) {
    guess.x_m = session.mount_guess->x_m;
    guess.y_m = session.mount_guess->y_m;
    guess.yaw_rad = session.mount_guess->yaw_rad;
  }
  const double span_s = poses.end_s() - poses.start_s();
  const double min_interval_s = span_s / std::max(1, options.first_pass_max_scans);
  say("first pass: wall detection on a subsample with wide gates");
  const Gates wide{options.detector.wide_angle_gate_rad, options.detector.wide_offset_gate_m,
                   false};
  PassOutcome first =
      DetectionPass(context, guess, wide, min_interval_s, "first pass", 0, progress);
  if (first.scans_read == 0) {
    std::string why = "no scan records";
    if (const std::string w = DescribeSkips(session.scanner_log, first.line_skips); !w.empty()) {
      why += "; " + w;
    }
    throw io::InputError(io::Where(session.scanner_log, 0, why +
                                   "; expected CARMEN RAWLASER1/ROBOTLASER1/FLASER lines"));
  }
  if (first.observations.empty()) {
    // A scan log that lies wholly outside the GNSS/heading time span is bad input (wrong file,
    // wrong clock), not a geometry the data cannot decide.
    bool only_outside = !first.skipped.empty();
    for (const auto& [reason, count] : first.skipped) {
      only_outside = only_outside && (reason.find("before the GNSS") != std::string::npos ||
                                      reason.find("after the GNSS") != std::string::npos);
    }
    if (only_outside) {
      char span[256];
      std::snprintf(span, sizeof(span),
                    "the scans (%.3f..%.3f s) do not overlap the GNSS and heading logs "
                    "(%.3f..%.3f s); expected logs from the same run on the same clock "
                    "(check scanner.time_offset_s)",
                    first.first_stamp_s, first.last_stamp_s, poses.start_s(), poses.end_s());
      throw io::InputError(io::Where(session.scanner_log, 0, span));
    }
    std::ostringstream why;
    why << "the wall was not detected in any of " << first.scans_examined << " sampled scans (";
    bool first_reason = true;
    for (const auto& [reason, count] : first.skipped) {
      why << (first_reason ? "" : "; ") << reason << ": " << count;
      first_reason = false;
    }
    why << "); check the walls' survey codes, the scanner model, the time overlap of the logs, "
           "or give scanner.mount_guess";
    result.first_pass.usable = false;
    result.first_pass.message = why.str();
    result.estimate = result.first_pass;
    result.scans_total = first.scans_read + MalformedScans(first.line_skips);
    return result;
  }
  solvers::MountEstimate start =
      solvers::SolveMountBarawid(first.observations, result.walls, options.solver, request.force);
  if (!start.usable) {
    result.first_pass = start;
    result.estimate = start;
    result.scans_total = first.scans_read + MalformedScans(first.line_skips);
    return result;
  }
  result.first_pass = solvers::SolveMountCeres(first.observations, result.walls, options.solver,
                                               start.mount, request.force);
  if (!result.first_pass.usable) {
    result.estimate = result.first_pass;
    result.scans_total = first.scans_read + MalformedScans(first.line_skips);
    return result;
  }
  say("first pass: " + std::to_string(first.observations.size()) + " observations, mount x " +
      Fmt("%.3f", result.first_pass.mount.x_m) + " m, y " +
      Fmt("%.3f", result.first_pass.mount.y_m) + " m, yaw " +
      Fmt("%.2f", result.first_pass.mount.yaw_rad * kRadToDeg) + " deg");

  // --- Second pass: every scan, tight gates around the first estimate ------------------
  const Eigen::Matrix3d& c1 = result.first_pass.covariance;
  const Gates tight{
      std::max(options.detector.tight_angle_gate_rad, 5.0 * std::sqrt(std::max(0.0, c1(2, 2)))),
      std::max(options.detector.tight_offset_gate_m,
               5.0 * std::sqrt(std::max(0.0, c1(0, 0) + c1(1, 1)))),
      true};
  say("second pass: wall detection in every scan with tight gates");
  PassOutcome second = DetectionPass(
      context, result.first_pass.mount, tight, 0.0, "second pass", first.scans_read, progress,
      result.first_pass.time_offset_estimated ? result.first_pass.time_offset_s : 0.0);
  result.observations = std::move(second.observations);
  result.scans_skipped = second.skipped;
  result.scan_lines_skipped = second.line_skips;
  result.scans_total = second.scans_read + MalformedScans(second.line_skips);
  if (const std::string w = DescribeSkips(session.scanner_log, second.line_skips); !w.empty()) {
    result.warnings.push_back(w);
    for (const auto& [reason, count] : second.line_skips.by_reason) {
      if (!IsInformational(reason)) result.scans_skipped["malformed line: " + reason] += count;
    }
  }
  if (second.not_increasing > 0) {
    result.warnings.push_back(fs::path(session.scanner_log).filename().string() + ": " +
                              std::to_string(second.not_increasing) +
                              " scans not later than the scan before them (first at line " +
                              std::to_string(second.first_not_increasing_line) +
                              "); each was used at its own time");
  }
  if (second.beam_count_mismatch > 0) {
    result.warnings.push_back(std::to_string(second.beam_count_mismatch) + " scans have " +
                              std::to_string(second.first_mismatch_beams) + " beams, preset " +
                              preset.name + " has " + std::to_string(preset.num_beams) +
                              ": check scanner.model");
  }

  say("solving (" + request.method + ") on " + std::to_string(result.observations.size()) +
      " observations");
  if (request.method == "barawid") {
    result.estimate = solvers::SolveMountBarawid(result.observations, result.walls,
                                                 options.solver, request.force);
  } else {
    result.estimate = solvers::SolveMountCeres(result.observations, result.walls, options.solver,
                                               result.first_pass.mount, request.force);
  }
  if (request.method != "barawid" && result.estimate.usable &&
      result.estimate.time_offset_estimated) {
    // Re-interpolate the poses at the estimated true scan times and solve again, until the
    // offset left over is below kClockOffsetToleranceS; the offset reported is the total.
    double shifted_s = 0.0;
    int dropped = 0;
    for (int round = 0; round < kClockOffsetRounds && result.estimate.usable &&
                        std::abs(result.estimate.time_offset_s) > kClockOffsetToleranceS;
         ++round) {
      shifted_s += result.estimate.time_offset_s;
      say("clock offset " + Fmt("%.4f", shifted_s) + " s: poses interpolated at the shifted "
          "scan times, solving again");
      dropped += ShiftObservations(poses, result.estimate.time_offset_s, &result.observations);
      result.estimate = solvers::SolveMountCeres(result.observations, result.walls,
                                                 options.solver, result.estimate.mount,
                                                 request.force);
    }
    result.estimate.time_offset_s += shifted_s;
    if (dropped > 0) {
      result.scans_skipped["no pose at the clock-offset-corrected time"] += dropped;
    }
  }
  const solvers::MountEstimate& final_estimate = result.estimate;
  result.forced = final_estimate.usable && final_estimate.forced;
  for (const std::string& w : final_estimate.warnings) result.warnings.push_back(w);
  if (final_estimate.time_offset_estimated) {
    result.time_offset_s = final_estimate.time_offset_s;
    result.time_offset_sigma_s = final_estimate.time_offset_sigma_s;
  }
  if (final_estimate.usable) {
    say("residual analysis");
    result.residual_analysis = AnalyseResiduals(result.observations, result.walls, final_estimate, preset);
    for (const std::string& flag : result.residual_analysis.flags) {
      result.warnings.push_back("residuals: " + flag);
    }
    if (request.method == "ceres" && options.solver.bootstrap_samples >= 0) {
      say("repeatability: split halves and " + std::to_string(options.solver.bootstrap_samples) +
          " bootstrap resamples of the stations");
      result.repeatability =
          AssessRepeatability(result.observations, result.walls, options.solver,
                              final_estimate.mount, options.solver.bootstrap_samples);
    }
  }

  std::set<int> used_scans, used_segments;
  std::vector<double> grid_headings, wall_angles;
  for (const calib::WallObservation& o : result.observations) {
    used_scans.insert(o.scan_index);
    used_segments.insert(calib::GnssSegment(o));
    grid_headings.push_back(kPi / 2.0 - o.pose.yaw_rad);
    const calib::WallGeometry& wall = result.walls[o.wall_index];
    // φ of seed 002 Eq. 8: the wall normal (towards the wall) in the vehicle frame.
    const double side = (wall.offset_m - wall.normal_local.dot(o.pose.antenna_local_m)) >= 0 ? 1 : -1;
    wall_angles.push_back(
        calib::WrapAngle(std::atan2(side * wall.normal_local.y(), side * wall.normal_local.x()) -
                         o.pose.yaw_rad));
  }
  result.scans_used = static_cast<int64_t>(used_scans.size());
  result.num_segments_used = static_cast<int>(used_segments.size());
  // Scans that had an observation in the first pass only are not "skipped"; everything not
  // used is accounted for in scans_skipped.
  AngleRange(grid_headings, true, &result.heading_min_deg, &result.heading_max_deg);
  AngleRange(wall_angles, false, &result.wall_angle_min_deg, &result.wall_angle_max_deg);
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return result;
}

io::OffsetsDocument MakeOffsetsDocument(const CalibrationResult& result) {
  io::OffsetsDocument doc;
  const solvers::MountEstimate& e = result.estimate;
  doc.x_m = e.mount.x_m;
  doc.y_m = e.mount.y_m;
  doc.yaw_rad = e.mount.yaw_rad;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) doc.covariance[3 * r + c] = e.covariance(r, c);
  }
  doc.method = e.method;
  doc.scans_total = result.scans_total;
  doc.scans_used = result.scans_used;
  doc.heading_min_deg = result.heading_min_deg;
  doc.heading_max_deg = result.heading_max_deg;
  doc.residual_rms_m = e.residual_rms_m;
  auto add = [&doc](const std::string& key, const std::string& value) {
    doc.quality_extra.emplace_back(key, value);
  };
  add("observations", std::to_string(e.observations_used));
  add("outliers", std::to_string(e.observations_rejected));
  add("stations", std::to_string(result.num_dwells));
  add("gnss_segments", std::to_string(result.num_segments_used));
  add("vehicle_to_wall_angle_deg", "{min: " + Fmt("%.2f", result.wall_angle_min_deg) +
                                       ", max: " + Fmt("%.2f", result.wall_angle_max_deg) + "}");
  std::string skipped = "{";
  bool first = true;
  for (const auto& [reason, count] : result.scans_skipped) {
    skipped += (first ? "" : ", ") + std::string("\"") + reason + "\": " + std::to_string(count);
    first = false;
  }
  add("scans_skipped", skipped + "}");
  std::string quality = "{";
  first = true;
  for (const auto& [q, count] : result.fixes_by_quality) {
    quality += (first ? "" : ", ") + std::to_string(q) + ": " + std::to_string(count);
    first = false;
  }
  add("gnss_fixes_by_quality", quality + "}");
  add("gnss_fixes_used", std::to_string(result.fixes_used));
  add("headings_used", std::to_string(result.headings_used));
  add("control_points", std::to_string(result.num_control));
  add("control_rms_m", Fmt("%.4f", result.control_rms_m));
  add("utm_zone", "\"" + std::to_string(result.frame.zone) + (result.frame.north ? "N" : "S") + "\"");
  add("meridian_convergence_deg", Fmt("%.4f", result.frame.convergence_rad * kRadToDeg));
  add("point_scale", Fmt("%.7f", result.frame.scale_k0));
  std::string walls = "[";
  for (size_t i = 0; i < result.walls.size(); ++i) {
    const calib::WallGeometry& w = result.walls[i];
    walls += (i ? ", " : "") + std::string("{id: \"") + w.id + "\", points: " +
             std::to_string(w.num_points) + ", rms_m: " + Fmt("%.4f", w.rms_m) +
             ", sigma_offset_m: " + Fmt("%.4f", w.sigma_offset_m) +
             ", sigma_angle_deg: " + Fmt("%.4f", w.sigma_angle_rad * kRadToDeg) + "}";
  }
  add("walls", walls + "]");
  if (e.independent_stations > 0.0) {
    add("independent_stations", Fmt("%.2f", e.independent_stations));
  }
  if (e.time_offset_estimated) {
    add("time_offset_s", Fmt("%.4f", result.time_offset_s));
    add("time_offset_sigma_s", Fmt("%.4f", result.time_offset_sigma_s));
  } else {
    add("time_offset_s", "null  # not estimated: every scan used was taken at a station");
  }
  if (!e.weak_direction.empty()) add("weak_direction", "\"" + e.weak_direction + "\"");
  add("forced", result.forced ? "true" : "false");
  const ResidualAnalysis& ra = result.residual_analysis;
  if (ra.done) {
    add("residual_robust_sigma_m", Fmt("%.4f", ra.robust_sigma_m));
    add("outlier_share", Fmt("%.4f", ra.outlier_share));
    std::string trends = "{";
    for (size_t i = 0; i < ra.trends.size(); ++i) {
      const ResidualTrend& t = ra.trends[i];
      trends += (i ? ", " : "") + t.against + ": {slope: " + Fmt("%.4g", t.slope) + ", unit: \"" +
                t.unit + "\", significance: " + Fmt("%.2f", t.significance) +
                ", flagged: " + (t.flagged ? "true" : "false") + "}";
    }
    add("residual_trends", trends + "}");
    std::string flags = "[";
    for (size_t i = 0; i < ra.flags.size(); ++i) {
      flags += (i ? ", " : "") + std::string("\"") + ra.flags[i] + "\"";
    }
    add("residual_flags", flags + "]");
    if (ra.range_model_estimated) {
      add("range_scale_k_from_residuals",
          "{k: " + Fmt("%.5f", ra.range_scale_k) + ", sigma: " + Fmt("%.5f", ra.sigma_range_scale_k) +
              ", preset_k: " + Fmt("%.5f", result.preset.range_scale_k) + "}");
    }
  }
  const Repeatability& rep = result.repeatability;
  if (rep.done) {
    std::string text = "{bootstrap_samples: " + std::to_string(rep.bootstrap_samples) +
                       ", bootstrap_sigma: {x: " + Fmt("%.4f", rep.bootstrap_sigma_x_m) +
                       ", y: " + Fmt("%.4f", rep.bootstrap_sigma_y_m) +
                       ", yaw_deg: " + Fmt("%.4f", rep.bootstrap_sigma_yaw_rad * kRadToDeg) +
                       "}, split_max_shift: {x: " + Fmt("%.4f", rep.max_split_shift_x_m) +
                       ", y: " + Fmt("%.4f", rep.max_split_shift_y_m) +
                       ", yaw_deg: " + Fmt("%.4f", rep.max_split_shift_yaw_rad * kRadToDeg) +
                       "}, splits: [";
    for (size_t i = 0; i < rep.splits.size(); ++i) {
      const RepeatabilitySplit& sp = rep.splits[i];
      text += (i ? ", " : "") + std::string("{name: \"") + sp.name +
              "\", usable: " + (sp.usable ? "true" : "false") + ", x: " +
              Fmt("%.4f", sp.mount.x_m) + ", y: " + Fmt("%.4f", sp.mount.y_m) +
              ", yaw_deg: " + Fmt("%.4f", sp.mount.yaw_rad * kRadToDeg) + "}";
    }
    add("repeatability", text + "]}");
  }
  if (e.heading_drift_estimated) {
    // deg/h at the file edge; the rate is estimated with the prior solver.heading_drift_sigma.
    add("heading_drift_deg_per_h", Fmt("%.4f", e.heading_drift_rad_per_s * kRadToDeg * 3600.0));
    add("heading_drift_sigma_deg_per_h",
        Fmt("%.4f", e.heading_drift_sigma_rad_per_s * kRadToDeg * 3600.0));
  }
  add("yaw_reference",
      "\"relative to the heading sensor's zero at the first scan used (t = " +
          Fmt("%.3f", e.heading_reference_s) +
          " s): a constant heading bias is indistinguishable from mount yaw; the heading drift "
          "after that time is estimated (heading_drift_deg_per_h)\"");
  doc.warnings = result.warnings;
  doc.session = result.session.file;
  doc.tool_version = io::kToolVersion;
  return doc;
}

std::string FormatSummary(const CalibrationResult& result) {
  const solvers::MountEstimate& e = result.estimate;
  std::ostringstream out;
  char line[512];
  out << "wallcal " << io::kToolVersion << ": session '" << result.session.name << "' ("
      << result.preset.name << ")\n";
  std::snprintf(line, sizeof(line), "  scans      %lld read, %lld used",
                static_cast<long long>(result.scans_total), static_cast<long long>(result.scans_used));
  out << line;
  for (const auto& [reason, count] : result.scans_skipped) {
    out << "; " << count << " " << reason;
  }
  out << "\n";
  out << "  gnss       " << result.fixes_used << " fixes used (by quality:";
  for (const auto& [q, count] : result.fixes_by_quality) out << " " << q << ":" << count;
  out << "), " << result.headings_used << " headings\n";
  std::snprintf(line, sizeof(line),
                "  survey     %d control points (RMS %.4f m), %zu wall(s), UTM zone %d%s, "
                "convergence %.3f deg, scale %.6f\n",
                result.num_control, result.control_rms_m, result.walls.size(), result.frame.zone,
                result.frame.north ? "N" : "S", result.frame.convergence_rad * kRadToDeg,
                result.frame.scale_k0);
  out << line;
  std::snprintf(line, sizeof(line),
                "  geometry   %d stations, %d GNSS-error slices, grid headings %.1f..%.1f deg, "
                "vehicle-to-wall angles %.1f..%.1f deg\n",
                result.num_dwells, result.num_segments_used, result.heading_min_deg,
                result.heading_max_deg, result.wall_angle_min_deg, result.wall_angle_max_deg);
  out << line;
  if (e.usable) {
    const double sx = std::sqrt(std::max(0.0, e.covariance(0, 0)));
    const double sy = std::sqrt(std::max(0.0, e.covariance(1, 1)));
    const double syaw = std::sqrt(std::max(0.0, e.covariance(2, 2)));
    std::snprintf(line, sizeof(line),
                  "  mount      x = %.4f ± %.4f m   y = %.4f ± %.4f m   yaw = %.3f ± %.3f deg  "
                  "(%s)\n",
                  e.mount.x_m, sx, e.mount.y_m, sy, e.mount.yaw_rad * kRadToDeg, syaw * kRadToDeg,
                  e.method.c_str());
    out << line;
    std::snprintf(line, sizeof(line),
                  "  seed 002   a = %.4f m   b = %.4f m   delta = %.3f deg\n", -e.mount.y_m,
                  e.mount.x_m, e.mount.yaw_rad * kRadToDeg);
    out << line;
    std::snprintf(line, sizeof(line),
                  "  residuals  RMS %.4f m over %d observations, %d outliers (> 3 sigma)\n",
                  e.residual_rms_m, e.observations_used, e.observations_rejected);
    out << line;
    out << "  yaw        relative to the heading sensor's zero at the first scan used (a "
           "constant heading bias is indistinguishable from mount yaw)\n";
    if (e.independent_stations > 0.0) {
      std::snprintf(line, sizeof(line),
                    "  gnss error %.1f independent realisations over the stations (RTK error "
                    "correlated in time)\n",
                    e.independent_stations);
      out << line;
    }
    if (e.time_offset_estimated) {
      std::snprintf(line, sizeof(line),
                    "  clock      scanner time offset %+.4f ± %.4f s (true scan time = stamp + "
                    "offset)\n",
                    result.time_offset_s, result.time_offset_sigma_s);
      out << line;
    }
    const ResidualAnalysis& ra = result.residual_analysis;
    if (ra.done) {
      std::snprintf(line, sizeof(line),
                    "  analysis   robust sigma %.4f m, %.1f %% beyond 2 sigma, %zu flagged "
                    "trend(s)\n",
                    ra.robust_sigma_m, 100.0 * ra.outlier_share, ra.flags.size());
      out << line;
    }
    const Repeatability& rep = result.repeatability;
    if (rep.done) {
      std::snprintf(line, sizeof(line),
                    "  repeat     bootstrap (%d) sigma x %.4f m, y %.4f m, yaw %.3f deg; "
                    "split halves/odd-even move it at most x %.4f m, y %.4f m, yaw %.3f deg\n",
                    rep.bootstrap_samples, rep.bootstrap_sigma_x_m, rep.bootstrap_sigma_y_m,
                    rep.bootstrap_sigma_yaw_rad * kRadToDeg, rep.max_split_shift_x_m,
                    rep.max_split_shift_y_m, rep.max_split_shift_yaw_rad * kRadToDeg);
      out << line;
    }
    if (result.forced) out << "  FORCED     written although the data do not determine the mount\n";
  } else {
    out << "  mount      NOT DETERMINED: " << e.message << "\n";
  }
  for (const std::string& w : result.warnings) out << "  warning    " << w << "\n";
  std::snprintf(line, sizeof(line), "  time       %.2f s\n", result.seconds);
  out << line;
  return out.str();
}

SimulateSummary WriteSimulatedSession(const io::SimulationConfig& input_config, uint64_t seed,
                                      const std::string& dir) {
  const io::SimulationConfig config = calib::WithDefaultWalls(input_config);
  config.Validate();
  const io::ScannerPreset preset = io::LoadScannerPreset(config.scanner_model, PresetDirs());
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir)) {
    throw io::InputError(dir + ": cannot create the output folder (" + error.message() + ")");
  }
  const fs::path folder(dir);
  const std::string scans_path = (folder / "scans.clf").string();
  const std::string scans_tmp = scans_path + ".tmp-" + std::to_string(::getpid());
  std::ofstream scans(scans_tmp, std::ios::binary | std::ios::trunc);
  if (!scans) throw io::InputError(scans_tmp + ": cannot write");
  scans << "# wallcal simulate: scanner " << preset.name << ", seed " << seed << "\n";
  calib::SimulatedSession sim;
  try {
    sim = calib::Simulate(config, preset, seed, [&scans](const io::ScanRecord& scan) {
      scans << io::FormatCarmenRawlaser(scan) << '\n';
    });
    scans.flush();
    if (!scans) throw io::InputError(scans_tmp + ": write failed (disk full?)");
    scans.close();
  } catch (...) {
    scans.close();
    fs::remove(scans_tmp, error);
    throw;
  }

  std::string gnss_text;
  for (const io::GnssFix& fix : sim.fixes) {
    gnss_text += io::FormatGgaLine(fix) + "\n";
    if (config.write_gst) gnss_text += io::FormatGstLine(fix) + "\n";
  }
  std::string heading_text;
  for (const io::HeadingSample& h : sim.headings) {
    heading_text += io::FormatHdtLine(h.stamp_s, h.heading_rad) + "\n";
  }
  io::SessionSpec spec;
  spec.dir = folder.string();
  spec.file = (folder / "session.yaml").string();
  spec.name = config.name;
  spec.scanner_model = preset.name;
  spec.scanner_log = scans_path;
  spec.gnss_log = (folder / "gnss.nmea").string();
  spec.heading_log = (folder / "heading.nmea").string();
  spec.survey_points = (folder / "survey.csv").string();
  spec.control = sim.control;
  spec.walls = sim.walls;
  try {
    io::WriteFileAtomically(spec.gnss_log, gnss_text);
    io::WriteFileAtomically(spec.heading_log, heading_text);
    io::WriteFileAtomically(spec.survey_points, io::FormatSurveyCsv(sim.survey));
    io::WriteFileAtomically((folder / "truth.yaml").string(), io::FormatTruthYaml(config, seed));
    fs::rename(scans_tmp, scans_path);
    // session.yaml last: a folder with a session.yaml is a complete session.
    io::WriteFileAtomically(spec.file, io::FormatSessionYaml(spec));
  } catch (...) {
    fs::remove(scans_tmp, error);
    throw;
  }
  SimulateSummary summary;
  summary.scans_written = sim.scans_written;
  summary.scans_lost = sim.scans_lost;
  summary.fixes = static_cast<int64_t>(sim.fixes.size());
  summary.headings = static_cast<int64_t>(sim.headings.size());
  summary.survey_points = static_cast<int64_t>(sim.survey.size());
  if (!sim.truth_poses.empty()) {
    summary.duration_s = sim.truth_poses.back().stamp_s - sim.truth_poses.front().stamp_s;
  }
  return summary;
}

}  // namespace wallcal::app
