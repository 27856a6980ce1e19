// SPDX-License-Identifier: Apache-2.0
#include "sim/simulation_config.h"

#include <cmath>
#include <string>
#include <utility>

#include "io/config/options_text.h"
#include "io/config/yaml_text.h"

namespace wallcal::sim {
namespace {

using namespace io::option_checks;  // NOLINT: the checks every Validate() makes

// The keys a scenario carries beside VisitSimulationConfig's, and their checks: the per-stream
// delays and scan jitter, the car-like drives, more scanners, the scanner's true range model
// (NaN: the preset's) and the unit's errors off it, the 3-D site (NaN: not set) and the
// attitude stream, which truth.yaml writes only when set (FormatTruthYaml).
template <class V>
void VisitOptionalKeys(V& v, SimulationConfig& c) {
  v.Number("gnss_latency_s", c.gnss_latency_s, io::InRange(0.0, 10.0));
  v.Number("gnss_jitter_s", c.gnss_jitter_s, io::InRange(0.0, 1.0));
  v.Number("heading_latency_s", c.heading_latency_s, io::InRange(0.0, 10.0));
  v.Number("scanner_latency_s", c.scanner_latency_s, io::InRange(0.0, 10.0));
  v.Number("scanner_jitter_s", c.scanner_jitter_s, io::InRange(0.0, 1.0));
  v.Number("station_distance_far_m", c.station_distance_far_m, io::NonNegative());
  v.Number("drive_reverse_m", c.drive_reverse_m, io::InRange(0.0, 100.0));
  v.Scaled("weave_turn_deg", c.weave_turn_rad, kRadToDeg, io::InRange(0.0, 90.0));
  v.Number("yard_grade_pct", c.yard_grade_pct, io::InRange(0.0, 100.0));
  v.Scaled("yard_grade_dir_deg", c.yard_grade_dir_rad, kRadToDeg, io::InRange(-360.0, 360.0));
  v.Number("antenna_height_m", c.antenna_height_m, io::AboveUpTo(0.0, 20.0).OrUnset());
  v.Number("gnss_vertical_factor", c.gnss_vertical_factor, io::InRange(0.0, 100.0).OrUnset());
  v.Number("mount_z_m", c.mount_z_m, io::InRange(-10.0, 10.0).OrUnset());
  v.Scaled("scanner_pitch_deg", c.scanner_pitch_rad, kRadToDeg, io::InRange(-45.0, 45.0));
  v.Scaled("scanner_roll_deg", c.scanner_roll_rad, kRadToDeg, io::InRange(-45.0, 45.0));
  v.Boolean("write_z_m", c.write_z_m);
  v.Boolean("write_tilt", c.write_tilt);
  v.Number("attitude_rate_hz", c.attitude_rate_hz, io::NonNegative());
  v.Scaled("attitude_white_sigma_deg", c.attitude_white_sigma_rad, kRadToDeg, io::NonNegative());
  v.Text("attitude_sentence", c.attitude_sentence);
  v.Boolean("attitude_own_log", c.attitude_own_log);
  v.List("scanners", c.scanners, [](V& item, SimScanner& s) { VisitSimScanner(item, s); });
  std::string survey_mode = c.survey_mode == SurveyMode::kRover ? "rover" : "total_station";
  v.Text("survey_mode", survey_mode);
  if (survey_mode == "rover") {
    c.survey_mode = SurveyMode::kRover;
  } else if (survey_mode == "total_station") {
    c.survey_mode = SurveyMode::kTotalStation;
  } else {
    Fail("simulation.survey_mode", "total_station or rover", survey_mode);
  }
  v.Number("rover_sigma_m", c.rover_sigma_m, io::InRange(1e-4, 1.0));
  v.Number("range_scale_error", c.range_scale_error, io::InRange(-0.5, 0.5).OrUnset());
  v.Number("range_offset_error_m", c.range_offset_error_m, io::InRange(-1.0, 1.0).OrUnset());
  v.Boolean("draw_unit_range_models", c.draw_unit_range_models);
  v.Section("scanner_truth", [&c](auto& truth) {
    truth.Number("n", c.truth_scale_n, io::InRange(0.5, 1.5).OrUnset());
    truth.Number("c_m", c.truth_offset_c_m, io::InRange(-1.0, 1.0).OrUnset());
    truth.Number("sigma_m", c.truth_sigma_m, io::InRange(0.0, 1.0).OrUnset());
    truth.Number("resolution_m", c.truth_resolution_m, io::InRange(1e-6, 1.0).OrUnset());
    truth.Scaled("max_incidence_deg", c.truth_max_incidence_rad, kRadToDeg,
                 io::InRange(1.0, 90.0).OrUnset());
    truth.Section("drift", [&c](auto& drift) {
      drift.Number("amplitude_m", c.truth_drift_amplitude_m, io::InRange(-1.0, 1.0));
      drift.Number("time_constant_s", c.truth_drift_time_constant_s, io::NonNegative());
    });
  });
}

void ReadKeys(io::OptionsMap& section, SimulationConfig& config) {
  VisitSimulationConfig(section, config);
  VisitOptionalKeys(section, config);
}

}  // namespace

void SimulationConfig::Validate() const {
  io::CheckOptions("simulation.", *this, VisitSimulationConfig<io::OptionChecker>);
  io::CheckOptions("simulation.", *this, VisitOptionalKeys<io::OptionChecker>);
  if (attitude_sentence != "pashr" && attitude_sentence != "avr") {
    Fail("simulation.attitude_sentence", "pashr or avr", "'" + attitude_sentence + "'");
  }
  for (size_t i = 0; i < walls.size(); ++i) {
    const SimWall& wall = walls[i];
    const double length_m = std::hypot(wall.x1_m - wall.x0_m, wall.y1_m - wall.y0_m);
    if (!(length_m > 0.0)) {
      Fail("simulation.walls[" + std::to_string(i) + "].x1_m/y1_m",
           "a different point from x0_m/y0_m", "the same");
    }
    for (size_t k = 0; k < wall.survey_heights_m.size(); ++k) {
      if (wall.survey_heights_m[k] > wall.height_m) {
        Fail("simulation.walls[" + std::to_string(i) + "].survey_heights_m[" +
                 std::to_string(k) + "]",
             "within the wall's height_m (" + Number(wall.height_m) + ")",
             Number(wall.survey_heights_m[k]));
      }
    }
  }
  // The scanner above the ground: a 3-D site's antenna stands AntennaHeightM() above it.
  if (IsThreeDSite()) {
    auto check_above = [this](const std::string& key, double z_m) {
      if (!(AntennaHeightM() + z_m > 0.0)) {
        Fail(key, "> -antenna_height_m (" + Number(-AntennaHeightM()) +
                      ": the scanner above the ground)",
             Number(z_m));
      }
    };
    check_above("simulation.mount_z_m", MountZM());
    for (size_t i = 0; i < scanners.size(); ++i) {
      if (!std::isnan(scanners[i].z_m)) {
        check_above("simulation.scanners[" + std::to_string(i) + "].z_m", scanners[i].z_m);
      }
    }
  }
  // Several scanners: each unit's errors stand on its own entry, as its mount does.
  if (!scanners.empty()) {
    for (const auto& [key, value] :
         {std::pair<const char*, double>{"range_scale_error", range_scale_error},
          {"range_offset_error_m", range_offset_error_m}}) {
      if (!std::isnan(value)) {
        Fail(std::string("simulation.") + key,
             "unset with scanners: (give it on each scanner's entry)", Number(value));
      }
    }
  }
  for (size_t i = 0; i < scanners.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      if (scanners[j].id == scanners[i].id) {
        Fail("simulation.scanners[" + std::to_string(i) + "].id", "unique",
             "'" + scanners[i].id + "' twice");
      }
    }
  }
}

