// SPDX-License-Identifier: Apache-2.0
#include "outputs/summary.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/angles.h"
#include "common/format.h"
#include "io/version.h"

namespace wallcal::outputs {

using pipeline::CalibrationResult;

std::string ChangeText(const pipeline::Change& c) {
  // A change below the printed digit is shown as +0.0, not −0.0 (the previous file's rounding
  // alone makes the same data differ by a few µm).
  const auto shown = [](double value, double digit) {
    return std::abs(value) < 0.5 * digit ? 0.0 : value;
  };
  char line[512];
  std::snprintf(line, sizeof(line),
                "since %s: x %+.1f mm, y %+.1f mm, yaw %+.3f deg (%.1f, %.1f, %.1f combined sigma)",
                c.previous_file.c_str(), shown(c.dx_m * 1e3, 0.1), shown(c.dy_m * 1e3, 0.1),
                shown(c.dyaw_rad * kRadToDeg, 0.001), c.x_sigmas, c.y_sigmas, c.yaw_sigmas);
  if (c.previous_inverted) {
    return std::string(line) + "; the previous file holds it the other way round, inverted";
  }
  return line;
}

// The site's lines: where the attitude came from, the yard, the scanner's height and tilt, the
// walls' leans, and the site's terms of the σ. Nothing on a level site (nothing corrected, no
// lean fitted beyond upright).
std::string SiteText(const CalibrationResult& result) {
  const pipeline::SiteResult& site = result.site;
  std::string out;
  if (site.corrected || result.solve.unknown_height_bias) {
    out += "  site       attitude: " +
           std::string(calib::AttitudeSourceName(site.attitude.source()));
    if (site.attitude_samples > 0) {
      out += Format(" (%lld samples, %.1f Hz, roll %+.2f..%+.2f°, pitch %+.2f..%+.2f°)",
                    static_cast<long long>(site.attitude_samples), site.attitude_rate_hz,
                    site.roll_min_rad * kRadToDeg, site.roll_max_rad * kRadToDeg,
                    site.pitch_min_rad * kRadToDeg, site.pitch_max_rad * kRadToDeg);
    }
    if (site.yard.fitted) {
      out += Format("; yard %.2f ± %.2f %% rising towards %.0f° (GNSS heights, %.3f m RMS about "
                    "the plane)",
                    site.yard.GradePercent(),
                    100.0 * site.yard.GradeSigma(),
                    site.yard.RiseDirectionDeg(1.0), site.yard.residual_rms_m);
    }
    out += site.z_given ? Format("; scanner z %+.3f ± %.3f m", site.placement.z_m, site.z_sigma_m)
                        : std::string("; scanner z not given (scanner.z_m)");
    if (site.tilt_given) {
      out += Format(", pitch %+.2f°, roll %+.2f° (± %.2f°)", site.placement.pitch_rad * kRadToDeg,
                    site.placement.roll_rad * kRadToDeg, site.tilt_sigma_rad * kRadToDeg);
    }
    out += "\n";
  }
  for (const calib::WallGeometry& w : result.survey.walls) {
    if (w.lean_rad == 0.0) continue;
    out += Format("  wall lean  %s leans %.2f ± %.2f° from vertical%s\n",
                  w.id.c_str(), std::abs(w.lean_rad) * kRadToDeg, w.sigma_lean_rad * kRadToDeg,
                  std::isfinite(w.reference_height_m)
                      ? ""
                      : ": not used, the survey's heights are not tied to the GNSS's (control "
                        "points with heights)");
  }
  if (!result.solve.site_terms.empty()) {
    out += "  site σ    ";
    bool first = true;
    for (const pipeline::SolveResult::SiteTerm& t : result.solve.site_terms) {
      out += Format("%s %s x %.1f mm, y %.1f mm, yaw %.3f°", first ? "" : ";",
                    pipeline::SiteTermName(t.kind), 1e3 * std::sqrt(t.covariance(0, 0)),
                    1e3 * std::sqrt(t.covariance(1, 1)), std::sqrt(t.covariance(2, 2)) * kRadToDeg);
      first = false;
    }
    out += " (in the mount's σ)\n";
  }
  return out;
}

namespace {

// The noise line: the GNSS and heading white noise the solve took and where each came from
// (pipeline::WhiteNoiseInUse), with the degrees of freedom behind a measured one. Nothing when
// neither the stops nor the drives measured a figure (both are then the configured ones).
std::string NoiseText(const CalibrationResult& result) {
  const pipeline::PoseResult& poses = result.poses;
  const calib::MeasuredWhiteNoise& stops = poses.measured_noise;
  const calib::DriveWhiteNoise& drives = poses.drive_noise;
  if (stops.gnss_white_sigma_m <= 0.0 && stops.heading_sigma_rad <= 0.0 &&
      drives.gnss_white_sigma_m <= 0.0 && drives.heading_sigma_rad <= 0.0) {
    return "";
  }
  const solvers::SolverOptions& configured = result.loaded.options.solver;
  // "measured on the drives (1540 dof; 4 of 224 windows beyond 3× the median's scatter left
  // out)"
  const auto source = [&](pipeline::NoiseSource from, int stops_dof, int drives_dof, int used,
                          int dropped, const std::string& stops_text,
                          const std::string& drives_text) {
    std::string text = pipeline::NoiseSourceName(from);
    switch (from) {
      case pipeline::NoiseSource::kMeasuredAtStops:
        return text + Format(" (%d dof)", stops_dof);
      case pipeline::NoiseSource::kMeasuredOnDrives:
        return text + Format(" (%d dof; %d of %d windows beyond %g× the median's scatter "
                             "left out)",
                             drives_dof, dropped, used + dropped, calib::kDriveWindowRejectRatio);
      case pipeline::NoiseSource::kConfigured:
        if (!configured.use_measured_white_noise) {
          return text + " (use_measured_white_noise: false; at the stops " + stops_text +
                 ", on the drives " + drives_text + ")";
        }
        return text + " (too few samples at the stops and on the drives)";
    }
    return text;
  };
  const auto metres = [](double sigma_m) {
    return sigma_m > 0.0 ? Format("%.4f m", sigma_m) : std::string("none");
  };
  const auto degrees = [](double sigma_rad) {
    return sigma_rad > 0.0 ? Format("%.4f deg", sigma_rad * kRadToDeg) : std::string("none");
  };
  const pipeline::WhiteNoiseInUse& in_use = poses.white_noise;
  std::string out = "  noise      white noise GNSS " + metres(in_use.gnss_white_sigma_m) + " " +
                    source(in_use.gnss_source, stops.gnss_degrees_of_freedom,
                           drives.gnss_degrees_of_freedom, drives.gnss_windows_used,
                           drives.gnss_windows_dropped, metres(stops.gnss_white_sigma_m),
                           metres(drives.gnss_white_sigma_m)) +
                    ", heading " + degrees(in_use.heading_sigma_rad) + " " +
                    source(in_use.heading_source, stops.heading_degrees_of_freedom,
                           drives.heading_degrees_of_freedom, drives.heading_windows_used,
                           drives.heading_windows_dropped, degrees(stops.heading_sigma_rad),
                           degrees(drives.heading_sigma_rad));
  if (configured.use_measured_white_noise) {
    out += Format("; configured (the fallbacks): solver.gnss_white_sigma_m %.4f m, "
                  "heading_sigma_deg %.4f deg",
                  configured.gnss_white_sigma_m, configured.heading_sigma_rad * kRadToDeg);
  }
  return out + "\n";
}

}  // namespace

std::string FormatSummary(const CalibrationResult& result) {
  const solvers::MountEstimate& e = result.solve.estimate;
  std::ostringstream out;
  char line[512];
  out << "wallcal " << io::kToolVersion << ": session '" << result.loaded.session.name << "' ("
      << result.loaded.preset.name << ")\n";
  out << "  verdict    " << pipeline::VerdictName(result.decided.decision.verdict) << "\n";
  for (const std::string& reason : result.decided.decision.reasons)
    out << "             - " << reason << "\n";
  if (!result.detection.scanner_from_data.empty()) {
    out << "  scanner    " << result.loaded.preset.name
        << "'s range model; from the data: " << result.detection.scanner_from_data << "\n";
  }
  std::snprintf(line, sizeof(line),
                "  scans      %lld read, %lld used (%lld standing, %lld moving)",
                static_cast<long long>(result.detection.scans_total),
                static_cast<long long>(result.finish.coverage.scans_used),
                static_cast<long long>(result.finish.coverage.scans_used -
                                       result.finish.coverage.scans_used_moving),
                static_cast<long long>(result.finish.coverage.scans_used_moving));
  out << line;
  for (const auto& [reason, count] : result.ScansSkipped()) {
    out << "; " << count << " " << calib::ScanSkipName(reason);
  }
  out << "\n";
  out << "  gnss       " << result.poses.fixes_used << " fixes used (by quality:";
  for (const auto& [q, count] : result.poses.fixes_by_quality) out << " " << q << ":" << count;
  out << "), " << result.poses.headings_used << " headings\n";
  if (const calib::GnssEpochMapping& g = result.poses.gnss_epochs;
      g.status != calib::EpochMappingStatus::kNoLoggerStamp) {
    std::snprintf(line, sizeof(line),
                  "  gnss time  epoch %s: logger stamp − UTC %.4f s (latency + logger clock "
                  "offset), jitter %.4f s, drift %.1f ppm over %lld fixes\n",
                  calib::EpochMappingStatusName(g.status), g.offset_s, g.jitter_s, 1e6 * g.drift,
                  static_cast<long long>(g.fixes));
    out << line;
  }
  out << NoiseText(result);
  const bool rover = !result.survey.walls.empty() && result.survey.walls.front().from_rover;
  char tie[96];
  if (rover) {
    std::snprintf(tie, sizeof(tie), "rover points (no tie)");
  } else {
    std::snprintf(tie, sizeof(tie), "%d control points (RMS %.4f m)", result.survey.tie.num_control,
                  result.survey.tie.control_rms_m);
  }
  std::snprintf(line, sizeof(line),
                "  survey     %s, %zu wall(s), UTM zone %d%s, convergence %.3f deg, scale %.6f\n",
                tie, result.survey.walls.size(), result.survey.frame.zone,
                result.survey.frame.north ? "N" : "S",
                result.survey.frame.convergence_rad * kRadToDeg, result.survey.frame.scale_k0);
  out << line;
  std::snprintf(line, sizeof(line),
                "  geometry   %d stations, %d GNSS-error slices, grid headings %.1f..%.1f deg, "
                "vehicle-to-wall angles %.1f..%.1f deg\n",
                result.poses.num_dwells, result.finish.coverage.num_segments_used,
                result.finish.coverage.heading_min_deg, result.finish.coverage.heading_max_deg,
                result.finish.coverage.wall_angle_min_deg,
                result.finish.coverage.wall_angle_max_deg);
  out << line;
  if (e.usable && !result.solve.sigma_known) {
    std::snprintf(line, sizeof(line),
                  "  mount      x = %.4f m   y = %.4f m   yaw = %.3f deg  (%s; no sigma: see the "
                  "warning)\n",
                  e.mount.x_m, e.mount.y_m, e.mount.yaw_rad * kRadToDeg, MethodText(e));
    out << line;
  }
  if (e.usable && result.solve.sigma_known) {
    const double sx = std::sqrt(std::max(0.0, e.covariance(0, 0)));
    const double sy = std::sqrt(std::max(0.0, e.covariance(1, 1)));
    const double syaw = std::sqrt(std::max(0.0, e.covariance(2, 2)));
    std::snprintf(line, sizeof(line),
                  "  mount      x = %.4f ± %.4f m   y = %.4f ± %.4f m   yaw = %.3f ± %.3f deg  "
                  "(%s)\n",
                  e.mount.x_m, sx, e.mount.y_m, sy, e.mount.yaw_rad * kRadToDeg, syaw * kRadToDeg,
                  MethodText(e));
    out << line;
  }
  if (e.usable) {
    std::snprintf(line, sizeof(line),
                  "  Barawid    a = %.4f m   b = %.4f m   delta = %.3f deg  (Barawid et al. 2007's "
                  "notation)\n",
                  -e.mount.y_m, e.mount.x_m, e.mount.yaw_rad * kRadToDeg);
    out << line;
    const analysis::ErrorBudget& b = result.finish.budget;
    if (b.done) {
      static const char* const kAxes[3] = {"x", "y", "yaw"};
      out << "  σ budget  ";
      for (int axis = 0; axis < 3; ++axis) {
        out << (axis ? ";" : "") << " " << kAxes[axis] << ": "
            << analysis::ErrorSourceName(b.dominant[axis]) << " "
            << static_cast<int>(std::lround(100.0 * b.dominant_share[axis])) << " %";
      }
      out << " (largest share of each variance)\n";
    }
    out << SiteText(result);
    if (result.decided.change) {
      out << "  change     " << ChangeText(*result.decided.change) << "\n";
    }
    std::snprintf(line, sizeof(line),
                  "  residuals  RMS %.4f m over %d of %zu wall observations (%d down-weighted as "
                  "outliers, > 3 sigma)\n",
                  e.residual_rms_m, e.observations_used, result.solve.observations.size(),
                  e.observations_rejected);
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
                    "offset; prior σ %.4f s): %s\n",
                    result.solve.scanner_offset.value_s, result.solve.scanner_offset.sigma_s,
                    result.solve.scanner_offset.prior_sigma_s,
                    pipeline::DelayStatusName(result.solve.scanner_offset.status));
      out << line;
      if (result.solve.drives_timing_sigma_s > 0.0) {
        std::snprintf(line, sizeof(line),
                      "  clock      the moving scans' timing known to ± %.4f s (what their poses "
                      "need: the offset when driving towards a wall, offset + heading delay "
                      "when turning)\n",
                      result.solve.drives_timing_sigma_s);
        out << line;
      }
    }
    if (result.solve.heading_delay.status != pipeline::DelayStatus::kNotEstimated) {
      std::snprintf(line, sizeof(line),
                    "  clock      heading delay after the GNSS epochs %+.4f ± %.4f s (prior σ "
                    "%.4f s): %s\n",
                    result.solve.heading_delay.value_s, result.solve.heading_delay.sigma_s,
                    result.solve.heading_delay.prior_sigma_s,
                    pipeline::DelayStatusName(result.solve.heading_delay.status));
      out << line;
    } else {
      out << "  clock      heading delay not estimated (" << MethodText(e)
          << (e.method == solvers::Method::kCeres ? ": no moving scans in the adjustment, and at a station the "
                                    "heading does not change with time)\n"
                                  : " does not model it)\n");
    }
    const analysis::ResidualAnalysis& ra = result.finish.residual_analysis;
    if (ra.done) {
      std::snprintf(line, sizeof(line),
                    "  analysis   robust sigma %.4f m, %.1f %% beyond 2 sigma, %zu flagged "
                    "trend(s)\n",
                    ra.robust_sigma_m, 100.0 * ra.outlier_share, ra.flags.size());
      out << line;
    }
    const analysis::Repeatability& rep = result.finish.repeatability;
    if (rep.done) {
      out << "  repeat    ";
      if (rep.bootstrap_samples > 0) {
        std::snprintf(line, sizeof(line), " bootstrap (%d) sigma x %.4f m, y %.4f m, yaw %.3f deg;",
                      rep.bootstrap_samples, rep.bootstrap_sigma_x_m, rep.bootstrap_sigma_y_m,
                      rep.bootstrap_sigma_yaw_rad * kRadToDeg);
        out << line;
      }
      std::snprintf(line, sizeof(line),
                    " split halves/odd-even move it at most x %.4f m, y %.4f m, yaw %.3f deg\n",
                    rep.max_split_shift_x_m, rep.max_split_shift_y_m,
                    rep.max_split_shift_yaw_rad * kRadToDeg);
      out << line;
    }
    if (result.solve.forced)
      out << "  FORCED     written although the data do not determine the mount\n";
  } else {
    out << "  mount      NOT DETERMINED: " << result.Why() << "\n";
  }
  for (const pipeline::Warning& w : result.AllWarnings())
    out << "  warning    " << w.message << "\n";
  std::snprintf(line, sizeof(line), "  time       %.2f s\n", result.seconds);
  out << line;
  return out.str();
}

}  // namespace wallcal::outputs
