#include "outputs/report.h"
#include "outputs/report_decision.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "calib/range_model.h"
#include "calib/wall_detector.h"
#include "io/version.h"
#include "io/writers.h"
#include "common/angles.h"
#include "outputs/svg_plot.h"

namespace wallcal::outputs {

using pipeline::CalibrationResult;
using pipeline::Station;
namespace {

namespace fs = std::filesystem;
// ---- Text ------------------------------------------------------------------------------------

std::string F(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

std::string N(int64_t value) { return std::to_string(value); }

double SigmaOf(const Eigen::Matrix3d& covariance, int i) {
  return std::sqrt(std::max(0.0, covariance(i, i)));
}

// Grid heading (deg, clockwise from grid north) wrapped to (−180, 180] from a vehicle yaw (ccw
// from grid east): the sessions circle a wall, so headings straddle north as often as not.
double GridHeadingDeg(double yaw_rad) { return WrapAngle(kPi / 2.0 - yaw_rad) * kRadToDeg; }

const char* kBlue = "#1f5fbf";
const char* kRed = "#d62728";
const char* kOrange = "#ff7f0e";
const char* kGreen = "#2ca02c";
const char* kGrey = "#9a9a9a";
const char* kDark = "#333333";
const char* kPurple = "#7b3fb0";

// ---- Per-observation plot axes ------------------------------------------------------------

Eigen::Vector2d ScannerLocal(const calib::VehiclePose& pose, const solvers::Mount& mount) {
  return pose.antenna_local_m + Eigen::Rotation2Dd(pose.yaw_rad) * Eigen::Vector2d(mount.x_m, mount.y_m);
}

// The quantities residuals are plotted against, per observation. The "characteristic beam" of
// an observation is the beam at the middle of its inliers' range span, r_mid: its incidence on
// the wall is acos(ρ / r_mid) and it lies on the side of the wall's foot where the surveyed
// wall's centre is (seen from the scanner with the final mount).
struct ObservationAxes {
  double heading_deg = 0, range_m = 0, incidence_deg = 0, bearing_deg = 0;
};

ObservationAxes AxesOf(const calib::WallObservation& o, const calib::WallGeometry& wall,
                       const solvers::Mount& mount) {
  ObservationAxes a;
  a.heading_deg = GridHeadingDeg(o.pose.yaw_rad);
  a.range_m = 0.5 * (o.range_min_m + o.range_max_m);
  const double ratio = a.range_m > 0 ? std::min(1.0, o.rho_m / a.range_m) : 1.0;
  const double incidence_rad = std::acos(std::max(-1.0, ratio));
  a.incidence_deg = incidence_rad * kRadToDeg;
  const Eigen::Vector2d scanner = ScannerLocal(o.pose, mount);
  const Eigen::Vector2d centre = 0.5 * (wall.end_a_local + wall.end_b_local);
  const Eigen::Vector2d c_scanner =
      Eigen::Rotation2Dd(-(o.pose.yaw_rad + mount.yaw_rad)) * (centre - scanner);
  const double side = WrapAngle(std::atan2(c_scanner.y(), c_scanner.x()) - o.theta_rad) >= 0 ? 1.0 : -1.0;
  a.bearing_deg = WrapAngle(o.theta_rad + side * incidence_rad) * kRadToDeg;
  return a;
}

std::string Row(const std::string& key, const std::string& value) {
  return "<tr><th>" + Esc(key) + "</th><td>" + value + "</td></tr>\n";
}

std::string Figure(const std::string& svg, const std::string& caption) {
  return "<figure>" + svg + "<figcaption>" + caption + "</figcaption></figure>\n";
}

// Colour ramp for the accumulator (dark blue -> teal -> yellow), t in [0, 1].
std::string Ramp(double t) {
  static const double stops[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  t = std::clamp(t, 0.0, 1.0) * 4.0;
  const int i = std::min(3, static_cast<int>(t));
  const double f = t - i;
  char buffer[16];
  std::snprintf(buffer, sizeof(buffer), "#%02x%02x%02x",
                static_cast<int>(stops[i][0] + f * (stops[i + 1][0] - stops[i][0])),
                static_cast<int>(stops[i][1] + f * (stops[i + 1][1] - stops[i][1])),
                static_cast<int>(stops[i][2] + f * (stops[i + 1][2] - stops[i][2])));
  return buffer;
}

// ---- The page --------------------------------------------------------------------------------

class ReportBuilder {
 public:
  explicit ReportBuilder(const CalibrationResult& result)
      : r_(result), d_(result.report), mount_(d_.mount), mount_source_(d_.mount_source),
        have_mount_(d_.have_mount), stations_(d_.stations), panels_(d_.panels) {
    const solvers::MountEstimate& e = r_.estimate;
    residuals_ok_ = e.residual_rho_m.size() == r_.observations.size() && !r_.observations.empty();
  }

  std::string Build() {
    std::ostringstream html;
    html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n"
         << "<title>wallcal report: " << Esc(r_.session.name) << "</title>\n"
         << "<style>\n" << kStyle << "</style>\n</head>\n<body>\n";
    html << "<h1>wallcal calibration report: " << Esc(r_.session.name) << "</h1>\n";
    html << "<p class=\"meta\">session " << Esc(r_.session.file) << " &#183; scanner "
         << Esc(r_.preset.name) << " &#183; wallcal " << Esc(io::kToolVersion) << " &#183; run time "
         << F("%.2f", r_.seconds) << " s</p>\n";
    html << "<nav><a href=\"#decision\">verdict</a> <a href=\"#mount\">mount</a> "
         << "<a href=\"#site-map\">site map</a> <a href=\"#scans\">scans</a> "
         << "<a href=\"#diagnostics\">diagnostics</a></nav>\n";
    html << DecisionSectionHtml(r_) << MountSection() << SiteMapSection() << ScansSection();
    // Diagnostics, folded: what to look at when the verdict is not ACCEPT.
    html << "<details id=\"diagnostics\">\n<summary>Diagnostics: Hough accumulator, residuals "
            "and their trends, heading coverage, counts, solver report</summary>\n";
    html << HoughSection() << ResidualsSection() << CoverageSection() << CountsSection();
    if (!r_.estimate.solver_report.empty()) {
      html << "<section id=\"solver\">\n<h2>Solver</h2>\n<pre>" << Esc(r_.estimate.solver_report)
           << "</pre>\n</section>\n";
    }
    html << "</details>\n";
    html << "</body>\n</html>\n";
    return html.str();
  }

 private:
  static constexpr const char* kStyle =
      "body{font-family:sans-serif;font-size:14px;color:#222;margin:16px 24px;max-width:1240px}\n"
      "h1{font-size:22px;margin:4px 0}h2{font-size:18px;border-bottom:1px solid #ccc;"
      "margin-top:28px}\n"
      "p.meta{color:#555;margin:2px 0 8px 0}nav a{margin-right:12px}\n"
      "table{border-collapse:collapse;margin:6px 0}th,td{border:1px solid #ddd;padding:3px 8px;"
      "text-align:left;vertical-align:top}th{background:#f4f4f4;font-weight:normal}\n"
      "td.num{text-align:right;font-variant-numeric:tabular-nums}\n"
      ".flex{display:flex;flex-wrap:wrap;gap:12px;align-items:flex-start}\n"
      "figure{margin:0;display:inline-block}figcaption{font-size:12px;color:#444;"
      "max-width:600px;margin-top:2px}\n"
      "svg.plot{border:1px solid #ddd;font-family:sans-serif;font-size:11px}\n"
      "svg text.ptitle{font-size:13px;font-weight:bold}svg text.label{font-size:12px}\n"
      "svg text.legend{font-size:11px}\n"
      ".warn{color:#a15c00}.bad{color:#b00020;font-weight:bold}.ok{color:#1b7a1b}\n"
      ".big td,.big th{font-size:16px}\n"
      ".verdict{font-size:26px;font-weight:bold;padding:6px 14px;display:inline-block;"
      "border-radius:4px;color:#fff}.v-accept{background:#1b7a1b}.v-review{background:#b36b00}"
      ".v-reject{background:#b00020}\n"
      "details{margin-top:28px}summary{font-size:16px;cursor:pointer}\n";

  // ---- mount ----
  std::string MountSection() {
    const solvers::MountEstimate& e = r_.estimate;
    std::ostringstream s;
    s << "<section id=\"mount\">\n<h2>Mount: the scanner in the GNSS antenna frame</h2>\n";
    if (r_.forced) {
      s << "<p class=\"bad\">Written with --force despite a failed observability check: treat "
           "this estimate with suspicion.</p>\n";
    }
    s << "<div class=\"flex\"><div>\n";
    if (e.usable) {
      s << "<table class=\"big\">\n<tr><th></th><th>estimate</th><th>1&#963;</th></tr>\n";
      s << "<tr><th>x (forward)</th><td class=\"num\">" << F("%.4f", e.mount.x_m)
        << " m</td><td class=\"num\">" << F("%.4f", SigmaOf(e.covariance, 0)) << " m</td></tr>\n";
      s << "<tr><th>y (left)</th><td class=\"num\">" << F("%.4f", e.mount.y_m)
        << " m</td><td class=\"num\">" << F("%.4f", SigmaOf(e.covariance, 1)) << " m</td></tr>\n";
      s << "<tr><th>yaw (ccw)</th><td class=\"num\">" << F("%.3f", e.mount.yaw_rad * kRadToDeg)
        << "&#176;</td><td class=\"num\">" << F("%.3f", SigmaOf(e.covariance, 2) * kRadToDeg)
        << "&#176;</td></tr>\n</table>\n";
    } else {
      s << "<p class=\"bad\">Mount NOT DETERMINED: " << Esc(e.message) << "</p>\n";
    }
    s << "<table>\n";
    s << Row("method", Esc(e.method.empty() ? "(none)" : e.method) +
                           (e.method == "barawid" ? " (closed form, Barawid et al. 2007, Eq. 8-16)"
                                                  : e.method == "ceres"
                                                        ? " (joint least squares, robust loss)"
                                                        : ""));
    if (e.usable) {
      const double sxy = e.covariance(0, 1) / std::max(1e-300, SigmaOf(e.covariance, 0) *
                                                                    SigmaOf(e.covariance, 1));
      s << Row("correlation x-y", F("%.3f", sxy));
      s << Row("Barawid 2007 notation", "a = " + F("%.4f", -e.mount.y_m) + " m, b = " +
                                        F("%.4f", e.mount.x_m) + " m, &#948; = " +
                                        F("%.3f", e.mount.yaw_rad * kRadToDeg) + "&#176;");
      s << Row("residuals", "RMS " + F("%.2f", e.residual_rms_m * 1000) + " mm over " +
                                N(e.observations_used) + " observations, " +
                                N(e.observations_rejected) + " down-weighted as outliers");
    }
    if (r_.first_pass.usable) {
      s << Row("first pass (wide gates)",
               "x " + F("%.4f", r_.first_pass.mount.x_m) + " m, y " +
                   F("%.4f", r_.first_pass.mount.y_m) + " m, yaw " +
                   F("%.3f", r_.first_pass.mount.yaw_rad * kRadToDeg) + "&#176;");
    }
    if (r_.time_offset_sigma_s > 0) {
      s << Row("scanner clock offset", F("%.4f", r_.time_offset_s) + " &#177; " +
                                           F("%.4f", r_.time_offset_sigma_s) + " s (estimated)");
    }
    s << "</table>\n";
    s << "<h3 id=\"warnings\">Warnings</h3>\n";
    if (r_.warnings.empty()) {
      s << "<p class=\"ok\">none</p>\n";
    } else {
      s << "<ul>\n";
      for (const std::string& w : r_.warnings) s << "<li class=\"warn\">" << Esc(w) << "</li>\n";
      s << "</ul>\n";
    }
    s << "</div>\n";
    s << EllipsePlot();
    s << "</div>\n";
    s << RepeatabilityTable();
    s << "</section>\n";
    return s.str();
  }

  std::string EllipsePlot() {
    const solvers::MountEstimate& e = r_.estimate;
    if (!e.usable) return std::string();
    const Eigen::Matrix2d c = e.covariance.topLeftCorner<2, 2>();
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
        pts.push_back(Eigen::Vector2d(e.mount.x_m, e.mount.y_m) + k * eig.eigenvectors() * u);
      }
      return pts;
    };
    const double k95 = std::sqrt(5.991);  // χ²(2 dof) 95 %
    const std::vector<Eigen::Vector2d> e1 = ellipse(1.0), e95 = ellipse(k95);
    Box box;
    for (const auto& p : e95) box.Add(p);
    std::vector<std::pair<std::string, solvers::Mount>> others;
    if (r_.first_pass.usable) others.emplace_back("first pass", r_.first_pass.mount);
    if (r_.repeatability.done) {
      for (const analysis::RepeatabilitySplit& split : r_.repeatability.splits) {
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
    plot.Marker(e.mount.x_m, e.mount.y_m, "plus", 7, kBlue);
    plot.Legend(kBlue, "marker:plus", "estimate");
    plot.Legend(kBlue, "line", "1\xcf\x83 ellipse (39 %)");
    plot.Legend(kBlue, "dash", "95 % ellipse");
    bool first = true;
    for (const auto& [name, m] : others) {
      const bool fp = name == "first pass";
      plot.Marker(m.x_m, m.y_m, fp ? "ring" : "cross", fp ? 5 : 4, fp ? kOrange : kGrey);
      if (fp) plot.Legend(kOrange, "marker:ring", "first-pass estimate");
      if (!fp && first) {
        plot.Legend(kGrey, "marker:cross", "repeatability subsets (table below)");
        first = false;
      }
    }
    if (truth) {
      plot.Marker(truth->x_m, truth->y_m, "square", 3.5, kGreen);
      plot.Legend(kGreen, "marker:square", "truth (truth.yaml of a simulated session)");
    }
    return Figure(plot.Svg("Uncertainty of the scanner position (x, y)"),
                  "The estimate (+) with its 1&#963; and 95 % ellipses from the estimate's "
                  "covariance; equal scale on both axes.");
  }

  std::optional<solvers::Mount> Truth() const { return d_.truth; }

  std::string RepeatabilityTable() const {
    const analysis::Repeatability& rep = r_.repeatability;
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

  // ---- site map ----
  std::string SiteMapSection() {
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
    for (const auto& w : r_.walls) { box.Add(w.end_a_local); box.Add(w.end_b_local); }
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
    for (const calib::WallGeometry& w : r_.walls) {
      plot.Line(w.end_a_local.x(), w.end_a_local.y(), w.end_b_local.x(), w.end_b_local.y(), kDark, 4);
      const Eigen::Vector2d mid = 0.5 * (w.end_a_local + w.end_b_local);
      plot.Text(mid.x(), mid.y(), w.id, kDark, "middle", 0, -10);
    }
    for (const auto& p : wall_points) plot.Marker(p.x(), p.y(), "square", 2, "#000");
    for (size_t i = 0; i < control_survey.size(); ++i) {
      plot.Marker(control_survey[i].x(), control_survey[i].y(), "triangle", 7, kPurple);
      plot.Marker(control_rtk[i].x(), control_rtk[i].y(), "cross", 4, kPurple);
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
    plot.Legend("#8c8c8c", "line", "vehicle track (GNSS antenna, all fixes with a position)");
    plot.Legend(kDark, "line", "surveyed wall (fitted line)");
    plot.Legend("#000", "marker:square", "surveyed wall points");
    plot.Legend(kPurple, "marker:triangle", "control point in the survey (tied)");
    plot.Legend(kPurple, "marker:cross", "control point by RTK");
    plot.Legend(kBlue, "dot", "stations: antenna, dashed: heading");
    plot.Legend(kRed, "dot", "scanner at each station (" + mount_source_ + ")");
    s << Figure(plot.Svg("Site map"),
                "Local ground frame of the session (UTM zone " + N(r_.frame.zone) +
                    (r_.frame.north ? "N" : "S") +
                    " grid axes, origin at the first control point, ground metres). Stations are "
                    "numbered in time order. Control point tie RMS " +
                    F("%.1f", r_.control_rms_m * 1000) + " mm over " + N(r_.num_control) +
                    " points." + Esc(note));
    s << "</section>\n";
    return s.str();
  }

  // ---- scans ----
  double TightAngleGate() const { return d_.tight_gates.angle_rad; }
  double TightOffsetGate() const { return d_.tight_gates.offset_m; }

  std::string ScansSection() {
    std::ostringstream s;
    s << "<section id=\"scans\">\n<h2>Scans in the scanner frame</h2>\n";
    if (panels_.empty()) {
      s << "<p>No station scans to show (no stationary observations).</p>\n</section>\n";
      return s.str();
    }
    s << "<p>One scan from the middle of each of " << panels_.size()
      << " stations spread over the headings, detected again with the run's detector options and "
         "a gate around the "
      << Esc(mount_source_) << " (&#177;" << F("%.2f", TightAngleGate() * kRadToDeg) << "&#176;, &#177;"
      << F("%.2f", TightOffsetGate()) << " m, as the second pass).</p>\n<div class=\"flex\">\n";
    for (const pipeline::ScanPanel& panel : panels_) s << ScanPlot(panel);
    s << "</div>\n</section>\n";
    return s.str();
  }

  std::string ScanPlot(const pipeline::ScanPanel& panel) {
    const calib::WallObservation& o = r_.observations[panel.observation];
    const int station_number = panel.station + 1;
    if (!panel.have_scan) {
      return "<p>Station " + N(station_number) + ": scan " + N(o.scan_index) + " not found in the log.</p>\n";
    }
    const calib::ScanPoints& points = panel.points;
    const calib::LineGate& gate = panel.gate;
    const calib::WallDetection& d = panel.detection;
    std::vector<uint8_t> inlier(points.p_scanner_m.size(), 0);
    for (int i : d.inliers) inlier[static_cast<size_t>(i)] = 1;
    Box box;
    box.Add(0, 0);
    for (size_t i = 0; i < inlier.size(); ++i) {
      if (inlier[i]) box.Add(points.p_scanner_m[i]);
    }
    box.Add(gate.segment_a_scanner);
    box.Add(gate.segment_b_scanner);
    box.Pad(0.15, 1.0);
    SvgPlot plot(590, 440, &clip_counter_);
    plot.SetRange(box.x0, box.x1, box.y0, box.y1, true);
    plot.Axes("x, scanner forward (m)", "y, scanner left (m)");
    int clutter = 0, mixed = 0, outside = 0;
    for (size_t i = 0; i < points.p_scanner_m.size(); ++i) {
      const Eigen::Vector2d& p = points.p_scanner_m[i];
      if (!plot.Inside(p.x(), p.y())) {
        ++outside;
        if (!inlier[i]) {
          if (points.mixed_suspect[i]) ++mixed; else ++clutter;
        }
        continue;
      }
      if (inlier[i]) continue;  // drawn on top below
      if (points.mixed_suspect[i]) {
        ++mixed;
        plot.Marker(p.x(), p.y(), "cross", 3, kOrange);
      } else {
        ++clutter;
        plot.Dot(p.x(), p.y(), 1.8, kGrey);
      }
    }
    // The surveyed wall as predicted from the mount, then the detected line over its inliers.
    plot.Line(gate.segment_a_scanner.x(), gate.segment_a_scanner.y(), gate.segment_b_scanner.x(),
              gate.segment_b_scanner.y(), kGreen, 9, "", 0.3);
    for (int i : d.inliers) {
      const Eigen::Vector2d& p = points.p_scanner_m[static_cast<size_t>(i)];
      plot.Dot(p.x(), p.y(), 1.9, kBlue);
    }
    if (d.found && !d.inliers.empty()) {
      const Eigen::Vector2d n(std::cos(d.theta_rad), std::sin(d.theta_rad));
      const Eigen::Vector2d t(-n.y(), n.x());
      double lo = 1e300, hi = -1e300;
      for (int i : d.inliers) {
        const double u = t.dot(points.p_scanner_m[static_cast<size_t>(i)]);
        lo = std::min(lo, u);
        hi = std::max(hi, u);
      }
      const double ext = 0.1 * (hi - lo) + 0.3;
      const Eigen::Vector2d a = d.rho_m * n + (lo - ext) * t, b = d.rho_m * n + (hi + ext) * t;
      plot.Line(a.x(), a.y(), b.x(), b.y(), kRed, 1.6);
      const Eigen::Vector2d foot = d.rho_m * n;
      plot.Line(0, 0, foot.x(), foot.y(), kRed, 1, "4 3");
    }
    // The scanner: origin and its forward axis.
    const double axis_m = 25.0 / plot.PixelsPerUnitX();  // 25 px long whatever the scale
    plot.Line(0, 0, axis_m, 0, "#000", 2);
    plot.Dot(0, 0, 4, "#000");
    plot.Legend(kBlue, "dot", "inliers (" + N(d.num_inliers) + ")");
    plot.Legend(kOrange, "marker:cross", "possible mixed pixels (" + N(mixed) + ")");
    plot.Legend(kGrey, "dot", "other points: clutter, other surfaces (" + N(clutter) + ")");
    plot.Legend(kRed, "line", "detected wall line (\xcf\x81, \xce\xb8) and its normal");
    plot.Legend(kGreen, "line", "surveyed wall predicted from the mount");
    std::string caption = "Station " + N(station_number) + ", scan " + N(o.scan_index) +
                          " (log line " + N(panel.line) + "), grid heading " +
                          F("%.1f", GridHeadingDeg(o.pose.yaw_rad)) + "&#176;. ";
    if (d.found) {
      caption += "&#961; = " + F("%.3f", d.rho_m) + " m, &#952; = " + F("%.2f", d.theta_rad * kRadToDeg) +
                 "&#176;, line fit RMS " + F("%.1f", d.residual_rms_m * 1000) + " mm";
      if (residuals_ok_) {
        caption += ", residual against the adjusted wall " +
                   F("%.1f", r_.estimate.residual_rho_m[static_cast<size_t>(panel.observation)] * 1000) + " mm";
      }
      caption += ".";
    } else {
      caption += "Not detected again: " + Esc(d.reason) + ".";
    }
    if (outside > 0) caption += " " + N(outside) + " points lie outside the view.";
    return Figure(plot.Svg("Station " + N(station_number) + ": scan " + N(o.scan_index)), caption);
  }

  // ---- Hough ----
  std::string HoughSection() {
    std::ostringstream s;
    s << "<section id=\"hough\">\n<h2>Hough accumulator</h2>\n";
    if (!d_.hough.have) {
      s << "<p>No scan to show.</p>\n</section>\n";
      return s.str();
    }
    const pipeline::ScanPanel* panel = &panels_[static_cast<size_t>(d_.hough.panel)];
    const calib::WallObservation& o = r_.observations[panel->observation];
    const calib::LineGate& gate = d_.hough.window;
    const double angle_gate = gate.theta_halfwidth_rad;
    const double offset_gate = gate.rho_halfwidth_m;
    const calib::WallDetection& d = d_.hough.detection;
    const cv::Mat& acc = d.accumulator;
    if (acc.empty() || acc.type() != CV_32S) {
      s << "<p>The detector kept no accumulator for this scan.</p>\n</section>\n";
      return s.str();
    }
    int max_votes = 0, peak_row = 0, peak_col = 0;
    for (int k = 0; k < acc.rows; ++k) {
      for (int j = 0; j < acc.cols; ++j) {
        if (acc.at<int>(k, j) > max_votes) {
          max_votes = acc.at<int>(k, j);
          peak_row = k;
          peak_col = j;
        }
      }
    }
    const double t0 = d.acc_theta0_rad * kRadToDeg, ts = d.acc_theta_step_rad * kRadToDeg;
    const double r0 = d.acc_rho0_m, rs = d.acc_rho_step_m;
    SvgPlot plot(760, 440, &clip_counter_);
    plot.SetRange(t0 - 0.5 * ts, t0 + (acc.rows - 0.5) * ts, r0 - 0.5 * rs, r0 + (acc.cols - 0.5) * rs, false);
    plot.Axes("\xce\xb8, wall normal bearing in the scanner frame (deg)", "\xcf\x81, distance (m)");
    plot.Rect(t0 - 0.5 * ts, r0 - 0.5 * rs, t0 + (acc.rows - 0.5) * ts, r0 + (acc.cols - 0.5) * rs, "#1c0a2a");
    // Cells quantised to 24 levels; runs of equal level along ρ merged into one rectangle.
    constexpr int kLevels = 24;
    for (int k = 0; k < acc.rows; ++k) {
      int j = 0;
      while (j < acc.cols) {
        const int v = acc.at<int>(k, j);
        const int level = max_votes > 0 ? static_cast<int>(std::lround(kLevels * static_cast<double>(v) / max_votes)) : 0;
        int end = j + 1;
        while (end < acc.cols && max_votes > 0 &&
               static_cast<int>(std::lround(kLevels * static_cast<double>(acc.at<int>(k, end)) / max_votes)) == level) {
          ++end;
        }
        if (level > 0) {
          plot.Rect(t0 + (k - 0.5) * ts, r0 + (j - 0.5) * rs, t0 + (k + 0.5) * ts, r0 + (end - 0.5) * rs,
                    Ramp(static_cast<double>(level) / kLevels));
        }
        j = end;
      }
    }
    // The second pass's gate, the peak cell and the fitted line.
    const double tg = TightAngleGate() * kRadToDeg, og = TightOffsetGate();
    const double gt = gate.theta_rad * kRadToDeg;
    plot.Rect(gt - tg, gate.rho_m - og, gt + tg, gate.rho_m + og, "none", "#fff", "5 4");
    plot.Marker(t0 + peak_row * ts, r0 + peak_col * rs, "ring", 9, "#ff3030");
    if (d.found) plot.Marker(d.theta_rad * kRadToDeg, d.rho_m, "plus", 6, "#ffffff");
    plot.Legend("#ff3030", "marker:ring", "peak: most votes (" + N(max_votes) + ")");
    plot.Legend("#888", "marker:plus", "least-squares line (\xcf\x81, \xce\xb8) (white +)");
    plot.Legend("#888", "dash", "second-pass gate (white dashes)");
    s << Figure(plot.Svg("Hough accumulator, station " + N(panel->station + 1) + ", scan " + N(o.scan_index)),
                "Votes of the scan's points (Barawid 2007 Eq. 2, r = x cos &#952; + y sin &#952;) over a window "
                "of &#177;" + F("%.1f", angle_gate * kRadToDeg) + "&#176; and &#177;" + F("%.2f", offset_gate) +
                " m around the wall predicted from the mount; cells " + F("%.2f", ts) + "&#176; &#215; " +
                F("%.3f", rs) + " m, colour from few (dark) to most votes (yellow); possible mixed pixels do "
                "not vote." + (d.found ? "" : " The detector found no line in this window: " + Esc(d.reason) + "."));
    s << "</section>\n";
    return s.str();
  }

  // ---- residuals ----
  std::string ResidualsSection() {
    std::ostringstream s;
    s << "<section id=\"residuals\">\n<h2>Residuals</h2>\n";
    if (!residuals_ok_ || !have_mount_) {
      s << "<p>No residuals (no usable solve).</p>\n</section>\n";
      return s.str();
    }
    const analysis::ResidualAnalysis& ra = r_.residual_analysis;
    const std::vector<double>& res = r_.estimate.residual_rho_m;
    const size_t n = res.size();
    // Thin very long sessions so the page stays small (every k-th observation).
    const size_t stride = n > 4000 ? n / 4000 + 1 : 1;
    std::vector<ObservationAxes> axes;
    std::vector<double> res_mm;
    for (size_t i = 0; i < n; i += stride) {
      const calib::WallObservation& o = r_.observations[i];
      axes.push_back(AxesOf(o, r_.walls[o.wall_index], mount_));
      res_mm.push_back(res[i] * 1000.0);
    }
    double band_mm = 2.0 * r_.estimate.residual_rms_m * 1000.0;
    std::string band_name = "\xc2\xb1" "2 \xc3\x97 RMS";
    if (ra.done && ra.robust_sigma_m > 0) {
      band_mm = 2.0 * ra.robust_sigma_m * 1000.0;
      band_name = "\xc2\xb1" "2 robust \xcf\x83";
    }
    double lim = std::max(band_mm * 2.0, 1.0);
    std::vector<double> sorted = res_mm;
    for (double& v : sorted) v = std::fabs(v);
    std::sort(sorted.begin(), sorted.end());
    if (!sorted.empty()) lim = std::max(lim, 1.1 * sorted[static_cast<size_t>(0.995 * (sorted.size() - 1))]);
    s << "<p>Distance residual of each observation (observed &#8722; adjusted wall line, mm; "
      << N(static_cast<int64_t>(n)) << " observations"
      << (stride > 1 ? ", every " + N(static_cast<int64_t>(stride)) + "th shown" : std::string())
      << ") against what a systematic error would show up in (Hartzell, Glennie et al., Fig. 6). Each observation's "
         "range and incidence are those of its characteristic beam: the beam at the middle of its "
         "inliers' range span. Dashed: "
      << band_name << ".</p>\n<div class=\"flex\">\n";
    struct Axis {
      const char* title;
      const char* label;
      const char* key;
      double ObservationAxes::*field;
    };
    const Axis panels[] = {
        {"Residual vs heading", "grid heading of the vehicle (deg, \xe2\x88\x92" "180..180)", "heading",
         &ObservationAxes::heading_deg},
        {"Residual vs range", "range of the characteristic beam (m)", "range", &ObservationAxes::range_m},
        {"Residual vs incidence angle", "incidence angle on the wall (deg)", "incidence",
         &ObservationAxes::incidence_deg},
        {"Residual vs beam bearing", "beam bearing in the scanner frame (deg, ccw from forward)", "bearing",
         &ObservationAxes::bearing_deg},
    };
    for (const Axis& axis : panels) {
      Box box;
      for (const ObservationAxes& a : axes) box.Add(a.*(axis.field), 0.0);
      box.Pad(0.05, 0.5);
      SvgPlot plot(590, 300, &clip_counter_);
      plot.SetRange(box.x0, box.x1, -lim, lim, false);
      plot.Axes(axis.label, "residual (mm)");
      plot.Line(box.x0, 0, box.x1, 0, "#666", 1);
      plot.Line(box.x0, band_mm, box.x1, band_mm, kOrange, 1, "5 3");
      plot.Line(box.x0, -band_mm, box.x1, -band_mm, kOrange, 1, "5 3");
      for (size_t i = 0; i < axes.size(); ++i) {
        const double y = std::clamp(res_mm[i], -lim, lim);
        plot.Dot(axes[i].*(axis.field), y, 1.8, std::fabs(res_mm[i]) > band_mm ? kRed : kBlue);
      }
      std::string caption;
      if (ra.done) {
        for (const analysis::ResidualTrend& t : ra.trends) {
          if (t.against != axis.key) continue;
          caption = std::string(t.flagged ? "<span class=\"bad\">TREND FLAGGED</span>: " : "no significant trend: ") +
                    "slope " + F("%.3g", t.slope) + " " + Esc(t.unit) + ", " + F("%.1f", t.significance) +
                    " &#963;" + (t.message.empty() ? "" : "; " + Esc(t.message)) + ".";
        }
        if (caption.empty()) caption = "The residual analysis has no trend for this quantity.";
      } else {
        caption = "Residual analysis not run: no trend test.";
      }
      s << Figure(plot.Svg(axis.title), caption);
    }
    s << "</div>\n";
    if (ra.done) {
      s << "<h3>Residual analysis</h3>\n<table>\n";
      s << Row("robust \xcf\x83 (1.4826 MAD)", F("%.2f", ra.robust_sigma_m * 1000) + " mm");
      s << Row("beyond 2 robust \xcf\x83", F("%.1f", ra.outlier_share * 100) + " %");
      if (ra.range_model_estimated) {
        s << Row("range model re-estimated", "k = " + F("%.5f", ra.range_scale_k) + " &#177; " +
                                                 F("%.5f", ra.sigma_range_scale_k) + ", b = " +
                                                 F("%.4f", ra.range_offset_b_m) + " &#177; " +
                                                 F("%.4f", ra.sigma_range_offset_b_m) + " m");
      }
      s << "</table>\n<table>\n<tr><th>against</th><th>slope</th><th>significance</th><th>flag</th>"
           "<th>meaning</th></tr>\n";
      for (const analysis::ResidualTrend& t : ra.trends) {
        s << "<tr><th>" << Esc(t.against) << "</th><td class=\"num\">" << F("%.3g", t.slope) << " "
          << Esc(t.unit) << "</td><td class=\"num\">" << F("%.1f", t.significance) << " &#963;</td><td>"
          << (t.flagged ? "<span class=\"bad\">flagged</span>" : "<span class=\"ok\">ok</span>")
          << "</td><td>" << Esc(t.message) << "</td></tr>\n";
      }
      s << "</table>\n";
      if (!ra.flags.empty()) {
        s << "<ul>\n";
        for (const std::string& f : ra.flags) s << "<li class=\"warn\">" << Esc(f) << "</li>\n";
        s << "</ul>\n";
      }
    }
    s << "</section>\n";
    return s.str();
  }

  // ---- coverage ----
  std::string CoverageSection() {
    std::ostringstream s;
    s << "<section id=\"coverage\">\n<h2>Heading coverage</h2>\n";
    constexpr int kBins = 36;
    std::vector<int64_t> bins(kBins, 0);
    for (const calib::WallObservation& o : r_.observations) {
      double h = std::fmod(GridHeadingDeg(o.pose.yaw_rad) + 360.0, 360.0);
      bins[static_cast<size_t>(std::min(kBins - 1, static_cast<int>(h / (360.0 / kBins))))]++;
    }
    const int64_t max_count = *std::max_element(bins.begin(), bins.end());
    // Compass plot: north up, clockwise, as headings are given.
    const double size = 440, cx = 220, cy = 225, radius = 170;
    auto at = [&](double heading_deg, double r) {
      const double a = heading_deg * kDegToRad;
      return std::make_pair(cx + r * std::sin(a), cy - r * std::cos(a));
    };
    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << size << "\" height=\"" << size + 10
      << "\" viewBox=\"0 0 " << size << " " << size + 10 << "\" class=\"plot\">"
      << "<title>Heading coverage</title><rect x=\"0\" y=\"0\" width=\"" << size << "\" height=\""
      << size + 10 << "\" fill=\"#fff\"/>"
      << "<text x=\"10\" y=\"17\" class=\"ptitle\">Grid headings of the observations</text>";
    for (int ring = 1; ring <= 4; ++ring) {
      o << "<circle cx=\"" << cx << "\" cy=\"" << cy << "\" r=\"" << radius * ring / 4.0
        << "\" fill=\"none\" stroke=\"#ddd\"/>";
    }
    for (int deg = 0; deg < 360; deg += 30) {
      const auto [x1, y1] = at(deg, radius);
      const auto [xl, yl] = at(deg, radius + 16);
      o << "<line x1=\"" << cx << "\" y1=\"" << cy << "\" x2=\"" << SvgPlot::P(x1) << "\" y2=\""
        << SvgPlot::P(y1) << "\" stroke=\"#e4e4e4\"/>";
      const std::string label = deg == 0 ? "N" : deg == 90 ? "E" : deg == 180 ? "S" : deg == 270 ? "W"
                                                                                            : std::to_string(deg) + "\xc2\xb0";
      o << "<text x=\"" << SvgPlot::P(xl) << "\" y=\"" << SvgPlot::P(yl + 4)
        << "\" text-anchor=\"middle\" class=\"label\">" << label << "</text>";
    }
    for (int b = 0; b < kBins; ++b) {
      if (bins[static_cast<size_t>(b)] == 0 || max_count == 0) continue;
      const double r = radius * static_cast<double>(bins[static_cast<size_t>(b)]) / static_cast<double>(max_count);
      const double h0 = b * 360.0 / kBins, h1 = (b + 1) * 360.0 / kBins;
      const auto [xa, ya] = at(h0, r);
      const auto [xb, yb] = at(h1, r);
      o << "<path d=\"M" << cx << "," << cy << "L" << SvgPlot::P(xa) << "," << SvgPlot::P(ya) << "A"
        << SvgPlot::P(r) << "," << SvgPlot::P(r) << " 0 0 1 " << SvgPlot::P(xb) << "," << SvgPlot::P(yb)
        << "Z\" fill=\"" << kBlue << "\" fill-opacity=\"0.75\" stroke=\"#fff\" stroke-width=\"0.5\"/>";
    }
    // Facing each wall square-on: the heading of the wall normal pointing away from the vehicle.
    Eigen::Vector2d mean_antenna = Eigen::Vector2d::Zero();
    for (const Station& st : stations_) mean_antenna += st.antenna_local_m;
    if (!stations_.empty()) mean_antenna /= static_cast<double>(stations_.size());
    for (const calib::WallGeometry& w : r_.walls) {
      const double side = (w.offset_m - w.normal_local.dot(mean_antenna)) >= 0 ? 1.0 : -1.0;
      const Eigen::Vector2d v = side * w.normal_local;
      const double heading = std::atan2(v.x(), v.y()) * kRadToDeg;
      const auto [xw, yw] = at(heading, radius + 4);
      o << "<line x1=\"" << cx << "\" y1=\"" << cy << "\" x2=\"" << SvgPlot::P(xw) << "\" y2=\""
        << SvgPlot::P(yw) << "\" stroke=\"" << kRed << "\" stroke-width=\"1.5\" stroke-dasharray=\"5 3\"/>";
    }
    o << "<text x=\"10\" y=\"" << size + 4 << "\" class=\"legend\">blue: observations per 10\xc2\xb0 (outer ring "
      << max_count << "); red dashes: facing the wall square-on</text>";
    o << "</svg>";
    s << "<div class=\"flex\">\n"
      << Figure(o.str(), "Grid heading (clockwise from grid north) of the vehicle for every wall observation "
                         "used. The mount's yaw and its lever arm separate only when the wall is seen from "
                         "several headings (docs/field-guide.md).");
    s << "<table>\n" << Row("grid headings used", F("%.1f", r_.heading_min_deg) + "&#176; .. " + F("%.1f", r_.heading_max_deg) + "&#176;")
      << Row("vehicle-to-wall angles", F("%.1f", r_.wall_angle_min_deg) + "&#176; .. " + F("%.1f", r_.wall_angle_max_deg) + "&#176;")
      << Row("stations", N(r_.num_dwells) + " found, " + N(static_cast<int64_t>(stations_.size())) + " with observations")
      << Row("GNSS-error slices used", N(r_.num_segments_used)) << "</table>\n</div>\n</section>\n";
    return s.str();
  }

  // ---- counts ----
  std::string CountsSection() {
    std::ostringstream s;
    s << "<section id=\"counts\">\n<h2>Counts</h2>\n<div class=\"flex\">\n";
    s << "<table>\n<tr><th colspan=\"2\">Scans</th></tr>\n";
    s << Row("read (valid records + malformed scan lines)", N(r_.scans_total));
    s << Row("used (at least one wall observation)", N(r_.scans_used));
    for (const auto& [reason, count] : r_.scans_skipped) {
      s << Row(std::string("not used: ") + calib::ScanSkipName(reason), N(count));
    }
    s << Row("wall observations", N(static_cast<int64_t>(r_.observations.size())));
    if (r_.estimate.usable) s << Row("down-weighted as outliers", N(r_.estimate.observations_rejected));
    for (const auto& [reason, count] : r_.scan_lines_skipped.by_reason) {
      s << Row("log line skipped: " + reason, N(count));
    }
    s << "</table>\n";
    s << "<table>\n<tr><th colspan=\"2\">GNSS and heading</th></tr>\n";
    for (const auto& [q, count] : r_.fixes_by_quality) {
      s << Row("GGA quality " + N(q) + " (" + io::FixQualityName(q) + ")", N(count));
    }
    s << Row("fixes used (quality \xe2\x89\xa5 " + N(r_.session.min_fix_quality) + ", in time order)", N(r_.fixes_used));
    for (const auto& [reason, count] : r_.gnss_skipped.by_reason) s << Row("GNSS line skipped: " + reason, N(count));
    s << Row("headings used", N(r_.headings_used));
    if (r_.session.heading_log != r_.session.gnss_log) {
      for (const auto& [reason, count] : r_.heading_skipped.by_reason) {
        s << Row("heading line skipped: " + reason, N(count));
      }
    }
    s << "</table>\n";
    s << "<table>\n<tr><th colspan=\"2\">Time alignment</th></tr>\n";
    s << Row("scanner clock offset applied (session)", F("%.4f", r_.session.scanner_time_offset_s) + " s");
    if (r_.time_offset_sigma_s > 0) {
      s << Row("scanner clock offset estimated", F("%.4f", r_.time_offset_s) + " &#177; " +
                                                     F("%.4f", r_.time_offset_sigma_s) + " s");
    } else {
      s << Row("scanner clock offset estimated", "no (needs scans taken while moving)");
    }
    if (d_.gnss_fixes > 0) {
      s << Row("GNSS log span", F("%.1f", d_.gnss_last_s - d_.gnss_first_s) + " s (" + N(d_.gnss_fixes) + " GGA fixes)");
    }
    if (!r_.observations.empty()) {
      double t0 = 1e300, t1 = -1e300;
      for (const calib::WallObservation& o : r_.observations) {
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

  const CalibrationResult& r_;
  const pipeline::ReportData& d_;
  const solvers::Mount& mount_;
  const std::string& mount_source_;
  bool have_mount_ = false;
  const std::vector<pipeline::Station>& stations_;
  const std::vector<pipeline::ScanPanel>& panels_;
  bool residuals_ok_ = false;
  int clip_counter_ = 0;
};

}  // namespace

std::string FormatReportHtml(const CalibrationResult& result) {
  ReportBuilder builder(result);
  return builder.Build();
}

std::string WriteReport(const CalibrationResult& result, const std::string& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir)) {
    throw io::InputError(dir + ": cannot create the report folder" +
                         (error ? " (" + error.message() + ")" : std::string()));
  }
  const std::string path = (fs::path(dir) / "report.html").string();
  io::WriteFileAtomically(path, FormatReportHtml(result));
  return path;
}

}  // namespace wallcal::outputs
