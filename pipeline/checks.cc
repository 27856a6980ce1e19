// SPDX-License-Identifier: Apache-2.0
// The mistake checks of pipeline/checks.h. The thresholds are generous on purpose: each check
// is for a gross mistake (a wrong preset, a mirrored or misplaced survey, a wrong sign on the
// tape), never for the noise of a good session.

#include "pipeline/checks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "calib/geodesy.h"
#include "common/angles.h"
#include "common/format.h"
#include "io/scanner_geometry.h"

namespace wallcal::pipeline {
namespace {

// The rigid (det +1) or reflecting (det −1) 2-D fit of `from` onto `to`; the RMS of the
// residual distances (m).
double ProcrustesRms(const std::vector<Eigen::Vector2d>& from, const std::vector<Eigen::Vector2d>& to,
                     bool reflect) {
  const size_t n = from.size();
  Eigen::Vector2d from_mean = Eigen::Vector2d::Zero(), to_mean = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < n; ++i) {
    from_mean += from[i];
    to_mean += to[i];
  }
  from_mean /= static_cast<double>(n);
  to_mean /= static_cast<double>(n);
  // Reflect the source about its x axis first; then the best rotation (closed form in 2-D).
  double sxx = 0.0, sxy = 0.0;  // Σ a·b and Σ a×b
  std::vector<Eigen::Vector2d> a(n);
  for (size_t i = 0; i < n; ++i) {
    a[i] = from[i] - from_mean;
    if (reflect) a[i].y() = -a[i].y();
    const Eigen::Vector2d b = to[i] - to_mean;
    sxx += a[i].dot(b);
    sxy += a[i].x() * b.y() - a[i].y() * b.x();
  }
  const double angle = std::atan2(sxy, sxx);
  const double c = std::cos(angle), s = std::sin(angle);
  double sum_sq = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d turned(c * a[i].x() - s * a[i].y(), s * a[i].x() + c * a[i].y());
    sum_sq += (turned - (to[i] - to_mean)).squaredNorm();
  }
  return std::sqrt(sum_sq / static_cast<double>(n));
}

double PointToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length_sq = ab.squaredNorm();
  const double t = length_sq > 0.0 ? std::clamp((p - a).dot(ab) / length_sq, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

}  // namespace

PresetFit CheckPresetAgainstScans(const std::function<std::unique_ptr<io::ScanSource>()>& open_scans,
                                  const io::ScannerPreset& preset, int64_t max_scans) {
  PresetFit fit;
  std::unique_ptr<io::ScanSource> source = open_scans();
  std::map<int, int64_t> by_beams;
  std::map<int, double> step_by_beams;
  std::map<int, double> range_max_by_beams;
  io::ScanRecord scan;
  // A reading counts as beyond the preset when it is clearly longer than the preset's maximum
  // (1 % + 5 cm) and is not the log's own no-return value (a reading at the log's maximum). A
  // scan whose own range limit lies within the family's (io/scanner_geometry.h) allows
  // readings up to that limit.
  const double beyond_m = preset.max_range_m * 1.01 + 0.05;
  while (fit.scans_checked < max_scans && source->Next(&scan)) {
    ++fit.scans_checked;
    const int beams = static_cast<int>(scan.ranges_m.size());
    ++by_beams[beams];
    step_by_beams.emplace(beams, scan.angular_step_rad);
    range_max_by_beams.emplace(beams, scan.max_range_m);
    const double no_return_m = scan.max_range_m > 0.0 ? scan.max_range_m - 0.005
                                                       : std::numeric_limits<double>::infinity();
    const bool driver_limit = scan.max_range_m > preset.max_range_m &&
                              scan.max_range_m <= io::kDriverRangeFactor * preset.max_range_m;
    const double allowed_m = driver_limit ? scan.max_range_m * 1.01 + 0.05 : beyond_m;
    for (float r : scan.ranges_m) {
      const double range_m = r;
      if (!(range_m > preset.error_codes_below_m) || !(range_m < no_return_m)) continue;
      ++fit.readings;
      fit.longest_range_m = std::max(fit.longest_range_m, range_m);
      if (range_m > allowed_m) ++fit.beyond_preset_max;
    }
  }
  if (fit.scans_checked == 0) return fit;  // the detection pass reports an empty log
  const auto most = std::max_element(by_beams.begin(), by_beams.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
  fit.beams_in_log = most->first;
  fit.step_in_log_rad = step_by_beams[most->first];
  // The scans' geometry against the scanner family's limits: within them it is taken from the
  // data (each scan's bearings come from its own start and step), outside them it is another
  // scanner.
  const io::GeometryCheck geometry = io::CheckScanGeometry(
      fit.beams_in_log, fit.step_in_log_rad, range_max_by_beams[most->first], preset);
  if (geometry.fit == io::GeometryFit::kOtherScanner) {
    fit.problems.push_back("the scans have " + geometry.what);
  } else if (geometry.fit == io::GeometryFit::kFromData) {
    fit.taken_from_data = geometry.what;
  }
  // More than 1 % of the readings beyond the preset's maximum: not a stray reflection.
  if (fit.readings > 0 && fit.beyond_preset_max * 100 > fit.readings) {
    fit.problems.push_back(Format("%lld of %lld readings are longer than the preset's maximum "
                                  "range %.2f m (longest %.2f m)",
                                  static_cast<long long>(fit.beyond_preset_max),
                                  static_cast<long long>(fit.readings), preset.max_range_m,
                                  fit.longest_range_m));
  }
  return fit;
}

void EnforcePresetFit(const PresetFit& fit, const io::ScannerPreset& preset,
                      const io::SessionSpec& session, bool force,
                      Warnings* warnings) {
  if (fit.problems.empty()) return;
  std::string what;
  for (const std::string& p : fit.problems) what += (what.empty() ? "" : "; ") + p;
  const std::string message = "scanner.model '" + preset.name + "' does not fit " +
                              session.scanner_log + " (first " +
                              std::to_string(fit.scans_checked) + " scans): " + what;
  if (!force) {
    throw io::InputError(io::Where(
        session.file, 0,
        message + "; expected the preset of the scanner that recorded the log (configs/scanners/), "
                  "or --force to use it anyway"));
  }
  warnings->push_back({WarningKind::kForcedPresetMismatch, "FORCED: " + message});
}

void CheckSurveyNotMirrored(const std::vector<io::SurveyPoint>& survey,
                            const io::SessionSpec& session, const calib::LocalFrame& frame) {
  if (session.control.size() < 3) return;
  std::vector<Eigen::Vector2d> from, to;
  for (const io::ControlPoint& control : session.control) {
    const auto point = std::find_if(survey.begin(), survey.end(),
                                    [&control](const io::SurveyPoint& p) { return p.id == control.id; });
    if (point == survey.end()) return;  // the tie names the missing point
    from.emplace_back(point->x_m, point->y_m);
    to.push_back(calib::ToLocal(frame, control.lat_deg, control.lon_deg));
  }
  const double rotation_rms_m = ProcrustesRms(from, to, false);
  const double reflection_rms_m = ProcrustesRms(from, to, true);
  // A good survey: the rotation fits to centimetres. A mirrored one: the reflection does, and
  // the rotation is off by the size of the control layout.
  if (rotation_rms_m > 0.1 && reflection_rms_m < 0.25 * rotation_rms_m) {
    throw io::InputError(io::Where(
        session.file, session.control.front().line,
        Format("mirrored survey: the survey is mirrored against the control points' RTK "
               "positions: a reflected fit matches them with RMS %.3f m, a rotation only with "
               "%.3f m; check whether the survey's x and y (easting and northing) columns are "
               "swapped (survey.columns, or the header) in ",
               reflection_rms_m, rotation_rms_m) +
            session.survey_points));
  }
}

double TrackToWallsDistance(const std::vector<Eigen::Vector2d>& track_local_m,
                            const std::vector<calib::WallGeometry>& walls) {
  double best_m = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& p : track_local_m) {
    for (const calib::WallGeometry& wall : walls) {
      best_m = std::min(best_m, PointToSegment(p, wall.end_a_local, wall.end_b_local));
    }
  }
  return best_m;
}

