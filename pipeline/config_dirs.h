// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where the shipped scanner presets and default configs are found. In order:
//   $WALLCAL_CONFIG_DIR (when set and not empty);
//   <program>/../share/wallcal   (an installed program: <prefix>/bin -> <prefix>/share/wallcal);
//   <program>/share/wallcal      (the build tree: build/ holds the programs and a copy of
//                                 configs/ made at build time, build/share/wallcal; test and
//                                 bench programs one folder deeper find it by the first rule).
// Never the source tree: an installed wallcal runs with no source present.

#include <string>
#include <vector>

#include "io/types.h"

namespace wallcal::pipeline {

std::vector<std::string> ConfigDirs();
std::vector<std::string> PresetDirs();  // <config dir>/scanners for each of ConfigDirs()

// The one preset resolution every program uses (calibrate, inspect, inspect --dump, the
// provenance digest, the simulator): <session_dir>/scanners first (characterise writes a measured
// preset there), then PresetDirs(). An empty session_dir: PresetDirs() alone.
std::vector<std::string> SessionPresetDirs(const std::string& session_dir);

// The preset `model` as found by SessionPresetDirs(session_dir); ScannerPreset::file names the
// file read. Throws io::InputError for an unknown model (listing the folders searched) or a bad
// preset file.
io::ScannerPreset LoadSessionPreset(const std::string& model, const std::string& session_dir);

// The path of the file LoadSessionPreset would read, or "" when there is none.
std::string SessionPresetPath(const std::string& model, const std::string& session_dir);

}  // namespace wallcal::pipeline
