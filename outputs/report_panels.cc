// SPDX-License-Identifier: Apache-2.0
// The report's data panels (outputs/report_builder.h): scans in the scanner frame, the Hough
// accumulator, residuals and heading coverage.

#include "outputs/report_builder.h"

namespace wallcal::outputs::report_detail {

std::string ReportBuilder::ScansSection() {
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

std::string ReportBuilder::ScanPlot(const pipeline::ScanPanel& panel) {
  const calib::WallObservation& o = r_.solve.observations[panel.observation];
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
      plot.Marker(p.x(), p.y(), Shape::kCross, 3, kOrange);
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
  plot.Legend(kBlue, Swatch::kDot, "inliers (" + N(d.num_inliers) + ")");
  plot.Legend(kOrange, Swatch::kCross, "possible mixed pixels (" + N(mixed) + ")");
  plot.Legend(kGrey, Swatch::kDot, "other points: clutter, other surfaces (" + N(clutter) + ")");
  plot.Legend(kRed, Swatch::kLine, "detected wall line (\xcf\x81, \xce\xb8) and its normal");
  plot.Legend(kGreen, Swatch::kLine, "surveyed wall predicted from the mount");
  std::string caption = "Station " + N(station_number) + ", scan " + N(o.scan_index) +
                        " (log line " + N(panel.line) + "), grid heading " +
                        F("%.1f", GridHeadingDeg(o.pose.yaw_rad)) + "&#176;. ";
  if (d.found) {
    caption += "&#961; = " + F("%.3f", d.rho_m) + " m, &#952; = " + F("%.2f", d.theta_rad * kRadToDeg) +
               "&#176;, line fit RMS " + F("%.1f", d.residual_rms_m * 1000) + " mm";
    if (residuals_ok_) {
      caption +=
          ", residual against the adjusted wall " +
          F("%.1f",
            r_.solve.estimate.residual_rho_m[static_cast<size_t>(panel.observation)] * 1000) +
          " mm";
    }
    caption += ".";
  } else {
    caption += "Not detected again: " + Esc(d.reason) + ".";
  }
  if (outside > 0) caption += " " + N(outside) + " points lie outside the view.";
  return Figure(plot.Svg("Station " + N(station_number) + ": scan " + N(o.scan_index)), caption);
}

std::string ReportBuilder::HoughSection() {
  std::ostringstream s;
  s << "<section id=\"hough\">\n<h2>Hough accumulator</h2>\n";
  if (!d_.hough.have) {
    s << "<p>No scan to show.</p>\n</section>\n";
    return s.str();
  }
  const pipeline::ScanPanel* panel = &panels_[static_cast<size_t>(d_.hough.panel)];
  const calib::WallObservation& o = r_.solve.observations[panel->observation];
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
  plot.Marker(t0 + peak_row * ts, r0 + peak_col * rs, Shape::kRing, 9, "#ff3030");
  if (d.found) plot.Marker(d.theta_rad * kRadToDeg, d.rho_m, Shape::kPlus, 6, "#ffffff");
  plot.Legend("#ff3030", Swatch::kRing, "peak: most votes (" + N(max_votes) + ")");
  plot.Legend("#888", Swatch::kPlus, "least-squares line (\xcf\x81, \xce\xb8) (white +)");
  plot.Legend("#888", Swatch::kDash, "second-pass gate (white dashes)");
  s << Figure(plot.Svg("Hough accumulator, station " + N(panel->station + 1) + ", scan " + N(o.scan_index)),
              "Votes of the scan's points (Barawid 2007 Eq. 2, r = x cos &#952; + y sin &#952;) over a window "
              "of &#177;" + F("%.1f", angle_gate * kRadToDeg) + "&#176; and &#177;" + F("%.2f", offset_gate) +
              " m around the wall predicted from the mount; cells " + F("%.2f", ts) + "&#176; &#215; " +
              F("%.3f", rs) + " m, colour from few (dark) to most votes (yellow); possible mixed pixels do "
              "not vote." + (d.found ? "" : " The detector found no line in this window: " + Esc(d.reason) + "."));
  s << "</section>\n";
  return s.str();
}

std::string ReportBuilder::ResidualsSection() {
  std::ostringstream s;
  s << "<section id=\"residuals\">\n<h2>Residuals</h2>\n";
  if (!residuals_ok_ || !have_mount_) {
    s << "<p>No residuals (no usable solve).</p>\n</section>\n";
    return s.str();
  }
  const analysis::ResidualAnalysis& ra = r_.finish.residual_analysis;
  const std::vector<double>& res = r_.solve.estimate.residual_rho_m;
  const size_t n = res.size();
  std::vector<ObservationAxes> axes;
  std::vector<double> res_mm;
  axes.reserve(n);
  res_mm.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const calib::WallObservation& o = r_.solve.observations[i];
    axes.push_back(AxesOf(o, r_.survey.walls[o.wall_index], mount_));
    res_mm.push_back(res[i] * 1000.0);
  }
  double band_mm = 2.0 * r_.solve.estimate.residual_rms_m * 1000.0;
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
    << N(static_cast<int64_t>(n)) << " observations: every one beyond the band in red (those at the "
       "same pixel drawn once); of those inside it, one dot per dot-sized cell of the plot, so that the page stays small whatever "
       "the session's length) against what a systematic error would show up in (Hartzell, Glennie et al., Fig. 6). Each observation's "
       "range and incidence are those of its characteristic beam: the beam at the middle of its "
       "inliers' range span. Dashed: "
    << band_name << ".</p>\n<div class=\"flex\">\n";
  struct Axis {
    const char* title;
    const char* label;
    analysis::TrendAxis key;
    double ObservationAxes::*field;
  };
  const Axis panels[] = {
      {"Residual vs heading", "grid heading of the vehicle (deg, \xe2\x88\x92" "180..180)", analysis::TrendAxis::kHeading,
       &ObservationAxes::heading_deg},
      {"Residual vs range", "range of the characteristic beam (m)", analysis::TrendAxis::kRange, &ObservationAxes::range_m},
      {"Residual vs incidence angle", "incidence angle on the wall (deg)", analysis::TrendAxis::kIncidence,
       &ObservationAxes::incidence_deg},
      {"Residual vs beam bearing", "beam bearing in the scanner frame (deg, ccw from forward)", analysis::TrendAxis::kBearing,
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
    // Inliers thinned to one dot per cell (svg_plot.h DotCloud), drawn first; every outlier
    // drawn on top of them.
    std::vector<Eigen::Vector2d> inliers, outliers;
    for (size_t i = 0; i < axes.size(); ++i) {
      const Eigen::Vector2d p(axes[i].*(axis.field), std::clamp(res_mm[i], -lim, lim));
      (std::fabs(res_mm[i]) > band_mm ? outliers : inliers).push_back(p);
    }
    constexpr double kDotRadiusPx = 1.8;
    plot.DotCloud(inliers, kDotRadiusPx, kBlue, 2.0 * kDotRadiusPx);
    plot.DotCloud(outliers, kDotRadiusPx, kRed, 1.0);
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
      s << "<tr><th>" << Esc(analysis::TrendAxisName(t.against)) << "</th><td class=\"num\">" << F("%.3g", t.slope) << " "
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

std::string ReportBuilder::CoverageSection() {
  std::ostringstream s;
  s << "<section id=\"coverage\">\n<h2>Heading coverage</h2>\n";
  constexpr int kBins = 36;
  std::vector<int64_t> bins(kBins, 0);
  for (const calib::WallObservation& o : r_.solve.observations) {
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
  for (const calib::WallGeometry& w : r_.survey.walls) {
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
  s << "<table>\n"
    << Row("grid headings used", F("%.1f", r_.finish.coverage.heading_min_deg) + "&#176; .. " +
                                     F("%.1f", r_.finish.coverage.heading_max_deg) + "&#176;")
    << Row("vehicle-to-wall angles",
           F("%.1f", r_.finish.coverage.wall_angle_min_deg) + "&#176; .. " +
               F("%.1f", r_.finish.coverage.wall_angle_max_deg) + "&#176;")
    << Row("stations", N(r_.poses.num_dwells) + " found, " +
                           N(static_cast<int64_t>(stations_.size())) + " with observations")
    << Row("GNSS-error slices used", N(r_.finish.coverage.num_segments_used))
    << "</table>\n</div>\n</section>\n";
  return s.str();
}

}  // namespace wallcal::outputs::report_detail