bool SimulationConfig::IsThreeDSite() const {
  const auto set = [](double value) { return !std::isnan(value); };
  const auto tilted = [](double value) { return !std::isnan(value) && value != 0.0; };
  if (yard_grade_pct != 0.0 || set(antenna_height_m) || set(gnss_vertical_factor) ||
      set(mount_z_m) || scanner_pitch_rad != 0.0 || scanner_roll_rad != 0.0) {
    return true;
  }
  for (const SimWall& wall : walls) {
    if (tilted(wall.lean_rad)) return true;
  }
  for (const SimScanner& scanner : scanners) {
    if (set(scanner.z_m) || tilted(scanner.pitch_rad) || tilted(scanner.roll_rad)) return true;
  }
  return false;
}

SimulationConfig ForScanner(const SimulationConfig& config, size_t index) {
  SimulationConfig one = config;
  const SimScanner& scanner = config.scanners.at(index);
  one.mount_x_m = scanner.mount_x_m;
  one.mount_y_m = scanner.mount_y_m;
  one.mount_yaw_rad = scanner.mount_yaw_rad;
  one.mount_z_m = scanner.z_m;
  one.scanner_pitch_rad = std::isnan(scanner.pitch_rad) ? 0.0 : scanner.pitch_rad;
  one.scanner_roll_rad = std::isnan(scanner.roll_rad) ? 0.0 : scanner.roll_rad;
  one.scanner_time_offset_s = scanner.scanner_time_offset_s;
  one.scanner_latency_s = scanner.scanner_latency_s;
  one.range_scale_error = scanner.range_scale_error;
  one.range_offset_error_m = scanner.range_offset_error_m;
  one.scanner_noise_stream = static_cast<uint32_t>(index);
  one.scanners.clear();
  // The site is the vehicle's, not the scanner's: every scanner's run sees the same one.
  if (config.IsThreeDSite() && !one.IsThreeDSite()) one.antenna_height_m = config.AntennaHeightM();
  return one;
}

