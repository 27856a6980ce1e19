// SPDX-License-Identifier: Apache-2.0
#include "outputs/report.h"

#include <filesystem>

#include "outputs/report_builder.h"
#include "outputs/report_decision.h"

namespace wallcal::outputs {
namespace report_detail {

std::string ReportBuilder::Build() {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n"
       << "<title>wallcal report: " << Esc(r_.loaded.session.name) << ScannerTitle() << "</title>\n"
       << "<style>\n"
       << kStyle << "</style>\n</head>\n<body>\n";
  html << "<h1>wallcal calibration report: " << Esc(r_.loaded.session.name) << ScannerTitle()
       << "</h1>\n";
  // One scanner of several: its page sits in DIR/ID/, beside the run's DIR/index.html.
  if (!r_.loaded.session.scanner_id.empty()) {
    html << "<p class=\"meta\"><a href=\"../index.html\">all scanners of this run</a></p>\n";
  }
  html << "<p class=\"meta\">session " << Esc(r_.loaded.session.file) << " &#183; scanner "
       << Esc(r_.loaded.preset.name) << " &#183; wallcal " << Esc(io::kToolVersion)
       << " &#183; run time " << F("%.2f", r_.seconds) << " s</p>\n";
  html << "<nav><a href=\"#decision\">verdict</a> <a href=\"#mount\">mount</a> "
       << "<a href=\"#site-map\">site map</a> <a href=\"#scans\">scans</a> "
       << "<a href=\"#diagnostics\">diagnostics</a></nav>\n";
  html << DecisionSectionHtml(outcome_) << MountSection() << SiteMapSection() << ScansSection();
  // Diagnostics, folded: what to look at when the verdict is not ACCEPT.
  html << "<details id=\"diagnostics\">\n<summary>Diagnostics: Hough accumulator, residuals "
          "and their trends, heading coverage, counts, solver report</summary>\n";
  html << HoughSection() << ResidualsSection() << CoverageSection() << CountsSection();
  if (!r_.solve.estimate.solver_report.empty()) {
    html << "<section id=\"solver\">\n<h2>Solver</h2>\n<pre>"
         << Esc(r_.solve.estimate.solver_report) << "</pre>\n</section>\n";
  }
  html << "</details>\n";
  html << "</body>\n</html>\n";
  return html.str();
}

std::string ReportBuilder::ScannerTitle() const {
  if (r_.loaded.session.scanner_id.empty()) return "";
  return ", scanner " + Esc(r_.loaded.session.scanner_id);
}

std::string ReportBuilder::MountSection() {
  const solvers::MountEstimate& e = r_.solve.estimate;
  const calib::Mount& m = outcome_.mount;
  const Eigen::Matrix3d& c = outcome_.covariance;
  std::ostringstream s;
  s << "<section id=\"mount\">\n<h2>Mount: the scanner in the GNSS antenna frame</h2>\n";
  if (outcome_.joint) {
    s << "<p class=\"meta\">The mount, its &#963; and the clock offset are the joint "
         "adjustment's of all scanners; the residuals, the error budget, the repeatability, the "
         "clock offset's &#963; and the counts are this scanner's own run's.</p>\n";
  }
  if (r_.solve.forced) {
    s << "<p class=\"bad\">Written with --force despite a failed observability check: treat "
         "this estimate with suspicion.</p>\n";
  }
  s << "<div class=\"flex\"><div>\n";
  if (e.usable) {
    s << "<table class=\"big\">\n<tr><th></th><th>estimate</th><th>1&#963;</th></tr>\n";
    s << "<tr><th>x (forward)</th><td class=\"num\">" << F("%.4f", m.x_m)
      << " m</td><td class=\"num\">" << F("%.4f", SigmaOf(c, 0)) << " m</td></tr>\n";
    s << "<tr><th>y (left)</th><td class=\"num\">" << F("%.4f", m.y_m)
      << " m</td><td class=\"num\">" << F("%.4f", SigmaOf(c, 1)) << " m</td></tr>\n";
    s << "<tr><th>yaw (ccw)</th><td class=\"num\">" << F("%.3f", m.yaw_rad * kRadToDeg)
      << "&#176;</td><td class=\"num\">" << F("%.3f", SigmaOf(c, 2) * kRadToDeg)
      << "&#176;</td></tr>\n</table>\n";
  } else {
    s << "<p class=\"bad\">Mount NOT DETERMINED: " << Esc(r_.Why()) << "</p>\n";
  }
  s << "<table>\n";
  const char* method_note = !e.method ? "(none)"
                            : *e.method == solvers::Method::kBarawid
                                ? "barawid (closed form, Barawid et al. 2007, Eq. 8-16)"
                                : "ceres (joint least squares, robust loss)";
  s << Row("method", Esc(method_note));
  if (e.usable) {
    const double sxy = c(0, 1) / std::max(1e-300, SigmaOf(c, 0) * SigmaOf(c, 1));
    s << Row("correlation x-y", F("%.3f", sxy));
    s << Row("Barawid 2007 notation", "a = " + F("%.4f", -m.y_m) + " m, b = " + F("%.4f", m.x_m) +
                                          " m, &#948; = " + F("%.3f", m.yaw_rad * kRadToDeg) +
                                          "&#176;");
    s << Row("residuals", "RMS " + F("%.2f", e.residual_rms_m * 1000) + " mm over " +
                              N(e.observations_used) + " observations, " +
                              N(e.observations_rejected) + " down-weighted as outliers");
  }
  if (r_.detection.first_pass.usable) {
    s << Row("first pass (wide gates)",
             "x " + F("%.4f", r_.detection.first_pass.mount.x_m) + " m, y " +
                 F("%.4f", r_.detection.first_pass.mount.y_m) + " m, yaw " +
                 F("%.3f", r_.detection.first_pass.mount.yaw_rad * kRadToDeg) + "&#176;");
  }
  if (r_.solve.scanner_offset.sigma_s > 0) {
    s << Row("scanner clock offset", F("%.4f", outcome_.clock_offset_s) + " &#177; " +
                                         F("%.4f", r_.solve.scanner_offset.sigma_s) + " s, " +
                                         pipeline::DelayStatusName(r_.solve.scanner_offset.status));
  }
  s << Row("heading delay after GNSS",
           r_.solve.heading_delay.status == pipeline::DelayStatus::kNotEstimated
               ? std::string("not estimated (no moving scans)")
               : F("%.4f", r_.solve.heading_delay.value_s) + " &#177; " +
                     F("%.4f", r_.solve.heading_delay.sigma_s) + " s, " +
                     pipeline::DelayStatusName(r_.solve.heading_delay.status));
  if (std::isfinite(r_.poses.gnss_epochs.offset_s)) {
    s << Row("GNSS epoch time",
             std::string(calib::EpochMappingStatusName(r_.poses.gnss_epochs.status)) +
                 ": latency + clock " + F("%.4f", r_.poses.gnss_epochs.offset_s) + " s, jitter " +
                 F("%.4f", r_.poses.gnss_epochs.jitter_s) + " s");
  }
  s << "</table>\n";
  s << "<h3 id=\"warnings\">Warnings</h3>\n";
  if (r_.AllWarnings().empty()) {
    s << "<p class=\"ok\">none</p>\n";
  } else {
    s << "<ul>\n";
    for (const pipeline::Warning& w : r_.AllWarnings()) {
      s << "<li class=\"warn\"><i>" << Esc(pipeline::WarningKindName(w.kind)) << "</i>: "
        << Esc(w.message) << "</li>\n";
    }
    s << "</ul>\n";
  }
  s << "</div>\n";
  s << EllipsePlot();
  s << "</div>\n";
  s << RepeatabilityTable();
  s << "</section>\n";
  return s.str();
}

std::string ReportBuilder::EllipsePlot() {
  const solvers::MountEstimate& e = r_.solve.estimate;
  if (!e.usable) return std::string();
  const calib::Mount& shown = outcome_.mount;
  const Eigen::Matrix2d c = outcome_.covariance.topLeftCorner<2, 2>();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(c);
  if (eig.info() != Eigen::Success || eig.eigenvalues()(0) < 0 || !(eig.eigenvalues()(1) > 0)) {
    return "<p>No uncertainty ellipse: the covariance of (x, y) is not positive.</p>\n";
  }
  auto ellipse = [&](double k) {
    std::vector<Eigen::Vector2d> pts;
    for (int i = 0; i <= 72; ++i) {
      const double t = i * 2.0 * kPi / 72.0;
      const Eigen::Vector2d u(std::sqrt(eig.eigenvalues()(0)) * std::cos(t),
                              std::sqrt(eig.eigenvalues()(1)) * std::sin(t));
      pts.push_back(Eigen::Vector2d(shown.x_m, shown.y_m) + k * eig.eigenvectors() * u);
    }
    return pts;
  };
  const double k95 = std::sqrt(5.991);  // χ²(2 dof) 95 %
  const std::vector<Eigen::Vector2d> e1 = ellipse(1.0), e95 = ellipse(k95);
  Box box;
  for (const auto& p : e95) box.Add(p);
  std::vector<std::pair<std::string, solvers::Mount>> others;
  if (r_.detection.first_pass.usable)
    others.emplace_back("first pass", r_.detection.first_pass.mount);
  if (r_.finish.repeatability.done) {
    for (const analysis::RepeatabilitySplit& split : r_.finish.repeatability.splits) {
      if (split.usable) others.emplace_back(split.name, split.mount);
    }
  }
  std::optional<solvers::Mount> truth = Truth();
  for (const auto& [name, m] : others) box.Add(m.x_m, m.y_m);
  if (truth) box.Add(truth->x_m, truth->y_m);
  box.Pad(0.12, 1e-4);
  box.y1 += 0.5 * (box.y1 - box.y0);  // room for the legend above the ellipse
  SvgPlot plot(460, 420, &clip_counter_);
  plot.SetRange(box.x0, box.x1, box.y0, box.y1, true);
  plot.Axes("x, forward (m)", "y, left (m)");
  plot.Polyline(e95, kBlue, 1.5, "5 3");
  plot.Polyline(e1, kBlue, 2.0);
  plot.Marker(shown.x_m, shown.y_m, Shape::kPlus, 7, kBlue);
  plot.Legend(kBlue, Swatch::kPlus, "estimate");
  plot.Legend(kBlue, Swatch::kLine, "1\xcf\x83 ellipse (39 %)");
  plot.Legend(kBlue, Swatch::kDash, "95 % ellipse");
  bool first = true;
  for (const auto& [name, m] : others) {
    const bool fp = name == "first pass";
    plot.Marker(m.x_m, m.y_m, fp ? Shape::kRing : Shape::kCross, fp ? 5 : 4, fp ? kOrange : kGrey);
    if (fp) plot.Legend(kOrange, Swatch::kRing, "first-pass estimate");
    if (!fp && first) {
      plot.Legend(kGrey, Swatch::kCross, "repeatability subsets (table below)");
      first = false;
    }
  }
  if (truth) {
    plot.Marker(truth->x_m, truth->y_m, Shape::kSquare, 3.5, kGreen);
    plot.Legend(kGreen, Swatch::kSquare, "truth (truth.yaml of a simulated session)");
  }
  return Figure(plot.Svg("Uncertainty of the scanner position (x, y)"),
                "The estimate (+) with its 1&#963; and 95 % ellipses from the estimate's "
                "covariance; equal scale on both axes.");
}

std::string ReportBuilder::RepeatabilityTable() const {
  const analysis::Repeatability& rep = r_.finish.repeatability;
  if (!rep.done) return std::string();
  std::ostringstream s;
  s << "<h3>Repeatability</h3>\n<table>\n<tr><th>subset</th><th>x (m)</th><th>y (m)</th>"
       "<th>yaw (&#176;)</th></tr>\n";
  for (const analysis::RepeatabilitySplit& split : rep.splits) {
    s << "<tr><th>" << Esc(split.name) << "</th>";
    if (split.usable) {
      s << "<td class=\"num\">" << F("%.4f", split.mount.x_m) << "</td><td class=\"num\">"
        << F("%.4f", split.mount.y_m) << "</td><td class=\"num\">"
        << F("%.3f", split.mount.yaw_rad * kRadToDeg) << "</td>";
    } else {
      s << "<td colspan=\"3\">not usable</td>";
    }
    s << "</tr>\n";
  }
  s << "</table>\n<table>\n";
  if (rep.bootstrap_samples > 0) {
    s << Row("bootstrap (" + N(rep.bootstrap_samples) + " samples) 1\xcf\x83",
             "x " + F("%.4f", rep.bootstrap_sigma_x_m) + " m, y " +
                 F("%.4f", rep.bootstrap_sigma_y_m) + " m, yaw " +
                 F("%.3f", rep.bootstrap_sigma_yaw_rad * kRadToDeg) + "&#176;");
  }
  s << Row("largest shift between subsets",
           "x " + F("%.4f", rep.max_split_shift_x_m) + " m, y " +
               F("%.4f", rep.max_split_shift_y_m) + " m, yaw " +
               F("%.3f", rep.max_split_shift_yaw_rad * kRadToDeg) + "&#176;");
  s << "</table>\n";
  return s.str();
}

std::string ReportBuilder::SiteMapSection() {
  std::ostringstream s;
  s << "<section id=\"site-map\">\n<h2>Site map (local ground frame)</h2>\n";
  const std::vector<Eigen::Vector2d>& track = d_.track_local_m;
  const std::vector<Eigen::Vector2d>& wall_points = d_.wall_points_local_m;
  std::vector<Eigen::Vector2d> control_survey, control_rtk;
  std::vector<std::string> control_ids;
  for (const pipeline::ControlMark& c : d_.controls) {
    control_survey.push_back(c.survey_local_m);
    control_rtk.push_back(c.rtk_local_m);
    control_ids.push_back(c.id);
  }
  std::string note;
  for (const std::string& n : d_.notes) note += " " + n + ".";
  Box box;
  for (const auto& p : track) box.Add(p);
  for (const auto& p : wall_points) box.Add(p);
  for (const auto& p : control_rtk) box.Add(p);
  for (const auto& w : r_.survey.walls) {
    box.Add(w.end_a_local);
    box.Add(w.end_b_local);
  }
  for (const Station& st : stations_) { box.Add(st.antenna_local_m); box.Add(st.scanner_local_m); }
  if (box.Empty()) {
    s << "<p>Nothing to draw.</p>\n</section>\n";
    return s.str();
  }
  box.Pad(0.06, 1.0);
  SvgPlot plot(1180, 620, &clip_counter_);
  plot.SetRange(box.x0, box.x1, box.y0, box.y1, true);
  plot.Axes("x, grid east (m)", "y, grid north (m)");
  plot.Polyline(track, "#8c8c8c", 2.0);
  for (const calib::WallGeometry& w : r_.survey.walls) {
    plot.Line(w.end_a_local.x(), w.end_a_local.y(), w.end_b_local.x(), w.end_b_local.y(), kDark, 4);
    const Eigen::Vector2d mid = 0.5 * (w.end_a_local + w.end_b_local);
    plot.Text(mid.x(), mid.y(), w.id, kDark, "middle", 0, -10);
  }
  for (const auto& p : wall_points) plot.Marker(p.x(), p.y(), Shape::kSquare, 2, "#000");
  for (size_t i = 0; i < control_survey.size(); ++i) {
    plot.Marker(control_survey[i].x(), control_survey[i].y(), Shape::kTriangle, 7, kPurple);
    plot.Marker(control_rtk[i].x(), control_rtk[i].y(), Shape::kCross, 4, kPurple);
    plot.Text(control_rtk[i].x(), control_rtk[i].y(), control_ids[i], kPurple, "start", 9, 4);
  }
  const double arrow_m = 1.8 * std::max(1.0, std::hypot(mount_.x_m, mount_.y_m));
  for (size_t i = 0; i < stations_.size(); ++i) {
    const Station& st = stations_[i];
    const Eigen::Vector2d a = st.antenna_local_m;
    const Eigen::Vector2d tip = a + arrow_m * Eigen::Vector2d(std::cos(st.yaw_rad), std::sin(st.yaw_rad));
    plot.Line(a.x(), a.y(), tip.x(), tip.y(), kBlue, 1.2, "3 2");
    plot.Line(a.x(), a.y(), st.scanner_local_m.x(), st.scanner_local_m.y(), kRed, 1.2);
    plot.Dot(a.x(), a.y(), 4, kBlue);
    plot.Dot(st.scanner_local_m.x(), st.scanner_local_m.y(), 3.5, kRed);
    plot.Text(a.x(), a.y(), std::to_string(i + 1), kBlue, "middle", 0, 16);
  }
  plot.Legend("#8c8c8c", Swatch::kLine, "vehicle track (GNSS antenna, all fixes with a position)");
  plot.Legend(kDark, Swatch::kLine, "surveyed wall (fitted line)");
  plot.Legend("#000", Swatch::kSquare, "surveyed wall points");
  plot.Legend(kPurple, Swatch::kTriangle, "control point in the survey (tied)");
  plot.Legend(kPurple, Swatch::kCross, "control point by RTK");
  plot.Legend(kBlue, Swatch::kDot, "stations: antenna, dashed: heading");
  plot.Legend(kRed, Swatch::kDot, "scanner at each station (" + mount_source_ + ")");
  s << Figure(plot.Svg("Site map"),
              "Local ground frame of the session (UTM zone " + N(r_.survey.frame.zone) +
                  (r_.survey.frame.north ? "N" : "S") +
                  " grid axes, origin at the first control point, or the first rover point, "
                  "ground metres). Stations are numbered in time order. " +
                  (r_.survey.tie.num_control > 0
                       ? "Control point tie RMS " + F("%.1f", r_.survey.tie.control_rms_m * 1000) +
                             " mm over " + N(r_.survey.tie.num_control) + " points."
                       : std::string("Walls surveyed by a GNSS rover: no tie.")) +
                  Esc(note));
  s << "</section>\n";
  return s.str();
}

std::string ReportBuilder::CountsSection() {
  std::ostringstream s;
  s << "<section id=\"counts\">\n<h2>Counts</h2>\n<div class=\"flex\">\n";
  s << "<table>\n<tr><th colspan=\"2\">Scans</th></tr>\n";
  s << Row("read (valid records + malformed scan lines)", N(r_.detection.scans_total));
  s << Row("used (at least one wall observation)", N(r_.finish.coverage.scans_used));
  for (const auto& [reason, count] : r_.ScansSkipped()) {
    s << Row(std::string("not used: ") + calib::ScanSkipName(reason), N(count));
  }
  s << Row("wall observations", N(static_cast<int64_t>(r_.solve.observations.size())));
  if (r_.solve.estimate.usable)
    s << Row("down-weighted as outliers", N(r_.solve.estimate.observations_rejected));
  for (const auto& [reason, count] : r_.detection.scan_lines_skipped.by_reason) {
    s << Row("log line skipped: " + reason, N(count));
  }
  s << "</table>\n";
  s << "<table>\n<tr><th colspan=\"2\">GNSS and heading</th></tr>\n";
  for (const auto& [q, count] : r_.poses.fixes_by_quality) {
    s << Row("GGA quality " + N(q) + " (" + io::FixQualityName(q) + ")", N(count));
  }
  s << Row("fixes used (quality \xe2\x89\xa5 " + N(r_.loaded.session.min_fix_quality) +
               ", in time order)",
           N(r_.poses.fixes_used));
  for (const auto& [reason, count] : r_.poses.gnss_skipped.by_reason)
    s << Row("GNSS line skipped: " + reason, N(count));
  s << Row("headings used", N(r_.poses.headings_used));
  if (r_.loaded.session.heading_log != r_.loaded.session.gnss_log) {
    for (const auto& [reason, count] : r_.poses.heading_skipped.by_reason) {
      s << Row("heading line skipped: " + reason, N(count));
    }
  }
  s << "</table>\n";
  s << "<table>\n<tr><th colspan=\"2\">Time alignment</th></tr>\n";
  s << Row("scanner clock offset applied (session)",
           F("%.4f", r_.loaded.session.scanner_time_offset_s) + " s");
  if (r_.solve.scanner_offset.sigma_s > 0) {
    s << Row("scanner clock offset estimated", F("%.4f", outcome_.clock_offset_s) + " &#177; " +
                                                   F("%.4f", r_.solve.scanner_offset.sigma_s) +
                                                   " s");
  } else {
    s << Row("scanner clock offset estimated", "no (needs scans taken while moving)");
  }
  if (d_.gnss_fixes > 0) {
    s << Row("GNSS log span", F("%.1f", d_.gnss_last_s - d_.gnss_first_s) + " s (" + N(d_.gnss_fixes) + " GGA fixes)");
  }
  if (!r_.solve.observations.empty()) {
    double t0 = 1e300, t1 = -1e300;
    for (const calib::WallObservation& o : r_.solve.observations) {
      t0 = std::min(t0, o.pose.stamp_s);
      t1 = std::max(t1, o.pose.stamp_s);
    }
    s << Row("observations span", F("%.1f", t1 - t0) + " s" +
                                      (d_.gnss_fixes > 0 ? ", from " + F("%.1f", t0 - d_.gnss_first_s) +
                                                             " s after the first GNSS fix"
                                                       : std::string()));
  }
  s << Row("poses", "GNSS and heading interpolated at each scan's time; scans outside their "
                    "overlap or in a gap are counted above as \"no pose\"");
  s << "</table>\n</div>\n</section>\n";
  return s.str();
}

}  // namespace report_detail

using report_detail::CalibrationResult;
using report_detail::ReportBuilder;
namespace fs = std::filesystem;

std::string FormatReportHtml(const CalibrationResult& result,
                             const pipeline::JointScannerResult* joint) {
  const PageOutcome outcome = joint ? JointOutcome(result, *joint) : OwnOutcome(result);
  ReportBuilder builder(outcome);
  return builder.Build();
}

std::string WriteReport(const CalibrationResult& result, const std::string& dir,
                        const pipeline::JointScannerResult* joint) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir)) {
    throw io::InputError(dir + ": cannot create the report folder" +
                         (error ? " (" + error.message() + ")" : std::string()));
  }
  const std::string path = (fs::path(dir) / "report.html").string();
  io::WriteFileAtomically(path, FormatReportHtml(result, joint));
  return path;
}

}  // namespace wallcal::outputs
