// SPDX-License-Identifier: Apache-2.0
// Reading the YAML files beside session.yaml: scanner presets, calibrate options, simulation
// scenarios and truth.yaml (io/session_reader.h).

#include "io/config/internal/yaml_map_reader.h"

namespace wallcal::io {

using namespace yaml_detail;  // NOLINT: this file's own YAML helpers

ScannerPreset ReadScannerPreset(const std::string& file) {
  const YAML::Node root = LoadYamlStrict(file);
  MapReader top(root, file, "", 1);
  ScannerPreset preset;
  preset.name = fs::path(file).stem().string();
  preset.file = file;
  top.Text("name", preset.name);
  top.Text("source", preset.source);
  preset.num_beams =
      top.ToInteger(top.Require("num_beams", "the number of beams a scan"), "num_beams");
  preset.start_angle_rad =
      top.ToNumber(top.Require("start_angle_deg", "the bearing of beam 0 in degrees"),
                   "start_angle_deg") /
      kRadToDeg;
  preset.angular_step_rad =
      top.ToNumber(top.Require("angular_step_deg", "the step between beams in degrees"),
                   "angular_step_deg") /
      kRadToDeg;
  top.Number("rate_hz", preset.rate_hz);
  top.Number("min_range_m", preset.min_range_m);
  preset.max_range_m =
      top.ToNumber(top.Require("max_range_m", "the maximum range in metres"), "max_range_m");
  top.Number("error_codes_below_m", preset.error_codes_below_m);
  top.Boolean("max_range_is_no_return", preset.max_range_is_no_return);
  top.Number("range_resolution_m", preset.range_resolution_m);
  if (const YAML::Node node = top.Find("range_correction"); node.IsDefined()) {
    MapReader correction = top.Child("range_correction", node);
    correction.Number("k", preset.range_scale_k);
    correction.Number("b_m", preset.range_offset_b_m);
    correction.Finish();
  }
  if (const YAML::Node node = top.Find("range_model_sigma"); node.IsDefined()) {
    MapReader sigma = top.Child("range_model_sigma", node);
    sigma.Number("k", preset.range_scale_sigma);
    sigma.Number("b_m", preset.range_offset_sigma_m);
    sigma.Finish();
  }
  if (const YAML::Node node = top.Find("simulation"); node.IsDefined()) {
    MapReader sim = top.Child("simulation", node);
    sim.Number("n", preset.sim_scale_n);
    sim.Number("c_m", preset.sim_offset_c_m);
    sim.Number("sigma_m", preset.range_sigma_m);
    sim.Finish();
  }
  top.Scaled("max_incidence_deg", preset.max_incidence_rad, kRadToDeg);
  top.Finish();

  auto fail = [&file](const std::string& message) { throw InputError(Where(file, 0, message)); };
  if (preset.num_beams < 2) fail("num_beams must be >= 2, got " + std::to_string(preset.num_beams));
  if (preset.angular_step_rad == 0.0) fail("angular_step_deg must not be 0");
  if (preset.rate_hz < 0.0) fail("rate_hz must be >= 0");
  if (preset.min_range_m < 0.0) fail("min_range_m must be >= 0");
  if (!(preset.max_range_m > preset.min_range_m)) fail("max_range_m must be > min_range_m");
  if (preset.error_codes_below_m < 0.0) fail("error_codes_below_m must be >= 0");
  if (!(preset.range_resolution_m > 0.0)) fail("range_resolution_m must be > 0");
  if (!(preset.range_scale_k > 0.0)) fail("range_correction.k must be > 0");
  if (!(preset.sim_scale_n > 0.0)) fail("simulation.n must be > 0");
  if (!(preset.range_scale_sigma >= 0.0 && preset.range_scale_sigma < 0.1)) {
    fail("range_model_sigma.k must be in [0, 0.1) (a relative scale error)");
  }
  if (!(preset.range_offset_sigma_m >= 0.0 && preset.range_offset_sigma_m < 1.0)) {
    fail("range_model_sigma.b_m must be in [0, 1) m");
  }
  if (preset.range_sigma_m < 0.0) fail("simulation.sigma_m must be >= 0");
  if (!(preset.max_incidence_rad > 0.0 && preset.max_incidence_rad * kRadToDeg <= 90.0)) {
    fail("max_incidence_deg must be in (0, 90]");
  }
  return preset;
}

ScannerPreset LoadScannerPreset(const std::string& model,
                                const std::vector<std::string>& search_dirs) {
  std::error_code ec;
  // A model is a file stem, never a path: "../x" must not escape the preset folders.
  const bool plain_name = !model.empty() && model.find('/') == std::string::npos &&
                          model.find('\\') == std::string::npos && model != "." && model != "..";
  if (plain_name) {
    for (const std::string& dir : search_dirs) {
      const fs::path candidate = fs::path(dir) / (model + ".yaml");
      if (fs::is_regular_file(candidate, ec)) return ReadScannerPreset(candidate.string());
    }
  }
  std::set<std::string> available;
  for (const std::string& dir : search_dirs) {
    if (!fs::is_directory(dir, ec)) continue;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      if (entry.path().extension() == ".yaml") available.insert(entry.path().stem().string());
    }
  }
  const std::string names =
      available.empty() ? "none found"
                        : Join(std::vector<std::string>(available.begin(), available.end()), ", ");
  throw InputError("unknown scanner model '" + model + "'; available presets: " + names +
                   " (searched " + Join(search_dirs, ", ") + ")");
}

TruthMount ReadTruthMount(const std::string& file) {
  TruthMount mount;
  ReadOptionsFile(
      file,
      [&mount](OptionsMap& top) {
        top.RequiredSection("truth", "the true mount {x, y, yaw}", [&mount](OptionsMap& truth) {
          truth.Number("x", mount.x_m);
          truth.Number("y", mount.y_m);
          truth.Number("yaw", mount.yaw_rad);
          truth.AllowOthers();
        });
        top.AllowOthers();
      },
      [] {});
  return mount;
}

std::optional<TruthMount> ReadTruthScannerMount(const std::string& file,
                                                const std::string& scanner_id) {
  struct Entry {
    std::string id;
    TruthMount mount;
  };
  std::vector<Entry> entries;
  ReadOptionsFile(
      file,
      [&entries](OptionsMap& top) {
        top.RequiredSection("simulation", "the simulator's settings", [&entries](OptionsMap& sim) {
          sim.List("scanners", entries, [](OptionsMap& item, Entry& entry) {
            item.Text("id", entry.id);
            item.Number("mount_x_m", entry.mount.x_m);
            item.Number("mount_y_m", entry.mount.y_m);
            item.Scaled("mount_yaw_deg", entry.mount.yaw_rad, kRadToDeg);
            item.AllowOthers();
          });
          sim.AllowOthers();
        });
        top.AllowOthers();
      },
      [] {});
  for (const Entry& entry : entries) {
    if (entry.id == scanner_id) return entry.mount;
  }
  return std::nullopt;
}

}  // namespace wallcal::io
