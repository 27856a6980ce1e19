// SPDX-License-Identifier: Apache-2.0
// The page of a run with several scanners (outputs/multi_report.h).

#include "outputs/multi_report.h"

#include "outputs/report_builder.h"
#include "outputs/summary.h"

namespace wallcal::outputs {
namespace {

using namespace report_detail;  // NOLINT: the report's drawing helpers

// One colour per scanner on the site map, in session.yaml's order (then repeating).
const char* const kScannerColours[] = {kRed, kBlue, kGreen, kOrange, kPurple};
// At most this many detections per scanner are drawn (every k-th), so that an hour's session
// still gives a page of a few hundred kilobytes.
constexpr size_t kMaxDetectionsPerScanner = 1500;

const char* VerdictClass(pipeline::Verdict v) {
  return v == pipeline::Verdict::kAccept ? "v-accept"
         : v == pipeline::Verdict::kReview ? "v-review"
                                           : "v-reject";
}

std::string Badge(pipeline::Verdict v) {
  return std::string("<span class=\"") + (v == pipeline::Verdict::kAccept ? "ok" : "bad") + "\">" +
         pipeline::VerdictName(v) + "</span>";
}

std::string Reasons(const pipeline::Decision& decision) {
  std::string out;
  for (const std::string& reason : decision.reasons) out += "<br/>&#8226; " + Esc(reason);
  return out;
}

// "2.4580 &#177; 0.0134 m" cells for x, y (m) and yaw (degrees); digits for mm-level σ.
std::string PoseCells(const solvers::Mount& mount, const Eigen::Matrix3d& covariance,
                      const char* format_m) {
  return "<td class=\"num\">" + F(format_m, mount.x_m) + " &#177; " +
         F(format_m, SigmaOf(covariance, 0)) + " m</td><td class=\"num\">" +
         F(format_m, mount.y_m) + " &#177; " + F(format_m, SigmaOf(covariance, 1)) +
         " m</td><td class=\"num\">" + F("%.4f", mount.yaw_rad * kRadToDeg) + " &#177; " +
         F("%.4f", SigmaOf(covariance, 2) * kRadToDeg) + "&#176;</td>";
}

std::string ChangeCell(const std::optional<pipeline::Change>& change) {
  return "<td>" + (change ? Esc(ChangeText(*change)) : std::string("&#8212;")) + "</td>";
}

std::string ScannersSection(const pipeline::SeveralScannersResult& several) {
  std::ostringstream s;
  s << "<section id=\"scanners\">\n<h2>Scanners: each mount in the GNSS antenna frame</h2>\n";
  s << "<table>\n<tr><th>scanner (frame)</th><th>verdict</th><th>x (forward)</th>"
       "<th>y (left)</th><th>yaw (ccw)</th><th>clock offset</th><th>observations</th>"
       "<th>change since previous</th><th>its page</th></tr>\n";
  for (const pipeline::ScannerRun& run : several.scanners) {
    const pipeline::CalibrationResult& own = run.own;
    s << "<tr><th>" << Esc(run.spec.id) << " (" << Esc(run.spec.frame) << ")</th>";
    if (!run.joint) {
      s << "<td class=\"bad\">REFUSED</td><td colspan=\"6\">" << Esc(own.Why()) << "</td>";
    } else {
      const pipeline::JointScannerResult& joint = *run.joint;
      s << "<td>" << Badge(joint.decision.verdict) << Reasons(joint.decision) << "</td>"
        << PoseCells(joint.mount, joint.covariance, "%.4f") << "<td class=\"num\">"
        << F("%.4f", joint.time_offset_s) << " s</td><td class=\"num\">"
        << N(own.solve.estimate.observations_used) << "</td>" << ChangeCell(joint.change);
    }
    s << "<td><a href=\"" << Esc(run.spec.id) << "/report.html\">" << Esc(run.spec.id)
      << "/report.html</a></td></tr>\n";
  }
  s << "</table>\n";
  s << "<p>&#177; is the 1&#963; of the joint adjustment: the shared GNSS, heading and survey "
       "errors are in each mount's &#963; (docs/method.md, \"Several scanners\").</p>\n";
  for (const std::string& id : several.not_in_previous) {
    s << "<p class=\"warn\">Scanner " << Esc(id) << " is not in "
      << Esc(several.previous_input.path) << ": nothing to compare it with.</p>\n";
  }
  for (const std::string& id : several.only_in_previous) {
    s << "<p class=\"warn\">Scanner " << Esc(id) << " of " << Esc(several.previous_input.path)
      << " is not calibrated in this run.</p>\n";
  }
  s << "</section>\n";
  return s.str();
}

std::string RelativeSection(const pipeline::SeveralScannersResult& several) {
  std::ostringstream s;
  s << "<section id=\"relative\">\n<h2>Relative transforms: one scanner in another's frame</h2>\n";
  if (several.relative.empty()) {
    s << "<p>None: fewer than two scanners are calibrated.</p>\n</section>\n";
    return s.str();
  }
  s << "<table>\n<tr><th>to in from</th><th>verdict</th><th>x</th><th>y</th><th>yaw</th>"
       "<th>change since previous</th></tr>\n";
  for (const pipeline::RelativeMountResult& relative : several.relative) {
    s << "<tr><th>" << Esc(relative.to_id) << " in " << Esc(relative.from_id) << "</th><td>"
      << Badge(relative.decision.verdict) << Reasons(relative.decision) << "</td>"
      << PoseCells(relative.mount.from_T_to, relative.mount.covariance, "%.5f")
      << ChangeCell(relative.change) << "</tr>\n";
  }
  s << "</table>\n<p>The pose of <i>to</i> in the frame of <i>from</i> with its 1&#963; from the "
       "joint covariance: the errors both mounts share cancel in it, so it is known far better "
       "than either mount. Its tolerances are acceptance.relative_* of the options.</p>\n";
  s << "</section>\n";
  return s.str();
}

std::string SiteMapSection(const pipeline::SeveralScannersResult& several) {
  std::ostringstream s;
  s << "<section id=\"site-map\">\n<h2>Site map: every scanner's detections</h2>\n";
  // The session's walls, track and stations are the same in every scanner's run (one survey,
  // one GNSS log): the first run that has them draws them.
  const pipeline::CalibrationResult* base = nullptr;
  for (const pipeline::ScannerRun& run : several.scanners) {
    if (!run.own.survey.walls.empty()) {
      base = &run.own;
      break;
    }
  }
  if (base == nullptr) {
    s << "<p>Nothing to draw: no scanner's run got as far as the walls.</p>\n</section>\n";
    return s.str();
  }
  struct Drawn {
    std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> detections;
    std::vector<Eigen::Vector2d> scanner_at_stations;
    std::string label;
  };
  std::vector<Drawn> drawn;
  Box box;
  for (const pipeline::ScannerRun& run : several.scanners) {
    const pipeline::CalibrationResult& r = run.own;
    const std::vector<calib::WallObservation>& observations = r.solve.observations;
    if (!r.solve.estimate.usable || observations.empty()) continue;
    // Drawn with its joint mount; with its own when it is not in the joint adjustment.
    const solvers::Mount& mount = run.joint ? run.joint->mount : r.solve.estimate.mount;
    const pipeline::ReportData& report = run.joint ? run.joint->report : r.report;
    const std::vector<calib::WallGeometry>& walls = r.survey.walls;
    Drawn d;
    d.label = run.spec.id + (run.joint ? "" : " (own estimate, left out)");
    const size_t step =
        (observations.size() + kMaxDetectionsPerScanner - 1) / kMaxDetectionsPerScanner;
    for (size_t i = 0; i < observations.size(); i += step) {
      const calib::WallObservation& o = observations[i];
      if (o.wall_index < 0 || o.wall_index >= static_cast<int>(walls.size())) continue;
      d.detections.push_back(DetectionSegmentLocal(o, walls[o.wall_index], mount));
      box.Add(d.detections.back().first);
      box.Add(d.detections.back().second);
    }
    for (const pipeline::Station& station : report.stations) {
      d.scanner_at_stations.push_back(station.antenna_local_m +
                                      Eigen::Rotation2Dd(station.yaw_rad) *
                                          Eigen::Vector2d(mount.x_m, mount.y_m));
      box.Add(d.scanner_at_stations.back());
    }
    drawn.push_back(std::move(d));
  }
  const std::vector<Eigen::Vector2d>& track = base->report.track_local_m;
  for (const Eigen::Vector2d& p : track) box.Add(p);
  for (const calib::WallGeometry& w : base->survey.walls) {
    box.Add(w.end_a_local);
    box.Add(w.end_b_local);
  }
  box.Pad(0.06, 1.0);
  int clip_counter = 0;
  SvgPlot plot(1180, 620, &clip_counter);
  plot.SetRange(box.x0, box.x1, box.y0, box.y1, true);
  plot.Axes("x, grid east (m)", "y, grid north (m)");
  if (!track.empty()) plot.Polyline(track, "#8c8c8c", 2.0);
  for (const calib::WallGeometry& w : base->survey.walls) {
    plot.Line(w.end_a_local.x(), w.end_a_local.y(), w.end_b_local.x(), w.end_b_local.y(), kDark, 4);
    const Eigen::Vector2d mid = 0.5 * (w.end_a_local + w.end_b_local);
    plot.Text(mid.x(), mid.y(), w.id, kDark, "middle", 0, -10);
  }
  for (size_t k = 0; k < drawn.size(); ++k) {
    const char* colour = kScannerColours[k % (sizeof(kScannerColours) / sizeof(*kScannerColours))];
    for (const auto& [a, b] : drawn[k].detections) plot.Line(a.x(), a.y(), b.x(), b.y(), colour, 0.8);
    for (const Eigen::Vector2d& p : drawn[k].scanner_at_stations) plot.Dot(p.x(), p.y(), 3.5, colour);
    plot.Legend(colour, Swatch::kLine,
                drawn[k].label + ": detected wall lines (" + N(static_cast<int64_t>(drawn[k].detections.size())) +
                    " drawn), dots: the scanner at each station");
  }
  if (!track.empty()) plot.Legend("#8c8c8c", Swatch::kLine, "vehicle track (GNSS antenna)");
  plot.Legend(kDark, Swatch::kLine, "surveyed wall (fitted line)");
  s << Figure(plot.Svg("Site map"),
              "Local ground frame of the session (grid axes, ground metres). Each detection is "
              "the wall line a scanner's scan found, between its inliers' ranges, placed with "
              "the vehicle pose and that scanner's mount: where the scanners agree with each "
              "other and with the survey, their lines lie on the surveyed wall.");
  s << "</section>\n";
  return s.str();
}

}  // namespace

std::pair<Eigen::Vector2d, Eigen::Vector2d> DetectionSegmentLocal(const calib::WallObservation& o,
                                                                  const calib::WallGeometry& wall,
                                                                  const solvers::Mount& mount) {
  // The side follows the report's convention (outputs/report_builder.h AxesOf).
  const Eigen::Rotation2Dd local_R_scanner(o.pose.yaw_rad + mount.yaw_rad);
  const Eigen::Vector2d scanner = report_detail::ScannerLocal(o.pose, mount);
  const Eigen::Vector2d normal(std::cos(o.theta_rad), std::sin(o.theta_rad));
  const Eigen::Vector2d along(-normal.y(), normal.x());
  const Eigen::Vector2d centre_scanner =
      local_R_scanner.inverse() * (0.5 * (wall.end_a_local + wall.end_b_local) - scanner);
  const double side = centre_scanner.dot(along) >= 0.0 ? 1.0 : -1.0;
  const auto offset = [&o](double range_m) {
    return std::sqrt(std::max(0.0, range_m * range_m - o.rho_m * o.rho_m));
  };
  const Eigen::Vector2d foot = o.rho_m * normal;
  const Eigen::Vector2d a = foot + side * offset(o.range_min_m) * along;
  const Eigen::Vector2d b = foot + side * offset(o.range_max_m) * along;
  return {scanner + local_R_scanner * a, scanner + local_R_scanner * b};
}

std::string FormatSeveralReportHtml(const pipeline::SeveralScannersResult& several) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n"
       << "<title>wallcal report: " << Esc(several.session.name) << " (" << several.scanners.size()
       << " scanners)</title>\n<style>\n" << kReportStyle << "</style>\n</head>\n<body>\n";
  html << "<h1>wallcal calibration report: " << Esc(several.session.name) << ", "
       << several.scanners.size() << " scanners</h1>\n";
  html << "<p class=\"meta\">session " << Esc(several.session.file) << " &#183; wallcal "
       << Esc(io::kToolVersion) << " &#183; run time " << F("%.2f", several.seconds) << " s</p>\n";
  html << "<nav><a href=\"#decision\">verdict</a> <a href=\"#scanners\">scanners</a> "
       << "<a href=\"#relative\">relative transforms</a> <a href=\"#site-map\">site map</a></nav>\n";
  html << "<section id=\"decision\">\n<h2>Verdict</h2>\n";
  if (several.outcome == pipeline::SeveralOutcome::kFailed) {
    html << "<p><span class=\"verdict v-reject\">NOT WRITTEN</span></p>\n<p class=\"bad\">"
         << Esc(several.message) << "</p>\n";
  } else {
    html << "<p><span class=\"verdict " << VerdictClass(several.decision.verdict) << "\">"
         << pipeline::VerdictName(several.decision.verdict) << "</span></p>\n";
    html << "<p>The worst of the scanners' and the relative transforms' verdicts below.</p>\n";
    if (!several.decision.reasons.empty()) {
      html << "<ul>\n";
      for (const std::string& reason : several.decision.reasons) {
        html << "<li>" << Esc(reason) << "</li>\n";
      }
      html << "</ul>\n";
    }
    if (!several.message.empty()) html << "<p class=\"warn\">" << Esc(several.message) << "</p>\n";
  }
  html << "</section>\n";
  html << ScannersSection(several) << RelativeSection(several) << SiteMapSection(several);
  html << "</body>\n</html>\n";
  return html.str();
}

std::string WriteSeveralReport(const pipeline::SeveralScannersResult& several,
                               const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error || !std::filesystem::is_directory(dir)) {
    throw io::InputError(dir + ": cannot create the report folder" +
                         (error ? " (" + error.message() + ")" : std::string()));
  }
  const std::string path = (std::filesystem::path(dir) / "index.html").string();
  io::WriteFileAtomically(path, FormatSeveralReportHtml(several));
  return path;
}

}  // namespace wallcal::outputs
