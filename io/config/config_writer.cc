// SPDX-License-Identifier: Apache-2.0
#include "io/config/config_writer.h"

#include <cmath>

#include "common/angles.h"
#include "io/config/yaml_text.h"

namespace wallcal::io {

std::string FormatOffsetsYaml(const OffsetsDocument& doc) {
  const double* c = doc.covariance;
  auto stddev = [](double variance) { return variance >= 0.0 ? std::sqrt(variance) : kNaN; };
  const double yaw_deg = doc.yaw_rad * kRadToDeg;
  std::string out;
  out +=
      "# Mount of the scanner in the vehicle (GNSS antenna) frame: x forward, y left, yaw ccw.\n";
  out += "scanner_mount:\n";
  out += "  parent_frame: " + YamlText(doc.parent_frame) + "\n";
  out += "  child_frame: " + YamlText(doc.child_frame) + "\n";
  out += "  x: " + YamlNumber("%.6f", doc.x_m) + "  # m\n";
  out += "  y: " + YamlNumber("%.6f", doc.y_m) + "  # m\n";
  out += "  yaw: " + YamlNumber("%.8f", doc.yaw_rad) + "  # rad\n";
  out += "  yaw_deg: " + YamlNumber("%.4f", yaw_deg) + "\n";
  if (doc.sigma_known) {
    out += "  stddev: {x: " + YamlNumber("%.6f", stddev(c[0])) +
           ", y: " + YamlNumber("%.6f", stddev(c[4])) +
           ", yaw_deg: " + YamlNumber("%.4f", stddev(c[8]) * kRadToDeg) + "}\n";
    out += "  covariance: [";
    for (int i = 0; i < 9; ++i) {
      if (i > 0) out += ", ";
      out += YamlNumber("%.6e", c[i]);
    }
    out += "]  # 3x3 row-major, order x, y, yaw (m, m, rad)\n";
  } else {
    out += "  stddev: null  # not computed by this method: see warnings\n";
    out += "  covariance: null\n";
  }
  // Barawid et al. 2007 put x lateral to the right and y forward: a = -y, b = x, delta = yaw.
  out += "barawid_2007_notation: {a: " + YamlNumber("%.6f", -doc.y_m) +
         ", b: " + YamlNumber("%.6f", doc.x_m) + ", delta_deg: " + YamlNumber("%.4f", yaw_deg) +
         "}\n";
  out += "quality:\n";
  out += "  scans_total: " + std::to_string(doc.scans_total) + "\n";
  out += "  scans_used: " + std::to_string(doc.scans_used) + "\n";
  out += "  headings_deg: {min: " + YamlNumber("%.4f", doc.heading_min_deg) +
         ", max: " + YamlNumber("%.4f", doc.heading_max_deg) + "}\n";
  out += "  residual_rms_m: " + YamlNumber("%.6f", doc.residual_rms_m) + "\n";
  for (const auto& [key, value] : doc.quality_extra) {
    out += "  " + YamlText(key) + ": " + value + "\n";
  }
  if (doc.warnings.empty()) {
    out += "warnings: []\n";
  } else {
    out += "warnings:\n";
    for (const std::string& warning : doc.warnings) {
      // Always quoted: a warning is free text and may hold ':' or '#'.
      std::string quoted = YamlText(warning);
      if (quoted.front() != '"') quoted = "\"" + quoted + "\"";
      out += "  - " + quoted + "\n";
    }
  }
  for (const auto& [key, value] : doc.sections) out += YamlText(key) + ": " + value + "\n";
  out += "method: " + YamlText(doc.method) + "\n";
  out += "source:\n";
  out += "  session: " + YamlQuoted(doc.session) + "\n";
  out += "  tool_version: " + YamlQuoted(doc.tool_version) + "\n";
  if (!doc.created_utc.empty()) out += "  created_utc: " + YamlQuoted(doc.created_utc) + "\n";
  if (!doc.command_line.empty()) {
    out += "  command_line: [";
    for (size_t i = 0; i < doc.command_line.size(); ++i) {
      out += (i ? ", " : "") + YamlQuoted(doc.command_line[i]);
    }
    out += "]\n";
  }
  if (!doc.inputs.empty()) {
    out += "  inputs:\n";
    for (const InputFileDigest& input : doc.inputs) {
      out += "    - {role: " + YamlQuoted(input.role) + ", path: " + YamlQuoted(input.path) +
             ", sha256: " + (input.sha256.empty() ? std::string("null") : input.sha256) + "}\n";
    }
  }
  return out;
}

std::string FormatScannerPreset(const ScannerPreset& preset,
                                const std::vector<std::string>& comment_lines) {
  std::string out;
  for (const std::string& line : comment_lines) out += "# " + line + "\n";
  auto number = [&out](const char* key, double value) {
    out += std::string(key) + ": " + ShortestNumber(value) + "\n";
  };
  out += "name: " + YamlText(preset.name) + "\n";
  out += "source: " + YamlText(preset.source) + "\n";
  out += "num_beams: " + std::to_string(preset.num_beams) + "\n";
  number("start_angle_deg", preset.start_angle_rad * kRadToDeg);
  number("angular_step_deg", preset.angular_step_rad * kRadToDeg);
  number("rate_hz", preset.rate_hz);
  number("min_range_m", preset.min_range_m);
  number("max_range_m", preset.max_range_m);
  number("error_codes_below_m", preset.error_codes_below_m);
  out += std::string("max_range_is_no_return: ") +
         (preset.max_range_is_no_return ? "true" : "false") + "\n";
  number("range_resolution_m", preset.range_resolution_m);
  out += "range_correction: {k: " + ShortestNumber(preset.range_scale_k) +
         ", b_m: " + ShortestNumber(preset.range_offset_b_m) + "}\n";
  out += "range_model_sigma: {k: " + ShortestNumber(preset.range_scale_sigma) +
         ", b_m: " + ShortestNumber(preset.range_offset_sigma_m) + "}\n";
  out += "simulation: {n: " + ShortestNumber(preset.sim_scale_n) +
         ", c_m: " + ShortestNumber(preset.sim_offset_c_m) +
         ", sigma_m: " + ShortestNumber(preset.range_sigma_m) + "}\n";
  number("max_incidence_deg", preset.max_incidence_rad * kRadToDeg);
  return out;
}

}  // namespace wallcal::io