SimulationConfig ReadSimulationConfig(const std::string& file) {
  SimulationConfig config;
  io::ReadOptionsFile(
      file,
      [&config](io::OptionsMap& top) { ReadKeys(top, config); },
      [&config] { config.Validate(); });
  return config;
}

SimulationConfig ReadTruthYaml(const std::string& file) {
  SimulationConfig config;
  io::ReadOptionsFile(
      file,
      [&config](io::OptionsMap& top) {
        top.RequiredSection("simulation", "the simulation settings",
                            [&config](io::OptionsMap& s) { ReadKeys(s, config); });
        // The truth mount in radians is exact; simulation.mount_yaw_deg went through degrees.
        top.Section("truth", [&config](io::OptionsMap& mount) {
          mount.Number("x", config.mount_x_m);
          mount.Number("y", config.mount_y_m);
          mount.Number("yaw", config.mount_yaw_rad);
          double yaw_deg = 0.0;
          mount.Number("yaw_deg", yaw_deg);
          mount.Number("z", config.mount_z_m);
          mount.Scaled("pitch_deg", config.scanner_pitch_rad, kRadToDeg);
          mount.Scaled("roll_deg", config.scanner_roll_rad, kRadToDeg);
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
  out += "  yaw_deg: " + io::ShortestScaled(config.mount_yaw_rad, kRadToDeg) + "\n";
  // The 3-D mount only when set: a 2-D scenario's truth.yaml has no such keys.
  if (!std::isnan(config.mount_z_m)) {
    out += "  z: " + io::ShortestNumber(config.mount_z_m) + "  # up from the antenna (m)\n";
  }
  if (config.scanner_pitch_rad != 0.0 || config.scanner_roll_rad != 0.0) {
    out += "  pitch_deg: " + io::ShortestScaled(config.scanner_pitch_rad, kRadToDeg) +
           "  # nose up +\n";
    out += "  roll_deg: " + io::ShortestScaled(config.scanner_roll_rad, kRadToDeg) +
           "  # right side down +\n";
  }
  out += "seed: " + std::to_string(seed) + "\n";
  out += "simulation:\n";
  out += simulation.Block(2);
  // The per-stream delays and the characterisation keys only when set: older scenarios'
  // truth.yaml stays as it was.
  for (const auto& [key, value] :
       {std::pair<const char*, double>{"gnss_latency_s", config.gnss_latency_s},
        {"gnss_jitter_s", config.gnss_jitter_s},
        {"heading_latency_s", config.heading_latency_s},
        {"scanner_latency_s", config.scanner_latency_s},
        {"scanner_jitter_s", config.scanner_jitter_s}}) {
    if (value != 0.0) out += std::string("  ") + key + ": " + io::ShortestNumber(value) + "\n";
  }
  if (config.station_distance_far_m != 0.0) {
    out += "  station_distance_far_m: " + io::ShortestNumber(config.station_distance_far_m) + "\n";
  }
  if (config.drive_reverse_m != 0.0) {
    out += "  drive_reverse_m: " + io::ShortestNumber(config.drive_reverse_m) + "\n";
  }
  if (config.weave_turn_rad != 0.0) {
    out += "  weave_turn_deg: " + io::ShortestScaled(config.weave_turn_rad, kRadToDeg) + "\n";
  }
  // The 3-D site's keys, each only when set.
  if (config.yard_grade_pct != 0.0) {
    out += "  yard_grade_pct: " + io::ShortestNumber(config.yard_grade_pct) + "\n";
  }
  if (config.yard_grade_dir_rad != 0.0) {
    out += "  yard_grade_dir_deg: " + io::ShortestScaled(config.yard_grade_dir_rad, kRadToDeg) +
           "\n";
  }
  for (const auto& [key, value] :
       {std::pair<const char*, double>{"antenna_height_m", config.antenna_height_m},
        {"gnss_vertical_factor", config.gnss_vertical_factor},
        {"mount_z_m", config.mount_z_m}}) {
    if (!std::isnan(value)) out += std::string("  ") + key + ": " + io::ShortestNumber(value) + "\n";
  }
  for (const auto& [key, value] :
       {std::pair<const char*, double>{"scanner_pitch_deg", config.scanner_pitch_rad},
        {"scanner_roll_deg", config.scanner_roll_rad}}) {
    if (value != 0.0) {
      out += std::string("  ") + key + ": " + io::ShortestScaled(value, kRadToDeg) + "\n";
    }
  }
  if (!config.write_z_m) out += "  write_z_m: false\n";
  if (config.write_tilt) out += "  write_tilt: true\n";
  if (config.attitude_rate_hz != 0.0) {
    out += "  attitude_rate_hz: " + io::ShortestNumber(config.attitude_rate_hz) + "\n";
    out += "  attitude_white_sigma_deg: " +
           io::ShortestScaled(config.attitude_white_sigma_rad, kRadToDeg) + "\n";
    out += "  attitude_sentence: " + config.attitude_sentence + "\n";
    out += std::string("  attitude_own_log: ") + (config.attitude_own_log ? "true" : "false") +
           "\n";
  }
  if (!config.scanners.empty()) {
    out += "  scanners:\n";
    for (SimScanner& scanner : copy.scanners) {
      io::OptionsText item;
      VisitSimScanner(item, scanner);
      out += "    - " + item.Flow() + "\n";
    }
  }
  if (config.survey_mode == SurveyMode::kRover) {
    out += "  survey_mode: rover\n";
    out += "  rover_sigma_m: " + io::ShortestNumber(config.rover_sigma_m) + "\n";
  }
  // The unit's range model off the preset's correction: the errors applied (drawn ones as the
  // session writer resolved them), each only when set; the draw switch only when on.
  if (config.draw_unit_range_models) out += "  draw_unit_range_models: true\n";
  for (const auto& [key, value] :
       {std::pair<const char*, double>{"range_scale_error", config.range_scale_error},
        {"range_offset_error_m", config.range_offset_error_m}}) {
    if (!std::isnan(value)) {
      out += std::string("  ") + key + ": " + io::ShortestNumber(value) + "\n";
    }
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
