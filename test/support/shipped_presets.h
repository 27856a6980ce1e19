// SPDX-License-Identifier: Apache-2.0
#pragma once
// The scanner presets as shipped in configs/scanners/, for tests: one definition (the YAML files
// users get) instead of hand-copied numbers, so the tests also exercise the shipped files.

#include <string>

#include "io/config/session_reader.h"
#include "io/types.h"

namespace wallcal::testing_support {

// Loads configs/scanners/<name>.yaml of the source tree (WALLCAL_SOURCE_DIR, set by
// test/CMakeLists.txt). Throws io::InputError if the file is missing or wrong.
inline io::ScannerPreset ShippedPreset(const std::string& name) {
  return io::LoadScannerPreset(name, {std::string(WALLCAL_SOURCE_DIR) + "/configs/scanners"});
}

// configs/simulate/<name>.yaml of the source tree: a shipped simulation scenario.
inline std::string ShippedScenarioPath(const std::string& name) {
  return std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/" + name + ".yaml";
}

}  // namespace wallcal::testing_support
