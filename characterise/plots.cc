// SPDX-License-Identifier: Apache-2.0
// The --report plots: range error against true range, incidence and time, as in Ye &
// Borenstein 2002 (Fig. 5-7) and Okubo, Ye & Borenstein 2009 (error against distance and
// incidence, drift against time).

#include <algorithm>
#include <cmath>
#include <functional>

#include "characterise/characterisation.h"
#include "common/angles.h"
#include "outputs/svg_plot.h"

namespace wallcal::characterise {
namespace {

std::string Plot(const Characterisation& r, const std::string& title, const std::string& x_label,
                 const std::function<double(const PlotPoint&)>& x_of,
                 const std::function<double(double)>& model_mm, int* clips) {
  outputs::SvgPlot plot(640, 360, clips);
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const PlotPoint& p : r.plot) {
    x0 = std::min(x0, x_of(p));
    x1 = std::max(x1, x_of(p));
    y0 = std::min(y0, 1e3 * p.error_m);
    y1 = std::max(y1, 1e3 * p.error_m);
  }
  if (r.plot.empty()) x0 = y0 = 0, x1 = y1 = 1;
  plot.SetRange(x0, x1, y0, y1, false);
  plot.Axes(x_label, "range error z - true (mm)");
  for (const PlotPoint& p : r.plot) plot.Dot(x_of(p), 1e3 * p.error_m, 1.2, "#4a78b0");
  if (model_mm) {
    std::vector<Eigen::Vector2d> line;
    for (int i = 0; i <= 50; ++i) {
      const double x = x0 + (x1 - x0) * i / 50.0;
      line.emplace_back(x, model_mm(x));
    }
    plot.Polyline(line, "#c03030", 2.0);
    plot.Legend("#c03030", outputs::Swatch::kLine, "fitted model");
  }
  plot.Legend("#4a78b0", outputs::Swatch::kDot, "wall returns (a subsample)");
  return plot.Svg(title);
}

}  // namespace

std::vector<std::pair<std::string, std::string>> Plots(const Characterisation& r) {
  int clips = 0;
  const RangeModel& m = r.model;
  std::vector<std::pair<std::string, std::string>> files;
  files.emplace_back(
      "range_error_vs_range.svg",
      Plot(r, "Range error against true range", "true range (m)",
           [](const PlotPoint& p) { return p.true_range_m; },
           [&m](double t) { return 1e3 * ((m.n.value - 1.0) * t + m.c_m.value); }, &clips));
  files.emplace_back("range_error_vs_incidence.svg",
                     Plot(r, "Range error against incidence", "incidence (deg)",
                          [](const PlotPoint& p) { return p.incidence_rad * kRadToDeg; }, nullptr,
                          &clips));
  files.emplace_back("range_error_vs_time.svg",
                     Plot(r, "Range error against time", "time since the first scan (s)",
                          [](const PlotPoint& p) { return static_cast<double>(p.time_s); },
                          nullptr, &clips));
  return files;
}

}  // namespace wallcal::characterise
