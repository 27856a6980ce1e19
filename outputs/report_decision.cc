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

PageOutcome OwnOutcome(const pipeline::CalibrationResult& run) {
  PageOutcome outcome;
  outcome.run = &run;
  outcome.mount = run.solve.estimate.mount;
  outcome.covariance = run.solve.estimate.covariance;
  outcome.clock_offset_s = run.solve.scanner_offset.value_s;
  outcome.decision = &run.decided.decision;
  outcome.change = &run.decided.change;
  outcome.report = &run.report;
  return outcome;
}

PageOutcome JointOutcome(const pipeline::CalibrationResult& own,
                         const pipeline::JointScannerResult& joint) {
  PageOutcome outcome;
  outcome.run = &own;
  outcome.joint = true;
  outcome.mount = joint.mount;
  outcome.covariance = joint.covariance;
  outcome.clock_offset_s = joint.time_offset_s;
  outcome.decision = &joint.decision;
  outcome.change = &joint.change;
  outcome.report = &joint.report;
  return outcome;
}

std::string DecisionSectionHtml(const PageOutcome& outcome) {
  const pipeline::CalibrationResult& r = *outcome.run;
  const solvers::MountEstimate& e = r.solve.estimate;
  const pipeline::Decision& decision = *outcome.decision;
  const std::optional<pipeline::Change>& change = *outcome.change;
  const std::optional<calib::Mount>& truth = outcome.report->truth;
  std::ostringstream s;
  const pipeline::Verdict v = decision.verdict;
  const char* css = v == pipeline::Verdict::kAccept   ? "v-accept"
                    : v == pipeline::Verdict::kReview ? "v-review"
                                                      : "v-reject";
  s << "<section id=\"decision\">\n<h2>Verdict</h2>\n";
  s << "<p><span class=\"verdict " << css << "\">" << pipeline::VerdictName(v) << "</span></p>\n";
  const pipeline::AcceptanceOptions& a = r.loaded.options.acceptance;
  if (decision.reasons.empty()) {
    s << "<p class=\"ok\">Within the acceptance tolerances: &#963; x, y &#8804; "
      << Format("%.1f", a.max_sigma_xy_m * 1e3) << " mm, &#963; yaw &#8804; "
      << Format("%.2f", a.max_sigma_yaw_rad * kRadToDeg) << "&#176;"
      << (change ? ", change &#8804; " + Format("%.1f", a.max_change_xy_m * 1e3) + " mm / " +
                       Format("%.2f", a.max_change_yaw_rad * kRadToDeg) + "&#176;"
                 : std::string())
      << ".</p>\n";
  } else {
    s << "<ul>\n";
    for (const std::string& reason : decision.reasons) s << "<li>" << Esc(reason) << "</li>\n";
    s << "</ul>\n";
  }
  s << "<div class=\"flex\">\n";
  // The numbers: estimate, σ, change, truth error.
  if (e.usable) {
    s << "<table class=\"big\">\n<tr><th></th><th>estimate</th><th>1&#963;</th>";
    if (change) s << "<th>change since previous</th>";
    if (truth) s << "<th>error (estimate &#8722; truth)</th>";
    s << "</tr>\n";
    const calib::Mount& m = outcome.mount;
    const Eigen::Matrix3d& covariance = outcome.covariance;
    const double values[3] = {m.x_m, m.y_m, m.yaw_rad};
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
        << Cell(r.solve.sigma_known ? text(SigmaOf(covariance(k, k)), "%.1f", "%.3f") : "none");
      if (change) {
        const pipeline::Change& c = *change;
        const double d[3] = {c.dx_m, c.dy_m, c.dyaw_rad};
        const double u[3] = {c.x_sigmas, c.y_sigmas, c.yaw_sigmas};
        s << Cell(text(d[k], "%+.1f", "%+.3f") +
                  (std::isfinite(u[k]) ? " (" + Format("%.1f", u[k]) + "&#963;)" : std::string()));
      }
      if (truth) {
        const calib::Mount& t = *truth;
        const double err[3] = {m.x_m - t.x_m, m.y_m - t.y_m, WrapAngle(m.yaw_rad - t.yaw_rad)};
        const double sigma = SigmaOf(covariance(k, k));
        s << Cell(text(err[k], "%+.1f", "%+.3f") +
                  (r.solve.sigma_known && sigma > 0.0
                       ? " (" + Format("%.1f", std::abs(err[k]) / sigma) + "&#963;)"
                       : std::string()));
      }
      s << "</tr>\n";
    }
    s << "</table>\n";
  }
  // The error budget: σ from each source, per axis.
  const analysis::ErrorBudget& b = r.finish.budget;
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
  if (change) {
    s << "<p>Previous calibration: " << Esc(change->previous_file)
      << (change->previous_created_utc.empty() ? std::string()
                                               : " (" + Esc(change->previous_created_utc) + ")")
      << ".</p>\n";
  }
  s << "</section>\n";
  return s.str();
}

}  // namespace wallcal::outputs
