#pragma once
// Reading the YAML inputs of a session: session.yaml, scanner presets, option files and the
// simulator's configuration / truth. Every key is optional unless said otherwise (defaults come
// from the structs), unknown keys are rejected with their line, and every value is checked.
// YAML keys are the struct field names, except that angles are written in degrees: a field
// `foo_rad` is the key `foo_deg`, `stationary_yaw_rate_rps` is `stationary_yaw_rate_deg_per_s`
// and `heading_drift_rad_per_s` is `heading_drift_deg_per_h`.
//
// Every function throws io::InputError ("file:line: what is wrong; expected ...") on a missing
// file, a YAML syntax error, a missing required key, an unknown key or a bad value.

#include <string>
#include <vector>

#include "io/options.h"
#include "io/types.h"

namespace wallcal::io {

// Reads session.yaml (format: docs/session-format.md, plus the optional extension keys
// `scanner.mount_guess: {x, y, yaw_deg}` and `antenna_in_base: {x, y, z}`).
// `path` is the session.yaml itself or the folder holding it. The log and survey paths are
// resolved against the folder of session.yaml; the files themselves are not opened here (their
// readers report a missing file).
SessionSpec ReadSession(const std::string& path);

// Reads one scanner preset file (configs/scanners/NAME.yaml). `name` defaults to the file stem.
ScannerPreset ReadScannerPreset(const std::string& file);

// Finds `<dir>/<model>.yaml` in the first of `search_dirs` that has it and reads it. An unknown
// model throws InputError listing the presets available in the search dirs.
ScannerPreset LoadScannerPreset(const std::string& model,
                                const std::vector<std::string>& search_dirs);

// Calibrate options: top-level sections `detector:`, `alignment:`, `solver:` and the key
// `first_pass_max_scans`. Validated.
CalibrateOptions ReadCalibrateOptions(const std::string& file);

// A simulation configuration: the SimulationConfig keys at the top level, `walls:` a list of
// {id, code, x0_m, y0_m, x1_m, y1_m, height_m, survey_spacing_m}, `obstacles:` a list of
// {x_m, y_m, radius_m}. Validated.
SimulationConfig ReadSimulationConfig(const std::string& file);

// The `simulation:` section of a truth.yaml written by FormatTruthYaml, with the mount taken from
// its `truth:` section (full precision radians). Other top-level keys of truth.yaml (seed, notes
// a simulator may add) are ignored: truth.yaml is an output document, not a configuration.
SimulationConfig ReadTruthYaml(const std::string& file);

}  // namespace wallcal::io
