// SPDX-License-Identifier: Apache-2.0
#include "sim/simulated_session.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "common/angles.h"
#include "io/config/config_writer.h"
#include "io/config/session_reader.h"
#include "io/output_file.h"
#include "io/writers/writers.h"
#include "pipeline/config_dirs.h"
#include "sim/simulator.h"

namespace wallcal::sim {

namespace fs = std::filesystem;

namespace {

// One logger-stamped line of an NMEA log being assembled.
struct StampedLine {
  double stamp_s;
  std::string text;
};

// The lines in time order (stable: at equal stamps, in the order given), one a line.
std::string InTimeOrder(std::vector<StampedLine> lines) {
  std::stable_sort(lines.begin(), lines.end(), [](const StampedLine& a, const StampedLine& b) {
    return a.stamp_s < b.stamp_s;
  });
  std::string text;
  for (const StampedLine& line : lines) text += line.text + "\n";
  return text;
}

// The attitude sentences of the simulated session, with the heading its heading samples give.
std::vector<StampedLine> AttitudeLines(const SimulationConfig& config,
                                       const SimulatedSession& sim) {
  std::vector<StampedLine> lines;
  for (const io::AttitudeSample& sample : sim.attitudes) {
    const double heading_rad = HeadingAt(sim.headings, sample.stamp_s);
    lines.push_back({sample.stamp_s, config.attitude_sentence == "avr"
                                         ? io::FormatAvrLine(sample, heading_rad)
                                         : io::FormatPashrLine(sample, heading_rad)});
  }
  return lines;
}

}  // namespace

double HeadingAt(const std::vector<io::HeadingSample>& headings, double stamp_s) {
  if (headings.empty()) return io::kNaN;
  const auto after =
      std::upper_bound(headings.begin(), headings.end(), stamp_s,
                       [](double t, const io::HeadingSample& h) { return t < h.stamp_s; });
  if (after == headings.begin()) return headings.front().heading_rad;
  if (after == headings.end()) return headings.back().heading_rad;
  const io::HeadingSample& a = *(after - 1);
  const io::HeadingSample& b = *after;
  const double span_s = b.stamp_s - a.stamp_s;
  const double fraction = span_s > 0.0 ? (stamp_s - a.stamp_s) / span_s : 0.0;
  return WrapTwoPi(a.heading_rad + fraction * WrapAngle(b.heading_rad - a.heading_rad));
}

SimulateSummary WriteSimulatedSession(const sim::SimulationConfig& config, uint64_t seed,
                                      const std::string& dir) {
  return WriteSimulatedSession(config, seed, dir, SimulatedSessionEdit());
}

SimulateSummary WriteSimulatedSession(const sim::SimulationConfig& input_config, uint64_t seed,
                                      const std::string& dir, const SimulatedSessionEdit& edit) {
  const sim::SimulationConfig config = WithDefaultWalls(input_config);
  config.Validate();
  const io::ScannerPreset preset = pipeline::LoadSessionPreset(config.scanner_model, dir);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir)) {
    throw io::InputError(dir + ": cannot create the output folder (" + error.message() + ")");
  }
  const fs::path folder(dir);
  // One scan log per scanner: scans.clf for one scanner, scans_<id>.clf for each of several
  // (each run shares the seed, hence the GNSS, heading and survey draws, and draws its own
  // range noise: SimulationConfig::scanner_noise_stream).
  std::vector<std::pair<sim::SimulationConfig, std::string>> runs;
  if (config.scanners.empty()) {
    runs.emplace_back(config, (folder / "scans.clf").string());
  } else {
    for (size_t k = 0; k < config.scanners.size(); ++k) {
      runs.emplace_back(ForScanner(config, k),
                        (folder / ("scans_" + config.scanners[k].id + ".clf")).string());
    }
  }
  // Each unit's range errors resolved once (drawn ones included), for its run and truth.yaml.
  sim::SimulationConfig truth = config;
  for (size_t k = 0; k < runs.size(); ++k) {
    runs[k].first = UnitRangeErrors(runs[k].first, preset, seed);
    double& scale_error =
        truth.scanners.empty() ? truth.range_scale_error : truth.scanners[k].range_scale_error;
    double& offset_error_m = truth.scanners.empty() ? truth.range_offset_error_m
                                                    : truth.scanners[k].range_offset_error_m;
    scale_error = runs[k].first.range_scale_error;
    offset_error_m = runs[k].first.range_offset_error_m;
  }
  std::vector<std::string> written;  // temporary scan logs, renamed at the end
  const auto remove_written = [&written] {
    std::error_code ignored;
    for (const std::string& tmp : written) fs::remove(tmp, ignored);
  };
  SimulatedSession sim;
  int64_t scans_written = 0, scans_lost = 0, ground_returns = 0;
  for (size_t k = 0; k < runs.size(); ++k) {
    const std::string scans_tmp = runs[k].second + ".tmp-" + std::to_string(::getpid());
    std::ofstream scans(scans_tmp, std::ios::binary | std::ios::trunc);
    if (!scans) {
      remove_written();
      throw io::InputError(scans_tmp + ": cannot write");
    }
    written.push_back(scans_tmp);
    scans << "# wallcal simulate: scanner " << preset.name << ", seed " << seed << "\n";
    try {
      SimulatedSession one = Simulate(runs[k].first, preset, seed, [&scans](const io::ScanRecord& scan) {
        scans << io::FormatCarmenRawlaser(scan) << '\n';
      });
      scans.flush();
      if (!scans) throw io::InputError(scans_tmp + ": write failed (disk full?)");
      scans.close();
      scans_written += one.scans_written;
      scans_lost += one.scans_lost;
      ground_returns += one.ground_returns;
      if (k == 0) sim = std::move(one);
    } catch (...) {
      scans.close();
      remove_written();
      throw;
    }
  }
  const std::string scans_path = runs.front().second;
  if (edit) edit(sim);

  std::string gnss_text;
  for (const io::GnssFix& fix : sim.fixes) {
    gnss_text += io::FormatGgaLine(fix) + "\n";
    if (config.write_gst) gnss_text += io::FormatGstLine(fix) + "\n";
  }
  std::vector<StampedLine> heading_lines;
  for (const io::HeadingSample& h : sim.headings) {
    heading_lines.push_back({h.stamp_s, io::FormatHdtLine(h.stamp_s, h.heading_rad)});
  }
  const bool attitude = !sim.attitudes.empty();
  const bool own_attitude_log = attitude && config.attitude_own_log;
  std::string attitude_text;
  if (own_attitude_log) {
    attitude_text = InTimeOrder(AttitudeLines(config, sim));
  } else if (attitude) {
    for (StampedLine& line : AttitudeLines(config, sim)) heading_lines.push_back(std::move(line));
  }
  const std::string heading_text = InTimeOrder(std::move(heading_lines));
  io::SessionSpec spec;
  spec.dir = folder.string();
  spec.file = (folder / "session.yaml").string();
  spec.name = config.name;
  spec.scanner_model = preset.name;
  spec.scanner_log = scans_path;
  for (const SimScanner& scanner : config.scanners) {
    io::ScannerSpec entry;
    entry.id = scanner.id;
    entry.frame = scanner.id;
    entry.model = preset.name;
    entry.log = (folder / ("scans_" + scanner.id + ".clf")).string();
    // The mount as a drawing gives it (the truth to 0.1 m and 5°): a scanner angled well away
    // from the vehicle's axis needs it to centre the first detection pass.
    io::MountGuess guess;
    guess.x_m = std::round(scanner.mount_x_m * 10.0) / 10.0;
    guess.y_m = std::round(scanner.mount_y_m * 10.0) / 10.0;
    guess.yaw_rad = std::round(scanner.mount_yaw_rad * kRadToDeg / 5.0) * 5.0 / kRadToDeg;
    entry.mount_guess = guess;
    if (config.write_z_m && !std::isnan(scanner.z_m)) entry.z_m = scanner.z_m;
    if (config.write_tilt) {
      entry.tilt.pitch_rad = std::isnan(scanner.pitch_rad) ? 0.0 : scanner.pitch_rad;
      entry.tilt.roll_rad = std::isnan(scanner.roll_rad) ? 0.0 : scanner.roll_rad;
      entry.tilt.given = true;
    }
    spec.scanners.push_back(entry);
  }
  // The scanner's height and tilt as the crew measured them (write_z_m, write_tilt): exact, with
  // the session's default σ.
  if (config.write_z_m && !std::isnan(config.mount_z_m)) spec.scanner_z_m = config.mount_z_m;
  if (config.write_tilt) {
    spec.scanner_tilt.pitch_rad = config.scanner_pitch_rad;
    spec.scanner_tilt.roll_rad = config.scanner_roll_rad;
    spec.scanner_tilt.given = true;
  }
  spec.gnss_log = (folder / "gnss.nmea").string();
  spec.heading_log = (folder / "heading.nmea").string();
  if (attitude) {
    spec.attitude_log = own_attitude_log ? (folder / "attitude.nmea").string() : spec.heading_log;
  }
  spec.survey_points = (folder / "survey.csv").string();
  spec.control = sim.control;
  const bool rover = config.survey_mode == sim::SurveyMode::kRover;
  if (rover) spec.survey_point_sigma_m = config.rover_sigma_m;
  spec.walls = sim.walls;
  try {
    io::WriteFileAtomically(spec.gnss_log, gnss_text);
    io::WriteFileAtomically(spec.heading_log, heading_text);
    if (own_attitude_log) io::WriteFileAtomically(spec.attitude_log, attitude_text);
    io::WriteFileAtomically(spec.survey_points, rover ? io::FormatRoverSurveyCsv(sim.survey)
                                                           : io::FormatSurveyCsv(sim.survey));
    io::WriteFileAtomically((folder / "truth.yaml").string(), sim::FormatTruthYaml(truth, seed));
    for (size_t k = 0; k < runs.size(); ++k) fs::rename(written[k], runs[k].second);
    // session.yaml last: a folder with a session.yaml is a complete session.
    io::WriteFileAtomically(spec.file, io::FormatSessionYaml(spec));
  } catch (...) {
    remove_written();
    throw;
  }
  SimulateSummary summary;
  summary.scans_written = scans_written;
  summary.scans_lost = scans_lost;
  summary.ground_returns = ground_returns;
  summary.fixes = static_cast<int64_t>(sim.fixes.size());
  summary.headings = static_cast<int64_t>(sim.headings.size());
  summary.attitudes = static_cast<int64_t>(sim.attitudes.size());
  summary.survey_points = static_cast<int64_t>(sim.survey.size());
  if (!sim.truth_poses.empty()) {
    summary.duration_s = sim.truth_poses.back().stamp_s - sim.truth_poses.front().stamp_s;
  }
  return summary;
}

}  // namespace wallcal::sim
