// SPDX-License-Identifier: Apache-2.0
#include "sim/simulation_config.h"

#include <utility>

#include "io/config/options_text.h"
#include "io/config/yaml_text.h"

namespace wallcal::sim {
namespace {

using namespace io::option_checks;  // NOLINT: the checks every Validate() makes

// The keys a scenario carries beside the visitor's: the per-stream delays, the car-like drives
// and the scanner's true range model, which truth.yaml writes only when set.
void ReadOptionalKeys(io::OptionsMap& section, SimulationConfig& config) {
  section.Number("gnss_latency_s", config.gnss_latency_s);
  section.Number("gnss_jitter_s", config.gnss_jitter_s);
  section.Number("heading_latency_s", config.heading_latency_s);
  section.Number("scanner_latency_s", config.scanner_latency_s);
  section.Number("station_distance_far_m", config.station_distance_far_m);
  section.Number("drive_reverse_m", config.drive_reverse_m);
  section.Scaled("weave_turn_deg", config.weave_turn_rad, kRadToDeg);
  section.List("scanners", config.scanners, [](io::OptionsMap& item, SimScanner& scanner) {
    item.Text("id", scanner.id);
    item.Number("mount_x_m", scanner.mount_x_m);
    item.Number("mount_y_m", scanner.mount_y_m);
    item.Scaled("mount_yaw_deg", scanner.mount_yaw_rad, kRadToDeg);
    item.Number("scanner_time_offset_s", scanner.scanner_time_offset_s);
    item.Number("scanner_latency_s", scanner.scanner_latency_s);
  });
  std::string survey_mode =
      config.survey_mode == SurveyMode::kRover ? "rover" : "total_station";
  section.Text("survey_mode", survey_mode);
  if (survey_mode == "rover") {
    config.survey_mode = SurveyMode::kRover;
  } else if (survey_mode == "total_station") {
    config.survey_mode = SurveyMode::kTotalStation;
  } else {
    Fail("simulation.survey_mode", "total_station or rover", survey_mode);
  }
  section.Number("rover_sigma_m", config.rover_sigma_m);
  section.Section("scanner_truth", [&config](io::OptionsMap& truth) {
    truth.Number("n", config.truth_scale_n);
    truth.Number("c_m", config.truth_offset_c_m);
    truth.Number("sigma_m", config.truth_sigma_m);
    truth.Number("resolution_m", config.truth_resolution_m);
    truth.Scaled("max_incidence_deg", config.truth_max_incidence_rad, kRadToDeg);
    truth.Section("drift", [&config](io::OptionsMap& drift) {
      drift.Number("amplitude_m", config.truth_drift_amplitude_m);
      drift.Number("time_constant_s", config.truth_drift_time_constant_s);
    });
  });
}

}  // namespace

void SimulationConfig::Validate() const {
  const std::string s = "simulation.";
  CheckRange(s + "site_lat_deg", site_lat_deg, -80.0, 84.0);  // UTM's latitude band
  CheckRange(s + "site_lon_deg", site_lon_deg, -180.0, 180.0);
  CheckFinite(s + "site_height_m", site_height_m);
  if (name.empty()) Fail(s + "name", "non-empty", "\"\"");
  if (scanner_model.empty()) Fail(s + "scanner_model", "non-empty", "\"\"");
  if (!(std::isfinite(log_every_n) && log_every_n >= 1.0)) {
    Fail(s + "log_every_n", ">= 1", Number(log_every_n));
  }
  CheckFinite(s + "scanner_time_offset_s", scanner_time_offset_s);
  CheckFinite(s + "mount_x_m", mount_x_m);
  CheckFinite(s + "mount_y_m", mount_y_m);
  CheckRange(s + "mount_yaw_deg", mount_yaw_rad * kRadToDeg, -180.0, 180.0);
  for (size_t i = 0; i < walls.size(); ++i) {
    const SimWall& wall = walls[i];
    const std::string w = s + "walls[" + std::to_string(i) + "].";
    if (wall.id.empty()) Fail(w + "id", "non-empty", "\"\"");
    CheckFinite(w + "x0_m", wall.x0_m);
    CheckFinite(w + "y0_m", wall.y0_m);
    CheckFinite(w + "x1_m", wall.x1_m);
    CheckFinite(w + "y1_m", wall.y1_m);
    const double length_m = std::hypot(wall.x1_m - wall.x0_m, wall.y1_m - wall.y0_m);
    if (!(length_m > 0.0)) Fail(w + "x1_m/y1_m", "a different point from x0_m/y0_m", "the same");
    CheckPositive(w + "height_m", wall.height_m);
    CheckPositive(w + "survey_spacing_m", wall.survey_spacing_m);
  }
  for (size_t i = 0; i < obstacles.size(); ++i) {
    const std::string o = s + "obstacles[" + std::to_string(i) + "].";
    CheckFinite(o + "x_m", obstacles[i].x_m);
    CheckFinite(o + "y_m", obstacles[i].y_m);
    CheckPositive(o + "radius_m", obstacles[i].radius_m);
  }
  CheckAtLeast(s + "num_stations", num_stations, 1);
  CheckPositive(s + "station_distance_m", station_distance_m);
  CheckRange(s + "heading_spread_deg", heading_spread_rad * kRadToDeg, 0.0, 360.0);
  CheckNonNegative(s + "dwell_s", dwell_s);
  CheckPositive(s + "drive_speed_mps", drive_speed_mps);
  CheckNonNegative(s + "lateral_spread_m", lateral_spread_m);
  CheckPositive(s + "gnss_rate_hz", gnss_rate_hz);
  CheckNonNegative(s + "gnss_bias_sigma_m", gnss_bias_sigma_m);
  CheckPositive(s + "gnss_bias_tau_s", gnss_bias_tau_s);
  CheckNonNegative(s + "gnss_white_sigma_m", gnss_white_sigma_m);
  CheckRange(s + "float_fraction", float_fraction, 0.0, 1.0);
  CheckPositive(s + "heading_rate_hz", heading_rate_hz);
  CheckNonNegative(s + "heading_white_sigma_deg", heading_white_sigma_rad * kRadToDeg);
  CheckFinite(s + "heading_drift_deg_per_h", heading_drift_rad_per_s * kRadToDeg * 3600.0);
  CheckFinite(s + "heading_bias_deg", heading_bias_rad * kRadToDeg);
  CheckNonNegative(s + "total_station_sigma_m", total_station_sigma_m);
  CheckNonNegative(s + "control_sigma_m", control_sigma_m);
  CheckFinite(s + "survey_rotation_deg", survey_rotation_rad * kRadToDeg);
  CheckFinite(s + "survey_origin_x_m", survey_origin_x_m);
  CheckFinite(s + "survey_origin_y_m", survey_origin_y_m);
  if (!(lost_scan_fraction >= 0.0 && lost_scan_fraction < 1.0)) {
    Fail(s + "lost_scan_fraction", "in [0, 1)", Number(lost_scan_fraction));
  }
  CheckRange(s + "mixed_pixel_probability", mixed_pixel_probability, 0.0, 1.0);
  CheckNonNegative(s + "start_time_s", start_time_s);
  CheckRange(s + "gnss_latency_s", gnss_latency_s, 0.0, 10.0);
  CheckRange(s + "gnss_jitter_s", gnss_jitter_s, 0.0, 1.0);
  CheckRange(s + "heading_latency_s", heading_latency_s, 0.0, 10.0);
  CheckRange(s + "scanner_latency_s", scanner_latency_s, 0.0, 10.0);
  const std::string t = s + "scanner_truth.";
  if (!std::isnan(truth_scale_n)) CheckRange(t + "n", truth_scale_n, 0.5, 1.5);
  if (!std::isnan(truth_offset_c_m)) CheckRange(t + "c_m", truth_offset_c_m, -1.0, 1.0);
  if (!std::isnan(truth_sigma_m)) CheckRange(t + "sigma_m", truth_sigma_m, 0.0, 1.0);
  if (!std::isnan(truth_resolution_m)) CheckRange(t + "resolution_m", truth_resolution_m, 1e-6, 1.0);
  if (!std::isnan(truth_max_incidence_rad)) {
    CheckRange(t + "max_incidence_deg", truth_max_incidence_rad * kRadToDeg, 1.0, 90.0);
  }
  CheckRange(t + "drift.amplitude_m", truth_drift_amplitude_m, -1.0, 1.0);
  CheckNonNegative(t + "drift.time_constant_s", truth_drift_time_constant_s);
  CheckNonNegative(s + "station_distance_far_m", station_distance_far_m);
  CheckRange(s + "drive_reverse_m", drive_reverse_m, 0.0, 100.0);
  CheckRange(s + "weave_turn_deg", weave_turn_rad * kRadToDeg, 0.0, 90.0);
  CheckRange(s + "rover_sigma_m", rover_sigma_m, 1e-4, 1.0);
  for (size_t i = 0; i < scanners.size(); ++i) {
    const SimScanner& scanner = scanners[i];
    const std::string k = s + "scanners[" + std::to_string(i) + "].";
    if (scanner.id.empty()) Fail(k + "id", "non-empty", "\"\"");
    for (size_t j = 0; j < i; ++j) {
      if (scanners[j].id == scanner.id) Fail(k + "id", "unique", "'" + scanner.id + "' twice");
    }
    CheckFinite(k + "mount_x_m", scanner.mount_x_m);
    CheckFinite(k + "mount_y_m", scanner.mount_y_m);
    CheckRange(k + "mount_yaw_deg", scanner.mount_yaw_rad * kRadToDeg, -180.0, 180.0);
    CheckFinite(k + "scanner_time_offset_s", scanner.scanner_time_offset_s);
    CheckRange(k + "scanner_latency_s", scanner.scanner_latency_s, 0.0, 10.0);
  }
}

SimulationConfig ForScanner(const SimulationConfig& config, size_t index) {
  SimulationConfig one = config;
  const SimScanner& scanner = config.scanners.at(index);
  one.mount_x_m = scanner.mount_x_m;
  one.mount_y_m = scanner.mount_y_m;
  one.mount_yaw_rad = scanner.mount_yaw_rad;
  one.scanner_time_offset_s = scanner.scanner_time_offset_s;
  one.scanner_latency_s = scanner.scanner_latency_s;
  one.scanner_noise_stream = static_cast<uint32_t>(index);
  one.scanners.clear();
  return one;
}

SimulationConfig ReadSimulationConfig(const std::string& file) {
  SimulationConfig config;
  io::ReadOptionsFile(
      file,
      [&config](io::OptionsMap& top) {
        VisitSimulationConfig(top, config);
        ReadOptionalKeys(top, config);
      },
      [&config] { config.Validate(); });
  return config;
}

SimulationConfig ReadTruthYaml(const std::string& file) {
  SimulationConfig config;
  io::ReadOptionsFile(
      file,
      [&config](io::OptionsMap& top) {
        top.RequiredSection("simulation", "the simulation settings", [&config](io::OptionsMap& s) {
          VisitSimulationConfig(s, config);
          ReadOptionalKeys(s, config);
        });
        // The truth mount in radians is exact; simulation.mount_yaw_deg went through degrees.
        top.Section("truth", [&config](io::OptionsMap& mount) {
          mount.Number("x", config.mount_x_m);
          mount.Number("y", config.mount_y_m);
          mount.Number("yaw", config.mount_yaw_rad);
          double yaw_deg = 0.0;
          mount.Number("yaw_deg", yaw_deg);
        });
        top.Allow({"seed"});
      },
      [&config] { config.Validate(); });
  return config;
}

std::string FormatTruthYaml(const SimulationConfig& config, uint64_t seed) {
  SimulationConfig copy = config;  // the visitor takes mutable references
  io::OptionsText simulation;
  VisitSimulationConfig(simulation, copy);
  std::string out;
  out += "# The true mount and every setting the simulator used (wallcal simulate).\n";
  out += "truth:  # scanner in the vehicle frame: x forward, y left (m), yaw ccw\n";
  out += "  x: " + io::ShortestNumber(config.mount_x_m) + "\n";
  out += "  y: " + io::ShortestNumber(config.mount_y_m) + "\n";
  out += "  yaw: " + io::ShortestNumber(config.mount_yaw_rad) + "\n";
  out += "  yaw_deg: " + io::ShortestNumber(config.mount_yaw_rad * kRadToDeg) + "\n";
  out += "seed: " + std::to_string(seed) + "\n";
  out += "simulation:\n";
  out += simulation.Block(2);
  // The per-stream delays and the characterisation keys only when set: older scenarios'
  // truth.yaml stays as it was.
  for (const auto& [key, value] :
       {std::pair<const char*, double>{"gnss_latency_s", config.gnss_latency_s},
        {"gnss_jitter_s", config.gnss_jitter_s},
        {"heading_latency_s", config.heading_latency_s},
        {"scanner_latency_s", config.scanner_latency_s}}) {
    if (value != 0.0) out += std::string("  ") + key + ": " + io::ShortestNumber(value) + "\n";
  }
  if (config.station_distance_far_m != 0.0) {
    out += "  station_distance_far_m: " + io::ShortestNumber(config.station_distance_far_m) + "\n";
  }
  if (config.drive_reverse_m != 0.0) {
    out += "  drive_reverse_m: " + io::ShortestNumber(config.drive_reverse_m) + "\n";
  }
  if (config.weave_turn_rad != 0.0) {
    out += "  weave_turn_deg: " + io::ShortestNumber(config.weave_turn_rad * kRadToDeg) + "\n";
  }
  if (!config.scanners.empty()) {
    out += "  scanners:\n";
    for (const SimScanner& scanner : config.scanners) {
      out += "    - {id: " + io::YamlText(scanner.id) +
             ", mount_x_m: " + io::ShortestNumber(scanner.mount_x_m) +
             ", mount_y_m: " + io::ShortestNumber(scanner.mount_y_m) +
             ", mount_yaw_deg: " + io::ShortestNumber(scanner.mount_yaw_rad * kRadToDeg) +
             ", scanner_time_offset_s: " + io::ShortestNumber(scanner.scanner_time_offset_s) +
             ", scanner_latency_s: " + io::ShortestNumber(scanner.scanner_latency_s) + "}\n";
    }
  }
  if (config.survey_mode == SurveyMode::kRover) {
    out += "  survey_mode: rover\n";
    out += "  rover_sigma_m: " + io::ShortestNumber(config.rover_sigma_m) + "\n";
  }
  if (config.HasScannerTruth()) {
    std::string truth;
    auto add = [&truth](const char* key, double value) {
      if (std::isnan(value)) return;
      truth += std::string(truth.empty() ? "" : ", ") + key + ": " + io::ShortestNumber(value);
    };
    add("n", config.truth_scale_n);
    add("c_m", config.truth_offset_c_m);
    add("sigma_m", config.truth_sigma_m);
    add("resolution_m", config.truth_resolution_m);
    add("max_incidence_deg", config.truth_max_incidence_rad * kRadToDeg);
    truth += std::string(truth.empty() ? "" : ", ") +
             "drift: {amplitude_m: " + io::ShortestNumber(config.truth_drift_amplitude_m) +
             ", time_constant_s: " + io::ShortestNumber(config.truth_drift_time_constant_s) + "}";
    out += "  scanner_truth: {" + truth + "}\n";
  }
  return out;
}

}  // namespace wallcal::sim
