// SPDX-License-Identifier: Apache-2.0
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

#include <optional>
#include <string>
#include <vector>

#include "io/types.h"

namespace wallcal::io {

// Reads session.yaml (format: docs/session-format.md, plus the optional extension keys
// `scanner.mount_guess: {x, y, yaw_deg}` and `antenna_in_base: {x, y, z}`).
// `path` is the session.yaml itself or the folder holding it. The log and survey paths are
// resolved against the folder of session.yaml; the files themselves are not opened here (their
// readers report a missing file).
// A session may list several scanners (`scanners:`, each with an id); a duplicate id or frame,
// a scanner without a log and two scanners reading the same log or topic are refused, naming
// the scanner.
SessionSpec ReadSession(const std::string& path);

// The one-scanner session of session.scanners[index]: the scanner_* fields set from it,
// `scanners` empty; everything else (GNSS, heading, survey, walls) shared.
SessionSpec SessionForScanner(const SessionSpec& session, size_t index);

// The one-scanner session of the scanner `id` of a `scanners:` session (a command that takes
// one scanner: guide, characterise, inspect --dump scans). Throws io::InputError naming the
// session's scanners when `id` is not one of them, or when the session has no `scanners:`.
SessionSpec SessionForScannerId(const SessionSpec& session, const std::string& id);

// "front_left, front_right": the ids of a `scanners:` session, for messages.
std::string ScannerIds(const SessionSpec& session);

// Reads one scanner preset file (configs/scanners/NAME.yaml). `name` defaults to the file stem.
ScannerPreset ReadScannerPreset(const std::string& file);

// Finds `<dir>/<model>.yaml` in the first of `search_dirs` that has it and reads it. An unknown
// model throws InputError listing the presets available in the search dirs.
ScannerPreset LoadScannerPreset(const std::string& model,
                                const std::vector<std::string>& search_dirs);

// The true mount of a simulated session, from the `truth:` map of its truth.yaml (the other
// keys of that output document are left alone). Throws InputError when the file has no
// `truth:` map of finite x, y, yaw.
struct TruthMount {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
};
TruthMount ReadTruthMount(const std::string& file);

// The true mount of scanner `scanner_id` of a simulated session with several scanners, from its
// entry of truth.yaml's `simulation.scanners` list (mount_x_m, mount_y_m, mount_yaw_deg; the
// top-level `truth:` map is the unused one-scanner mount there). Empty when the list has no
// entry with that id. Throws InputError when the file is not such a document.
std::optional<TruthMount> ReadTruthScannerMount(const std::string& file,
                                                const std::string& scanner_id);

}  // namespace wallcal::io
