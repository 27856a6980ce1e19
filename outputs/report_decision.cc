// SPDX-License-Identifier: Apache-2.0
#include "outputs/report_decision.h"

#include <cmath>
#include <sstream>

#include "common/angles.h"
#include "common/format.h"
#include "outputs/svg_plot.h"

namespace wallcal::outputs {
namespace {

double SigmaOf(double variance) { return variance > 0.0 ? std::sqrt(variance) : 0.0; }

std::string Cell(const std::string& text) { return "<td class=\"num\">" + text + "</td>"; }

}  // namespace

std::string DecisionSectionHtml(const pipeline::CalibrationResult& r) {
  const solvers::MountEstimate& e = r.estimate;
  std::ostringstream s;
  const pipeline::Verdict v = r.decision.verdict;
  const char* css = v == pipeline::Verdict::kAccept   ? "v-accept"
                    : v == pipeline::Verdict::kReview ? "v-review"
                                                      : "v-reject";
  s << "<section id=\"decision\">\n<h2>Verdict</h2>\n";
  s << "<p><span class=\"verdict " << css << "\">" << pipeline::VerdictName(v) << "</span></p>\n";
  const pipeline::AcceptanceOptions& a = r.options.acceptance;
  if (r.decision.reasons.empty()) {
    s << "<p class=\"ok\">Within the acceptance tolerances: &#963; x, y &#8804; "
      << Format("%.1f", a.max_sigma_xy_m * 1e3) << " mm, &#963; yaw &#8804; "
      << Format("%.2f", a.max_sigma_yaw_rad * kRadToDeg) << "&#176;"
      << (r.change ? ", change &#8804; " + Format("%.1f", a.max_change_xy_m * 1e3) + " mm / " +
                         Format("%.2f", a.max_change_yaw_rad * kRadToDeg) + "&#176;"
                   : std::string())
      << ".</p>\n";
  } else {
    s << "<ul>\n";
    for (const std::string& reason : r.decision.reasons) s << "<li>" << Esc(reason) << "</li>\n";
    s << "</ul>\n";
  }
  s << "<div class=\"flex\">\n";
  // The numbers: estimate, σ, change, truth error.
  if (e.usable) {
    s << "<table class=\"big\">\n<tr><th></th><th>estimate</th><th>1&#963;</th>";
    if (r.change) s << "<th>change since previous</th>";
    if (r.report.truth) s << "<th>error (estimate &#8722; truth)</th>";
    s << "</tr>\n";
    const double values[3] = {e.mount.x_m, e.mount.y_m, e.mount.yaw_rad};
    const char* names[3] = {"x (forward)", "y (left)", "yaw (ccw)"};
    for (int k = 0; k < 3; ++k) {
      const bool yaw = k == 2;
      auto text = [yaw](double value, const char* format_mm, const char* format_deg) {
        return yaw ? Format(format_deg, value * kRadToDeg) + "&#176;"
                   : Format(format_mm, value * 1e3) + " mm";
      };
      s << "<tr><th>" << names[k] << "</th>"
        << Cell(yaw ? Format("%.3f", values[k] * kRadToDeg) + "&#176;"
                    : Format("%.4f", values[k]) + " m")
        << Cell(r.sigma_known ? text(SigmaOf(e.covariance(k, k)), "%.1f", "%.3f") : "none");
      if (r.change) {
        const pipeline::Change& c = *r.change;
        const double d[3] = {c.dx_m, c.dy_m, c.dyaw_rad};
        const double u[3] = {c.x_sigmas, c.y_sigmas, c.yaw_sigmas};
        s << Cell(text(d[k], "%+.1f", "%+.3f") +
                  (std::isfinite(u[k]) ? " (" + Format("%.1f", u[k]) + "&#963;)" : std::string()));
      }
      if (r.report.truth) {
        const calib::Mount& t = *r.report.truth;
        const double err[3] = {e.mount.x_m - t.x_m, e.mount.y_m - t.y_m,
                               WrapAngle(e.mount.yaw_rad - t.yaw_rad)};
        const double sigma = SigmaOf(e.covariance(k, k));
        s << Cell(text(err[k], "%+.1f", "%+.3f") +
                  (r.sigma_known && sigma > 0.0
                       ? " (" + Format("%.1f", std::abs(err[k]) / sigma) + "&#963;)"
                       : std::string()));
      }
      s << "</tr>\n";
    }
    s << "</table>\n";
  }
  // The error budget: σ from each source, per axis.
  const analysis::ErrorBudget& b = r.budget;
  if (b.done) {
    s << "<div><h3>Error budget: what the &#963; is made of</h3>\n<table>\n"
         "<tr><th>source</th><th>x (mm)</th><th>y (mm)</th><th>yaw (&#176;)</th></tr>\n";
    auto row = [&s, &b](const std::string& name, const Eigen::Vector3d& variance) {
      s << "<tr><th>" << name << "</th>";
      for (int k = 0; k < 3; ++k) {
        const double sigma = std::sqrt(std::max(0.0, variance[k]));
        const double share = b.total_variance[k] > 0.0 ? variance[k] / b.total_variance[k] : 0.0;
        const std::string value =
            k == 2 ? Format("%.3f", sigma * kRadToDeg) : Format("%.1f", sigma * 1e3);
        s << "<td class=\"num\">" << (share >= 0.5 ? "<b>" + value + "</b>" : value) << " ("
          << Format("%.0f", 100.0 * share) << " %)</td>";
      }
      s << "</tr>\n";
    };
    for (int k = 0; k < analysis::kNumErrorSources; ++k) {
      row(analysis::ErrorSourceName(static_cast<analysis::ErrorSource>(k)), b.variance[k]);
    }
    row("all (linearised)", b.total_variance);
    s << "</table>\n<p class=\"meta\">Each source's &#963;: the variance that goes away when "
         "that source is made exact (docs/method.md, \"Error budget\"); the percentages are "
         "shares of the variance and need not add to 100 %.</p></div>\n";
  }
  s << "</div>\n";
  if (r.change) {
    s << "<p>Previous calibration: " << Esc(r.change->previous_file)
      << (r.change->previous_created_utc.empty() ? std::string()
                                                 : " (" + Esc(r.change->previous_created_utc) + ")")
      << ".</p>\n";
  }
  s << "</section>\n";
  return s.str();
}

}  // namespace wallcal::outputs
