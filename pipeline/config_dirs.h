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

namespace wallcal::pipeline {

std::vector<std::string> ConfigDirs();
std::vector<std::string> PresetDirs();  // <config dir>/scanners for each of ConfigDirs()

}  // namespace wallcal::pipeline
