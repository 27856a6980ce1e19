// SPDX-License-Identifier: Apache-2.0
// wallcal simulate: write a synthetic wall-calibration session with known truth (truth.yaml).

#include <cstdint>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>

#include "apps/commands.h"
#include "sim/recording_session.h"
#include "sim/simulated_session.h"
#include "io/config/session_reader.h"

namespace wallcal::apps {

const CommandHelp& SimulateHelp() {
  static const CommandHelp help{
      "simulate",
      "write a synthetic wall session with a known mount (truth.yaml)",
      {"[--config FILE] [--seed N] [--format F] --output DIR"},
      "Writes a synthetic session folder in the format calibrate reads (session.yaml, scans.clf,\n"
      "gnss.nmea, heading.nmea, survey.csv) plus truth.yaml: the true mount and every noise setting\n"
      "used. The vehicle stops at several headings in front of a surveyed wall and drives between\n"
      "them; ranges follow the scanner preset's error model (Ye & Borenstein 2002; Okubo, Ye &\n"
      "Borenstein 2009), GNSS has time-correlated RTK noise, heading a FOG-class drift, the survey\n"
      "total-station noise.\n",
      {
          {"--config", "", "FILE", ValueKind::kFile, {},
           "simulation settings (YAML; examples in configs/simulate/; default: built-in)"},
          {"--seed", "", "N", ValueKind::kWord, {},
           "random seed (default 1); the same config and seed give the same files"},
          {"--output", "", "DIR", ValueKind::kFolder, {},
           "the session folder to write (created if missing; files in it are replaced)"},
          {"--format", "", "F", ValueKind::kChoice,
           {"text", "ros1", "ros1-bz2", "ros1-lz4", "mcap", "mcap-lz4", "db3"},
           "how the scans, GNSS and heading are written (default text):\n"
           "  text       scans.clf (CARMEN), gnss.nmea, heading.nmea\n"
           "  ros1       session.bag, ROS 1 bag v2.0 (ros1-bz2, ros1-lz4: compressed chunks)\n"
           "  mcap       session.mcap, ROS 2 MCAP with zstd chunks (mcap-lz4: lz4)\n"
           "  db3        session.db3, rosbag2 sqlite3 (Iron layout)\n"
           "recordings hold /scan (sensor_msgs/LaserScan), /fix (sensor_msgs/NavSatFix\n"
           "with the simulated σ as covariance) and /heading\n"
           "(geometry_msgs/QuaternionStamped); session.yaml names them.\n"
           "A config with `scanners:` (several scanners, e.g.\n"
           "configs/simulate/two_corner_scanners.yaml) writes one scan log per scanner,\n"
           "scans_ID.clf, or topic /ID/scan in a recording, and a scanners: session"},
          HelpOption(),
          VersionOption(),
      },
      "",
      "0 written; 2 bad input or usage; 3 an internal error (a bug: please report it).\n"};
  return help;
}

}  // namespace wallcal::apps

int wallcal::apps::RunSimulate(int argc, char** argv) {
  std::string config_path, output;
  uint64_t seed = 1;
  wallcal::sim::SessionFormat format = wallcal::sim::SessionFormat::kText;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (wallcal::apps::PrintHelpOrVersion(arg, wallcal::apps::SimulateHelp(), std::cout)) {
      return 0;
    } else if (arg == "--config" || arg == "--seed" || arg == "--output" || arg == "--format") {
      if (i + 1 >= argc) return UsageError(SimulateHelp(), arg + " needs a value");
      const std::string v = argv[++i];
      if (arg == "--format") {
        const auto parsed = wallcal::sim::ParseSessionFormat(v);
        if (!parsed) {
          return UsageError(SimulateHelp(), "--format: unknown format '" + v +
                                                "'; expected one of " +
                                                wallcal::sim::SessionFormatNames());
        }
        format = *parsed;
      } else if (arg == "--config") {
        config_path = v;
      } else if (arg == "--output") {
        output = v;
      } else {
        char* end = nullptr;
        const unsigned long long parsed = std::strtoull(v.c_str(), &end, 10);
        if (v.empty() || *end != '\0' || v[0] == '-') {
          return UsageError(SimulateHelp(),
                            "--seed: '" + v + "' is not a non-negative whole number");
        }
        seed = parsed;
      }
    } else {
      return UsageError(SimulateHelp(), "unknown argument '" + arg + "'");
    }
  }
  if (output.empty()) return UsageError(SimulateHelp(), "--output DIR is required");
  return wallcal::apps::ExitStatusOf(SimulateHelp(), [&] {
    wallcal::sim::SimulationConfig config;
    if (!config_path.empty()) config = wallcal::sim::ReadSimulationConfig(config_path);
    const wallcal::sim::SimulateSummary s = wallcal::sim::WriteSimulatedSession(config, seed, output, format);
    std::cout << "simulate: wrote " << output << ": " << s.scans_written << " scans ("
              << s.scans_lost << " lost), " << s.fixes << " GNSS fixes, " << s.headings
              << " headings, "
              << (s.attitudes > 0 ? std::to_string(s.attitudes) + " attitude samples, " : "")
              << s.survey_points << " survey points, " << s.duration_s << " s of driving";
    if (s.ground_returns > 0) std::cout << "; " << s.ground_returns << " beams saw the ground";
    std::cout << "\n";
    return 0;
  });
}