void CheckTrackNearWalls(const std::vector<Eigen::Vector2d>& track_local_m,
                         const std::vector<calib::WallGeometry>& walls,
                         const io::ScannerPreset& preset, const io::SessionSpec& session) {
  if (track_local_m.empty() || walls.empty()) return;
  const double distance_m = TrackToWallsDistance(track_local_m, walls);
  const double reach_m = preset.max_range_m + 20.0;
  if (distance_m <= reach_m) return;
  if (session.control.empty()) {  // a rover survey: its points are in the GNSS frame
    throw io::InputError(io::Where(
        session.survey_points, 0,
        Format("the GNSS track passes no closer than %.0f m to the walls of the rover survey "
               "(the scanner reaches %.0f m): the rover points are not where the vehicle drove; "
               "check their latitude and longitude (swapped? a digit wrong?), and that the GNSS "
               "log is from this site",
               distance_m, preset.max_range_m)));
  }
  std::string control_ids;
  for (const io::ControlPoint& c : session.control) {
    control_ids += (control_ids.empty() ? "" : ", ") + c.id;
  }
  throw io::InputError(io::Where(
      session.file, session.control.empty() ? 0 : session.control.front().line,
      Format("the GNSS track passes no closer than %.0f m to the surveyed walls (the scanner "
             "reaches %.0f m): the survey, tied by its control points (",
             distance_m, preset.max_range_m) +
          control_ids +
          "), is not where the vehicle drove; check the control points' lat/lon (a digit "
          "wrong?) against their survey ids, and that the GNSS log is from this site"));
}

std::string CheckMountGuess(const io::MountGuess& guess, const calib::Mount& estimate) {
  std::string out;
  const double dx_m = estimate.x_m - guess.x_m;
  const double dy_m = estimate.y_m - guess.y_m;
  const double dyaw_rad = WrapAngle(estimate.yaw_rad - guess.yaw_rad);
  if (guess.tolerance_m && (std::abs(dx_m) > *guess.tolerance_m || std::abs(dy_m) > *guess.tolerance_m)) {
    out = Format("the estimate x %.3f m, y %.3f m is %.3f m, %.3f m from scanner.mount_guess "
                 "(x %.3f m, y %.3f m), beyond its tolerance_m %.3f m",
                 estimate.x_m, estimate.y_m, dx_m, dy_m, guess.x_m, guess.y_m, *guess.tolerance_m);
  }
  if (guess.tolerance_yaw_rad && std::abs(dyaw_rad) > *guess.tolerance_yaw_rad) {
    out += (out.empty() ? "" : "; ") +
           Format("the estimated yaw %.2f° is %.2f° from scanner.mount_guess yaw_deg %.2f°, "
                  "beyond its tolerance_yaw_deg %.2f°",
                  estimate.yaw_rad * kRadToDeg, dyaw_rad * kRadToDeg, guess.yaw_rad * kRadToDeg,
                  *guess.tolerance_yaw_rad * kRadToDeg);
  }
  if (!out.empty()) {
    out += ": a gross error in the tape measure or in the data (a wrong wall, survey or "
           "preset); re-measure the mount, or --force to write the estimate anyway";
  }
  return out;
}

}  // namespace wallcal::pipeline
