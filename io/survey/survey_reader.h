// SPDX-License-Identifier: Apache-2.0
#pragma once
// Survey files (docs/survey-files.md): a surveyor's CSV, a Leica GSI-8/GSI-16 job or an RTK
// rover's CSV in latitude and longitude, each plain or gzip-compressed. The kind is recognised
// by content: a file whose first line begins as a GSI word does is GSI, a header naming a
// latitude and a longitude column is a rover's (io/survey/internal/geodetic_csv.h: points of
// frame SurveyFrame::kGeodetic), anything else CSV; gzip by its first bytes, whatever the name.
//
// CSV: a header row naming the columns, in any order and case, extra columns ignored (names
// accepted: docs/survey-files.md; e.g. Point,Northing,Easting,Elevation,Description or
// id,x,y,z,code, where x is east and y north), or no header with `survey.columns: PNEZD` or
// `PENZD` (point, northing/easting, elevation, optional description). Fields may be quoted.
// Header names may carry a unit in brackets (`Northing (m)`). Fields are separated by commas,
// or by semicolons or tabs (from the first row), and then a number may have a decimal comma.
// Lines starting with `#` and blank lines are skipped; LF, CRLF and CR-only line ends and a
// UTF-8 BOM are accepted.
//
// GSI: io/leica_gsi.h. The survey frame is the file's own local one: x east, y north, z up
// (right-handed), in metres.
//
// The reader returns one point per observation, in file order: a point measured twice (two
// faces, two set-ups, a repeated row) is two entries with the same id. CombineSurveyObservations
// makes one point of each place for the calibration.

#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include "io/types.h"

namespace wallcal::io {

// Largest survey file (uncompressed): 64 MiB, about a million points. Bounds memory on hostile
// input: the file is read whole before parsing.
inline constexpr int64_t kMaxSurveyFileBytes = int64_t{64} << 20;

// Largest coordinate magnitude accepted (1e9 m): far beyond any local or projected frame (UTM
// northings stay below 1e7 m); larger values are a unit or format error.
inline constexpr double kMaxSurveyCoordinateM = 1e9;

// Observations of one id within this distance (3-D) of the first of them are one point,
// measured again (faces I/II, a second set-up); farther apart, the id names different points.
inline constexpr double kSurveyRepeatToleranceM = 0.03;

// Reads every observation in file order. `columns` applies to a CSV without a header; a GSI
// file is recognised by its content whatever `columns` says. Throws InputError (with file:line,
// describing what was found in words, never quoting the file) on a missing file, corrupt or
// cut-off gzip data, a file larger than kMaxSurveyFileBytes, an unrecognised or ambiguous
// header, a row with the wrong number of fields, an empty id, a non-numeric or non-finite
// coordinate or one beyond kMaxSurveyCoordinateM, a control character in an id or code, any
// malformed GSI line (io/leica_gsi.h), or a file without points.
std::vector<SurveyPoint> ReadSurvey(const std::string& path,
                                    SurveyColumns columns = SurveyColumns::kHeader);

// The same from an open stream (plain text; ReadSurvey inflates gzip before this); `name` stands
// for the file in messages (the fuzz targets' entry).
std::vector<SurveyPoint> ParseSurvey(std::istream& in, const std::string& name,
                                     SurveyColumns columns = SurveyColumns::kHeader);

// What a file is as a survey, from its first content line (`inspect FILE` picks its summary by
// it): a GSI job, a CSV whose first row is a header the reader accepts, a rover's CSV (its
// header names a latitude and a longitude), or neither (kNone; a header-less CSV needs
// survey.columns and so is kNone here). delimiter: the CSV's (',', ';' or
// a tab). Reads at most the first 64 KiB (inflated when gzip). Throws InputError only when the
// path is no readable regular file.
enum class SurveyFormat { kNone, kCsv, kRoverCsv, kGsi };
struct SurveyFileKind {
  SurveyFormat format = SurveyFormat::kNone;
  char delimiter = ',';
};
SurveyFileKind SniffSurveyFile(const std::string& path);

// One point per place, for the calibration (docs/survey-files.md, "Repeated observations").
struct SurveyCombination {
  // One point per place, in the order of each place's first observation: the mean of its
  // observations, `observations` set to their count, `line` and `source` of the first, sigma_m
  // (when the observations carry one) the σ of their mean.
  std::vector<SurveyPoint> points;
  int repeated_points = 0;         // points averaged from two or more observations
  double max_repeat_spread_m = 0;  // largest distance of an averaged observation from its mean
  int ids_naming_several_places = 0;  // ids whose observations are farther apart than the
                                      // tolerance: kept as separate points with the same id
  // For people (they name lines, not ids): ids naming several places, and polar observations
  // reduced from the local origin in a file whose other points are in another frame.
  std::vector<std::string> warnings;
};

// Groups observations by id: each observation joins the first group of its id whose first
// observation lies within tolerance_m (3-D; > 0), or starts a new group. Every group becomes one
// point. Linear time in the number of observations.
SurveyCombination CombineSurveyObservations(const std::vector<SurveyPoint>& observations,
                                            double tolerance_m = kSurveyRepeatToleranceM);

// `inspect --dump survey`: the header `id,x_m,y_m,z_m,code` and one row per point, coordinates
// in metres with 5 decimals (x east, y north, z up); an id or code holding a comma, a quote or
// outer blanks is quoted as CSV does. ReadSurvey reads the output back.
std::string FormatSurveyDumpCsv(const std::vector<SurveyPoint>& points);

}  // namespace wallcal::io
