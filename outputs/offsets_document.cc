// SPDX-License-Identifier: Apache-2.0
#include "outputs/offsets_document.h"

#include <cmath>
#include <string>

#include "common/angles.h"
#include "common/format.h"
#include "io/config/yaml_text.h"
#include "io/version.h"

namespace wallcal::outputs {

using pipeline::CalibrationResult;

namespace {
// Free text (reasons, paths, times) by the one YAML escaper.
std::string Quoted(const std::string& text) { return io::YamlQuoted(text); }
// Metres as millimetres, radians as degrees, NaN as null: the YAML reads in the units people use.
std::string Mm(double m) { return std::isfinite(m) ? Format("%.2f", m * 1e3) : "null"; }
std::string Deg(double rad) { return std::isfinite(rad) ? Format("%.4f", rad * kRadToDeg) : "null"; }
std::string Ratio(double v) { return std::isfinite(v) ? Format("%.2f", v) : "null"; }
}  // namespace

std::string DecisionYaml(const pipeline::Decision& decision) {
  std::string out = std::string("{verdict: ") + pipeline::VerdictName(decision.verdict) +
                    ", reasons: [";
  for (size_t i = 0; i < decision.reasons.size(); ++i) {
    out += (i ? ", " : "") + Quoted(decision.reasons[i]);
  }
  return out + "]}";
}

std::string VerdictYaml(const CalibrationResult& result) {
  return DecisionYaml(result.decided.decision);
}

std::string BudgetYaml(const analysis::ErrorBudget& b,
                       const std::vector<pipeline::SolveResult::SiteTerm>& site_terms) {
  // σ per source (the square root of the variance it explains), mm and degrees.
  std::string out = "{method: \"variance removed when one source is exact (linearised)\"";
  out += ", total: {x_mm: " + Mm(std::sqrt(b.total_variance[0])) +
         ", y_mm: " + Mm(std::sqrt(b.total_variance[1])) +
         ", yaw_deg: " + Deg(std::sqrt(b.total_variance[2])) + "}";
  for (int k = 0; k < analysis::kNumErrorSources; ++k) {
    const Eigen::Vector3d& v = b.variance[k];
    out += std::string(", ") + analysis::ErrorSourceKey(static_cast<analysis::ErrorSource>(k)) +
           ": {x_mm: " + Mm(std::sqrt(v[0])) + ", y_mm: " + Mm(std::sqrt(v[1])) +
           ", yaw_deg: " + Deg(std::sqrt(v[2])) + "}";
  }
  // The site's terms (in the mount's covariance beside the adjustment's, not in `total`).
  for (const pipeline::SolveResult::SiteTerm& t : site_terms) {
    const Eigen::Vector3d v = t.covariance.diagonal();
    out += std::string(", ") + pipeline::SiteTermKey(t.kind) + ": {x_mm: " + Mm(std::sqrt(v[0])) +
           ", y_mm: " + Mm(std::sqrt(v[1])) + ", yaw_deg: " + Deg(std::sqrt(v[2])) + "}";
  }
  return out + "}";
}

// The site's 3-D geometry under quality: written when the level model was corrected or the
// yard is graded with scanner.z_m not given (absent: a level site, as the level model has it).
template <class Add>
void AddSite(const CalibrationResult& result, const Add& add) {
  const pipeline::SiteResult& site = result.site;
  if (!site.corrected && !result.solve.unknown_height_bias) return;
  std::string out = "{attitude_source: \"" +
                    std::string(calib::AttitudeSourceName(site.attitude.source())) + "\"";
  if (site.yard.fitted) {
    out += ", yard_grade_pct: " + Format("%.2f", site.yard.GradePercent()) +
           ", yard_grade_sigma_pct: " +
           Format("%.2f", 100.0 * site.yard.GradeSigma()) +
           ", yard_rises_towards_deg: " + Format("%.1f", site.yard.RiseDirectionDeg(0.1)) +
           ", yard_residual_rms_m: " + Format("%.3f", site.yard.residual_rms_m);
  }
  if (site.attitude_samples > 0) {
    out += ", attitude_samples: " + std::to_string(site.attitude_samples) +
           ", attitude_rate_hz: " + Format("%.1f", site.attitude_rate_hz);
  }
  out += ", scanner_z_m: " + (site.z_given ? Format("%.3f", site.placement.z_m) : std::string("null"));
  out += ", scanner_pitch_deg: " + Format("%.2f", site.placement.pitch_rad * kRadToDeg) +
         ", scanner_roll_deg: " + Format("%.2f", site.placement.roll_rad * kRadToDeg);
  std::string leans;
  for (const calib::WallGeometry& w : result.survey.walls) {
    if (w.lean_rad == 0.0) continue;
    leans += (leans.empty() ? "" : ", ") + std::string("{id: \"") + w.id +
             "\", lean_deg: " + Format("%.3f", w.lean_rad * kRadToDeg) +
             ", sigma_deg: " + Format("%.3f", w.sigma_lean_rad * kRadToDeg) +
             ", used: " + (std::isfinite(w.reference_height_m) ? "true" : "false") + "}";
  }
  if (!leans.empty()) out += ", leaning_walls: [" + leans + "]";
  add("site", out + "}");
}

std::string ChangeYaml(const pipeline::Change& c) {
  return "{previous: " + Quoted(c.previous_file) +
         (c.previous_created_utc.empty() ? std::string() : ", previous_created_utc: " + Quoted(c.previous_created_utc)) +
         ", dx_mm: " + Mm(c.dx_m) + ", dy_mm: " + Mm(c.dy_m) + ", dyaw_deg: " + Deg(c.dyaw_rad) +
         ", combined_sigmas: {x: " + Ratio(c.x_sigmas) + ", y: " + Ratio(c.y_sigmas) +
         ", yaw: " + Ratio(c.yaw_sigmas) + "}" +
         (c.previous_inverted ? ", previous_inverted: true" : "") + "}";
}

io::OffsetsDocument MakeOffsetsDocument(const CalibrationResult& result, const EmitFrames& frames) {
  io::OffsetsDocument doc;
  doc.parent_frame = frames.parent;
  doc.child_frame = frames.child;
  doc.sigma_known = result.solve.sigma_known;
  const solvers::MountEstimate& e = result.solve.estimate;
  doc.x_m = e.mount.x_m;
  doc.y_m = e.mount.y_m;
  doc.yaw_rad = e.mount.yaw_rad;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) doc.covariance[3 * r + c] = e.covariance(r, c);
  }
  doc.method = solvers::MethodText(e);
  doc.scans_total = result.detection.scans_total;
  doc.scans_used = result.finish.coverage.scans_used;
  doc.heading_min_deg = result.finish.coverage.heading_min_deg;
  doc.heading_max_deg = result.finish.coverage.heading_max_deg;
  doc.residual_rms_m = e.residual_rms_m;
  auto add = [&doc](const std::string& key, const std::string& value) {
    doc.quality_extra.emplace_back(key, value);
  };
  add("observations", std::to_string(e.observations_used));
  add("outliers", std::to_string(e.observations_rejected));
  add("stations", std::to_string(result.poses.num_dwells));
  add("gnss_segments", std::to_string(result.finish.coverage.num_segments_used));
  add("vehicle_to_wall_angle_deg",
      "{min: " + Format("%.2f", result.finish.coverage.wall_angle_min_deg) +
          ", max: " + Format("%.2f", result.finish.coverage.wall_angle_max_deg) + "}");
  std::string skipped = "{";
  bool first = true;
  for (const auto& [reason, count] : result.ScansSkipped()) {
    skipped += (first ? "" : ", ") + std::string("\"") + calib::ScanSkipName(reason) + "\": " +
               std::to_string(count);
    first = false;
  }
  add("scans_skipped", skipped + "}");
  std::string quality = "{";
  first = true;
  for (const auto& [q, count] : result.poses.fixes_by_quality) {
    quality += (first ? "" : ", ") + std::to_string(q) + ": " + std::to_string(count);
    first = false;
  }
  add("gnss_fixes_by_quality", quality + "}");
  add("gnss_fixes_used", std::to_string(result.poses.fixes_used));
  add("headings_used", std::to_string(result.poses.headings_used));
  add("control_points", std::to_string(result.survey.tie.num_control));
  add("control_rms_m", Format("%.4f", result.survey.tie.control_rms_m));
  add("utm_zone", "\"" + std::to_string(result.survey.frame.zone) +
                      (result.survey.frame.north ? "N" : "S") + "\"");
  add("meridian_convergence_deg", Format("%.4f", result.survey.frame.convergence_rad * kRadToDeg));
  add("point_scale", Format("%.7f", result.survey.frame.scale_k0));
  std::string walls = "[";
  for (size_t i = 0; i < result.survey.walls.size(); ++i) {
    const calib::WallGeometry& w = result.survey.walls[i];
    walls += (i ? ", " : "") + std::string("{id: \"") + w.id + "\", points: " +
             std::to_string(w.num_points) + ", rms_m: " + Format("%.4f", w.rms_m) +
             ", sigma_offset_m: " + Format("%.4f", w.sigma_offset_m) +
             ", sigma_angle_deg: " + Format("%.4f", w.sigma_angle_rad * kRadToDeg) + "}";
  }
  add("walls", walls + "]");
  AddSite(result, add);
  if (e.independent_stations > 0.0) {
    add("independent_stations", Format("%.2f", e.independent_stations));
  }
  if (e.time_offset_estimated) {
    add("time_offset_s", Format("%.4f", result.solve.scanner_offset.value_s));
    add("time_offset_sigma_s", Format("%.4f", result.solve.scanner_offset.sigma_s));
    add("time_offset_status",
        "\"" + std::string(pipeline::DelayStatusName(result.solve.scanner_offset.status)) + "\"");
    if (result.solve.drives_timing_sigma_s > 0.0) {
      add("moving_timing_sigma_s", Format("%.4f", result.solve.drives_timing_sigma_s) +
                                       "  # what the moving scans' poses need (docs/method.md)");
    }
  } else {
    add("time_offset_s", "null  # not estimated: every scan used was taken at a station");
  }
  if (result.solve.heading_delay.status != pipeline::DelayStatus::kNotEstimated) {
    add("heading_delay_s", Format("%.4f", result.solve.heading_delay.value_s));
    add("heading_delay_sigma_s", Format("%.4f", result.solve.heading_delay.sigma_s));
  } else {
    add("heading_delay_s", "null  # not estimated: no moving scans used");
  }
  add("heading_delay_status",
      "\"" + std::string(pipeline::DelayStatusName(result.solve.heading_delay.status)) + "\"");
  const calib::GnssEpochMapping& g = result.poses.gnss_epochs;
  add("gnss_epoch_time",
      "\"" + std::string(calib::EpochMappingStatusName(g.status)) + "\"");
  if (std::isfinite(g.offset_s)) {
    add("gnss_latency_s", Format("%.4f", g.offset_s) +
                              "  # logger stamp − UTC epoch: latency + logger clock offset");
    add("gnss_jitter_s", Format("%.4f", g.jitter_s));
    add("gnss_clock_drift_ppm", Format("%.1f", 1e6 * g.drift));
  }
  if (!e.weak_direction.empty()) add("weak_direction", "\"" + e.weak_direction + "\"");
  add("forced", result.solve.forced ? "true" : "false");
  const analysis::ResidualAnalysis& ra = result.finish.residual_analysis;
  if (ra.done) {
    add("residual_robust_sigma_m", Format("%.4f", ra.robust_sigma_m));
    add("outlier_share", Format("%.4f", ra.outlier_share));
    std::string trends = "{";
    for (size_t i = 0; i < ra.trends.size(); ++i) {
      const analysis::ResidualTrend& t = ra.trends[i];
      trends += (i ? ", " : "") + std::string(analysis::TrendAxisName(t.against)) +
                ": {slope: " + Format("%.4g", t.slope) + ", unit: \"" + t.unit +
                "\", significance: " + Format("%.2f", t.significance) + ", flagged: " + (t.flagged ? "true" : "false") + "}";
    }
    add("residual_trends", trends + "}");
    std::string flags = "[";
    for (size_t i = 0; i < ra.flags.size(); ++i) {
      flags += (i ? ", " : "") + std::string("\"") + ra.flags[i] + "\"";
    }
    add("residual_flags", flags + "]");
    if (ra.range_model_estimated) {
      add("range_scale_k_from_residuals",
          "{k: " + Format("%.5f", ra.range_scale_k) +
              ", sigma: " + Format("%.5f", ra.sigma_range_scale_k) +
              ", preset_k: " + Format("%.5f", result.loaded.preset.range_scale_k) + "}");
    }
  }
  const analysis::Repeatability& rep = result.finish.repeatability;
  if (rep.done) {
    std::string text = "{bootstrap_samples: " + std::to_string(rep.bootstrap_samples) +
                       ", bootstrap_sigma: {x: " + Format("%.4f", rep.bootstrap_sigma_x_m) +
                       ", y: " + Format("%.4f", rep.bootstrap_sigma_y_m) +
                       ", yaw_deg: " + Format("%.4f", rep.bootstrap_sigma_yaw_rad * kRadToDeg) +
                       "}, split_max_shift: {x: " + Format("%.4f", rep.max_split_shift_x_m) +
                       ", y: " + Format("%.4f", rep.max_split_shift_y_m) +
                       ", yaw_deg: " + Format("%.4f", rep.max_split_shift_yaw_rad * kRadToDeg) +
                       "}, splits: [";
    for (size_t i = 0; i < rep.splits.size(); ++i) {
      const analysis::RepeatabilitySplit& sp = rep.splits[i];
      text += (i ? ", " : "") + std::string("{name: \"") + sp.name +
              "\", usable: " + (sp.usable ? "true" : "false") + ", x: " +
              Format("%.4f", sp.mount.x_m) + ", y: " + Format("%.4f", sp.mount.y_m) +
              ", yaw_deg: " + Format("%.4f", sp.mount.yaw_rad * kRadToDeg) + "}";
    }
    add("repeatability", text + "]}");
  }
  if (e.heading_drift_estimated) {
    // deg/h at the file edge; the rate is estimated with the prior solver.heading_drift_sigma.
    add("heading_drift_deg_per_h", Format("%.4f", e.heading_drift_rad_per_s * kRadToDeg * 3600.0));
    add("heading_drift_sigma_deg_per_h",
        Format("%.4f", e.heading_drift_sigma_rad_per_s * kRadToDeg * 3600.0));
  }
  add("yaw_reference",
      "\"relative to the heading sensor's zero at the first scan used (t = " +
          Format("%.3f", e.heading_reference_s) +
          " s): a constant heading bias is indistinguishable from mount yaw; the heading drift "
          "after that time is estimated (heading_drift_deg_per_h)\"");
  doc.warnings = pipeline::Messages(result.AllWarnings());
  doc.sections.emplace_back("verdict", VerdictYaml(result));
  if (result.finish.budget.done)
    doc.sections.emplace_back("error_budget", BudgetYaml(result.finish.budget, result.solve.site_terms));
  if (result.decided.change)
    doc.sections.emplace_back("change_since_previous", ChangeYaml(*result.decided.change));
  doc.session = result.loaded.session.file;
  doc.tool_version = io::kToolVersion;
  doc.created_utc = result.decided.provenance.created_utc;
  doc.command_line = result.decided.provenance.command_line;
  doc.inputs = result.decided.provenance.inputs;
  return doc;
}

}  // namespace wallcal::outputs
