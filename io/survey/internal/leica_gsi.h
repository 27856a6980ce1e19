// SPDX-License-Identifier: Apache-2.0
#pragma once
// Leica GSI-8 / GSI-16 survey files (docs/survey-files.md). Word layout (Leica TPS1100 User
// Manual, "Data format"): a two-digit word index (WI), four information characters (the fourth,
// position 6, is the unit digit), a sign, then 8 (GSI-8) or 16 (GSI-16, the line begins with
// '*') data characters and a blank. Words read here:
//   11 point id (leading zeros dropped)    71 point code (remark 1, leading zeros dropped)
//   21 horizontal angle Hz, read as the azimuth (clockwise from the local north, the y axis)
//   22 vertical angle V, a zenith angle     31 slope distance
//   81/82/83 target easting/northing/height (stored coordinates)
//   84/85/86 station easting/northing/height (a set-up), 88 instrument height, 87 reflector height
// Units (position 6): 0 m (last digit 1 mm), 1 ft (1/1000 ft), 6 m (1/10 mm), 7 ft (1/10000 ft),
// 8 m (1/100 mm); 2 gon (5 decimals), 3 degrees (5 decimals), 4 sexagesimal DDD.MMSSs (tenths of
// an arc second), 5 mil of 6400 (4 decimals). Feet are international feet (0.3048 m).
// Every other word (25 orientation, 32/33 reduced distances, 41..49 code blocks, 51 ppm/prism,
// 58/59, 72..79, ...) is passed over without being decoded.

#include <string>
#include <string_view>
#include <vector>

#include "io/types.h"

namespace wallcal::io {

// What a word's value measures: a length (units 0, 1, 6, 7, 8) or an angle (2, 3, 4, 5).
enum class GsiQuantity { kLength, kAngle };

// One word as it stands on its line. `data` points into the line's text.
struct GsiWord {
  int index = 0;          // word index, 0..99
  char unit = 0;          // the unit character (position 6 of the word)
  bool negative = false;  // the sign
  std::string_view data;  // 8 (GSI-8) or 16 (GSI-16) characters
  int number = 0;         // 1-based position of the word on its line, for messages
};

// A line's words. Throws InputError (name:line) for a word cut short, a word without a two-digit
// index or a sign, or a word that runs on past its length (no blank after it).
std::vector<GsiWord> SplitGsiLine(std::string_view line, const std::string& name, int line_number);

// A numeric word's value: metres for a length, radians for an angle (sexagesimal angles are split
// into degrees, minutes, seconds and tenths with integer arithmetic). Throws InputError when the
// unit is not a GSI unit of that quantity, the data are not all digits, or minutes or seconds
// are 60 or more.
double GsiValue(const GsiWord& word, GsiQuantity quantity, const std::string& name,
                int line_number);

// The instrument set-up an observation is reduced from. Before the first set-up in a file the
// instrument stands at the local origin with zero instrument height.
struct GsiSetup {
  double e_m = 0.0;  // station easting (word 84)
  double n_m = 0.0;  // station northing (85)
  double h_m = 0.0;  // station height, the ground mark (86)
  double instrument_height_m = 0.0;  // word 88, the last one read
  int line = 0;                      // line of the set-up (84/85/86); 0: none yet
};

// A polar observation from the set-up to a target.
struct GsiPolar {
  double hz_rad = 0.0;   // word 21: azimuth, clockwise from the local north (y axis)
  double v_rad = 0.0;    // word 22: zenith angle (0 straight up, π/2 level)
  double slope_m = 0.0;  // word 31
  double reflector_height_m = 0.0;  // word 87, the last one read
};

struct GsiPosition {
  double e_m = 0.0;
  double n_m = 0.0;
  double h_m = 0.0;
};

// The target of a polar observation (plane surveying, no earth-curvature or refraction
// correction): horizontal distance d = s·sin V, E = E0 + d·sin Hz, N = N0 + d·cos Hz,
// H = H0 + hi + s·cos V − hr: the radiation (polar) reduction with trigonometric levelling of any
// surveying text, e.g. Ghilani & Wolf, "Elementary Surveying: An Introduction to Geomatics".
GsiPosition ReduceGsiPolar(const GsiSetup& setup, const GsiPolar& polar);

// One line of the file with a point id and a position.
struct GsiRecord {
  std::string id;
  std::string code;  // word 71; empty without it
  int line = 0;
  bool has_coordinates = false;  // words 81/82/83
  GsiPosition coordinates;
  bool has_polar = false;  // words 21/22/31
  GsiPolar polar;
  GsiSetup setup;  // the set-up in effect on this line (after the line's own 87/88)
};

struct GsiFile {
  std::vector<GsiRecord> records;  // file order
  int setups = 0;                  // lines with a set-up (84/85/86)
  int angle_only_lines = 0;  // lines with a point id but no position (angles without a distance)
  int other_lines = 0;       // lines with neither a point id nor a position (code blocks, ...)
  bool gsi16 = false;        // the first word line was GSI-16
};

// True when the line begins as a GSI word does: an optional '*', two digits, four information
// characters (digits or '.'), a sign. How ReadSurvey tells a GSI file from a CSV.
bool LooksLikeGsi(std::string_view line);

// Parses a whole GSI file. Throws InputError (name:line: what, and what was expected, never the
// file's characters) on any malformed word, on coordinates or a set-up missing one of their
// three words, on a slope distance without both angles, on a position without a point id
// (word 11), on a blank or unprintable point id or code, on a word index given twice on a line,
// and on a file without any point.
GsiFile ParseGsi(std::string_view text, const std::string& name);

// The survey points of a parsed file, one per record in file order: the stored coordinates
// (81/82/83) where the line has them (the instrument's own reduction), else the polar reduction.
// x = easting, y = northing, z = height.
std::vector<SurveyPoint> GsiSurveyPoints(const GsiFile& file);

}  // namespace wallcal::io
