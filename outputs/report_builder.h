// SPDX-License-Identifier: Apache-2.0
#pragma once
// The report page's builder and its drawing helpers, shared by outputs/report.cc (the page, the
// mount, the site map and the counts) and outputs/report_panels.cc (scans, Hough accumulator,
// residuals, heading coverage). Internal to outputs/.

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
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

#include "calib/geodesy.h"
#include "calib/range_model.h"
#include "calib/wall_detector.h"
#include "common/angles.h"
#include "io/output_file.h"
#include "io/version.h"
#include "outputs/report.h"
#include "outputs/report_decision.h"
#include "outputs/svg_plot.h"

namespace wallcal::outputs::report_detail {

using outputs::PageOutcome;
using pipeline::CalibrationResult;
using pipeline::Station;

// ---- Text ------------------------------------------------------------------------------------

inline std::string F(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

inline std::string N(int64_t value) { return std::to_string(value); }

inline double SigmaOf(const Eigen::Matrix3d& covariance, int i) {
  return std::sqrt(std::max(0.0, covariance(i, i)));
}

using calib::GridHeadingDeg;  // (−180°, 180°], clockwise from grid north

inline constexpr const char* kBlue = "#1f5fbf";
inline constexpr const char* kRed = "#d62728";
inline constexpr const char* kOrange = "#ff7f0e";
inline constexpr const char* kGreen = "#2ca02c";
inline constexpr const char* kGrey = "#9a9a9a";
inline constexpr const char* kDark = "#333333";
inline constexpr const char* kPurple = "#7b3fb0";

// ---- Per-observation plot axes ------------------------------------------------------------

inline Eigen::Vector2d ScannerLocal(const calib::VehiclePose& pose, const solvers::Mount& mount) {
  return pose.antenna_local_m + Eigen::Rotation2Dd(pose.yaw_rad) * Eigen::Vector2d(mount.x_m, mount.y_m);
}

// The quantities residuals are plotted against, per observation. The "characteristic beam" of
// an observation is the beam at the middle of its inliers' range span, r_mid: its incidence on
// the wall is acos(ρ / r_mid) and it lies on the side of the wall's foot where the surveyed
// wall's centre is (seen from the scanner with the final mount).
struct ObservationAxes {
  double heading_deg = 0, range_m = 0, incidence_deg = 0, bearing_deg = 0;
};

inline ObservationAxes AxesOf(const calib::WallObservation& o, const calib::WallGeometry& wall,
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

inline std::string Row(const std::string& key, const std::string& value) {
  return "<tr><th>" + Esc(key) + "</th><td>" + value + "</td></tr>\n";
}

inline std::string Figure(const std::string& svg, const std::string& caption) {
  return "<figure>" + svg + "<figcaption>" + caption + "</figcaption></figure>\n";
}

// Colour ramp for the accumulator (dark blue -> teal -> yellow), t in [0, 1].
inline std::string Ramp(double t) {
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

// The pages' style sheet (the one-scanner report and the page of several scanners).
inline constexpr const char* kReportStyle =
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

class ReportBuilder {
 public:
  explicit ReportBuilder(const PageOutcome& outcome)
      : outcome_(outcome),
        r_(*outcome.run),
        d_(*outcome.report),
        mount_(d_.mount),
        mount_source_(d_.mount_source),
        have_mount_(d_.have_mount),
        stations_(d_.stations),
        panels_(d_.panels) {
    const solvers::MountEstimate& e = r_.solve.estimate;
    residuals_ok_ =
        e.residual_rho_m.size() == r_.solve.observations.size() && !r_.solve.observations.empty();
  }

  std::string Build();

 private:
  static constexpr const char* kStyle = kReportStyle;

  // ---- mount ----
  std::string ScannerTitle() const;  // ", scanner ID" for one scanner of several, else ""
  std::string MountSection();

  std::string EllipsePlot();

  std::optional<solvers::Mount> Truth() const { return d_.truth; }

  std::string RepeatabilityTable() const;

  // ---- site map ----
  std::string SiteMapSection();

  // ---- scans ----
  double TightAngleGate() const { return d_.tight_gates.angle_rad; }
  double TightOffsetGate() const { return d_.tight_gates.offset_m; }

  std::string ScansSection();

  std::string ScanPlot(const pipeline::ScanPanel& panel);

  // ---- Hough ----
  std::string HoughSection();

  // ---- residuals ----
  std::string ResidualsSection();

  // ---- coverage ----
  std::string CoverageSection();

  // ---- counts ----
  std::string CountsSection();

  const PageOutcome& outcome_;
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

}  // namespace wallcal::outputs::report_detail
