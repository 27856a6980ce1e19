// SPDX-License-Identifier: Apache-2.0
#include "sim/simulated_session.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "io/config/session_reader.h"
#include "io/writers/writers.h"
#include "io/output_file.h"
#include "io/config/config_writer.h"
#include "pipeline/config_dirs.h"
#include "sim/simulator.h"

namespace wallcal::sim {

namespace fs = std::filesystem;

SimulateSummary WriteSimulatedSession(const sim::SimulationConfig& input_config, uint64_t seed,
                                      const std::string& dir) {
  const sim::SimulationConfig config = WithDefaultWalls(input_config);
  config.Validate();
  const io::ScannerPreset preset = pipeline::LoadSessionPreset(config.scanner_model, dir);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error || !fs::is_directory(dir)) {
    throw io::InputError(dir + ": cannot create the output folder (" + error.message() + ")");
  }
  const fs::path folder(dir);
  const std::string scans_path = (folder / "scans.clf").string();
  const std::string scans_tmp = scans_path + ".tmp-" + std::to_string(::getpid());
  std::ofstream scans(scans_tmp, std::ios::binary | std::ios::trunc);
  if (!scans) throw io::InputError(scans_tmp + ": cannot write");
  scans << "# wallcal simulate: scanner " << preset.name << ", seed " << seed << "\n";
  SimulatedSession sim;
  try {
    sim = Simulate(config, preset, seed, [&scans](const io::ScanRecord& scan) {
      scans << io::FormatCarmenRawlaser(scan) << '\n';
    });
    scans.flush();
    if (!scans) throw io::InputError(scans_tmp + ": write failed (disk full?)");
    scans.close();
  } catch (...) {
    scans.close();
    fs::remove(scans_tmp, error);
    throw;
  }

  std::string gnss_text;
  for (const io::GnssFix& fix : sim.fixes) {
    gnss_text += io::FormatGgaLine(fix) + "\n";
    if (config.write_gst) gnss_text += io::FormatGstLine(fix) + "\n";
  }
  std::string heading_text;
  for (const io::HeadingSample& h : sim.headings) {
    heading_text += io::FormatHdtLine(h.stamp_s, h.heading_rad) + "\n";
  }
  io::SessionSpec spec;
  spec.dir = folder.string();
  spec.file = (folder / "session.yaml").string();
  spec.name = config.name;
  spec.scanner_model = preset.name;
  spec.scanner_log = scans_path;
  spec.gnss_log = (folder / "gnss.nmea").string();
  spec.heading_log = (folder / "heading.nmea").string();
  spec.survey_points = (folder / "survey.csv").string();
  spec.control = sim.control;
  const bool rover = config.survey_mode == sim::SurveyMode::kRover;
  if (rover) spec.survey_point_sigma_m = config.rover_sigma_m;
  spec.walls = sim.walls;
  try {
    io::WriteFileAtomically(spec.gnss_log, gnss_text);
    io::WriteFileAtomically(spec.heading_log, heading_text);
    io::WriteFileAtomically(spec.survey_points, rover ? io::FormatRoverSurveyCsv(sim.survey)
                                                           : io::FormatSurveyCsv(sim.survey));
    io::WriteFileAtomically((folder / "truth.yaml").string(), sim::FormatTruthYaml(config, seed));
    fs::rename(scans_tmp, scans_path);
    // session.yaml last: a folder with a session.yaml is a complete session.
    io::WriteFileAtomically(spec.file, io::FormatSessionYaml(spec));
  } catch (...) {
    fs::remove(scans_tmp, error);
    throw;
  }
  SimulateSummary summary;
  summary.scans_written = sim.scans_written;
  summary.scans_lost = sim.scans_lost;
  summary.fixes = static_cast<int64_t>(sim.fixes.size());
  summary.headings = static_cast<int64_t>(sim.headings.size());
  summary.survey_points = static_cast<int64_t>(sim.survey.size());
  if (!sim.truth_poses.empty()) {
    summary.duration_s = sim.truth_poses.back().stamp_s - sim.truth_poses.front().stamp_s;
  }
  return summary;
}

}  // namespace wallcal::sim
