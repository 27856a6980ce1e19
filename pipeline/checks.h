// SPDX-License-Identifier: Apache-2.0
#pragma once
// Checks that catch a user's mistakes before (or right after) the estimate, and name the cause:
// a scanner preset that does not fit the data, a survey that cannot be where the GNSS track is,
// an estimate far from the tape-measured guess. Internal to pipeline/ (and preflight/, which
// reports the same findings). Each throws io::InputError ("file: what is wrong; what to check")
// for bad input, or says what it found in a typed result.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/observation.h"
#include "io/scan_source.h"
#include "io/types.h"
#include "pipeline/run_warnings.h"

namespace wallcal::pipeline {

// The first scans of the log against the preset: beam count, angular step, and readings beyond
// the preset's maximum range (that are not the log's own no-return value).
struct PresetFit {
  int64_t scans_checked = 0;
  int beams_in_log = 0;             // the most common beam count
  double step_in_log_rad = 0.0;     // the angular step of the first scan with that count
  double longest_range_m = 0.0;     // the longest reading below the log's no-return value
  int64_t beyond_preset_max = 0;    // readings longer than the preset allows
  int64_t readings = 0;             // valid readings examined
  std::vector<std::string> problems;  // one line per mismatch, naming both sides
  // The scanner geometry the scans carry where it differs from the preset's within the
  // family's limits (io/scanner_geometry.h), for the summary; empty when as the preset.
  std::string taken_from_data;
};

// Reads up to `max_scans` scans from `open_scans()`.
PresetFit CheckPresetAgainstScans(const std::function<std::unique_ptr<io::ScanSource>()>& open_scans,
                                  const io::ScannerPreset& preset, int64_t max_scans = 500);

// A mismatch throws io::InputError naming the preset, the session file and the data, unless
// `force` (then each problem is appended to `warnings`).
void EnforcePresetFit(const PresetFit& fit, const io::ScannerPreset& preset,
                      const io::SessionSpec& session, bool force,
                      Warnings* warnings);

// With 3 or more control points: fits the survey onto the control points' RTK positions (in
// `frame`) by a rotation and by a reflection; throws io::InputError when the reflection fits
// clearly better (a mirrored survey: x and y, or easting and northing, swapped).
void CheckSurveyNotMirrored(const std::vector<io::SurveyPoint>& survey,
                            const io::SessionSpec& session, const calib::LocalFrame& frame);

// The shortest distance (m) from any point of the track to any surveyed wall (as a segment).
double TrackToWallsDistance(const std::vector<Eigen::Vector2d>& track_local_m,
                            const std::vector<calib::WallGeometry>& walls);

// Throws io::InputError when the track never comes within the scanner's range (plus 20 m) of
// a surveyed wall: the survey or its control points are not where the vehicle drove.
void CheckTrackNearWalls(const std::vector<Eigen::Vector2d>& track_local_m,
                         const std::vector<calib::WallGeometry>& walls,
                         const io::ScannerPreset& preset, const io::SessionSpec& session);

// The estimate against scanner.mount_guess and its tolerances: empty when within (or when no
// tolerance is given), else one line naming the estimate, the guess and the tolerance.
std::string CheckMountGuess(const io::MountGuess& guess, const calib::Mount& estimate);

}  // namespace wallcal::pipeline
