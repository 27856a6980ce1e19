// SPDX-License-Identifier: Apache-2.0
#include "sim/simulation_config.h"

#include <utility>

#include "io/config/options_text.h"
#include "io/config/yaml_text.h"

namespace wallcal::sim {
namespace {

using namespace io::option_checks;  // NOLINT: the checks every Validate() makes

// The keys a scenario carries beside VisitSimulationConfig's, and their checks: the per-stream
// delays, the car-like drives, more scanners, the attitude stream and the scanner's true range
// model (NaN: the preset's), which truth.yaml writes only when set (FormatTruthYaml).
template <class V>
void VisitOptionalKeys(V& v, SimulationConfig& c) {
  v.Number("gnss_latency_s", c.gnss_latency_s, io::InRange(0.0, 10.0));
  v.Number("gnss_jitter_s", c.gnss_jitter_s, io::InRange(0.0, 1.0));
  v.Number("heading_latency_s", c.heading_latency_s, io::InRange(0.0, 10.0));
  v.Number("scanner_latency_s", c.scanner_latency_s, io::InRange(0.0, 10.0));
  v.Number("station_distance_far_m", c.station_distance_far_m, io::NonNegative());
  v.Number("drive_reverse_m", c.drive_reverse_m, io::InRange(0.0, 100.0));
  v.Scaled("weave_turn_deg", c.weave_turn_rad, kRadToDeg, io::InRange(0.0, 90.0));
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
    out += "  weave_turn_deg: " + io::ShortestScaled(config.weave_turn_rad, kRadToDeg) + "\n";
  }
  if (config.attitude_rate_hz > 0.0) {
    out += "  attitude_rate_hz: " + io::ShortestNumber(config.attitude_rate_hz) + "\n";
    out += "  attitude_white_sigma_deg: " +
           io::ShortestScaled(config.attitude_white_sigma_rad, kRadToDeg) + "\n";
    out += "  attitude_sentence: " + config.attitude_sentence + "\n";
    out +=
        std::string("  attitude_own_log: ") + (config.attitude_own_log ? "true" : "false") + "\n";
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
