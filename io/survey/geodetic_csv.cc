// SPDX-License-Identifier: Apache-2.0
#include "io/survey/internal/geodetic_csv.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "io/internal/decimal.h"
#include "io/survey/internal/line_splitter.h"
#include "io/survey/internal/survey_csv.h"

namespace wallcal::io {
namespace {

// The quantities a rover row carries, in the order of kRoles.
enum Role { kId = 0, kLatitude, kLongitude, kHeight, kCode, kSigma, kRoleCount };

// Header names, compared after dropping a bracketed unit ("Latitude (deg)", "H prec [m]"),
// lower-casing and dropping blanks, '_', '-' and '.'. Rover apps name the height above the
// ellipsoid in many ways; an orthometric "Elevation" is not it and is ignored with the other
// extra columns (heights play no part: the scan plane is horizontal).
const std::vector<HeaderRole> kRoles = {
    {"point id",
     {"id", "point", "pointid", "pointno", "pointnumber", "pointname", "pt", "ptid", "name"}},
    {"latitude", {"lat", "latitude", "latdeg", "latitudedeg", "phi"}},
    {"longitude", {"lon", "long", "lng", "longitude", "londeg", "longitudedeg", "lambda"}},
    {"ellipsoidal height",
     {"ellipsoidalheight", "ellipsoidheight", "ellheight", "hell", "hae", "heightellipsoidal",
      "ellipsoidalh", "ellipsoidalht", "ellht", "heightaboveellipsoid"}},
    {"code", {"code", "description", "desc", "pointcode", "feature", "featurecode"}},
    {"precision",
     {"sigma", "sigmam", "sigmah", "hsigma", "hprec", "hprecision", "horizontalprecision",
      "precisionh", "hrms", "horizontalrms", "hacc", "horizontalaccuracy", "haccuracy",
      "sigmahorizontal"}},
};

bool IsContent(std::string_view line) {
  size_t first = 0;
  while (first < line.size() && std::isspace(static_cast<unsigned char>(line[first]))) ++first;
  return first < line.size() && line[first] != '#';
}

}  // namespace

bool LooksLikeGeodeticSurvey(std::string_view text) {
  LineSplitter lines(text);
  std::string_view header;
  while (lines.Next(&header) && !IsContent(header)) {
  }
  if (!IsContent(header)) return false;
  std::vector<std::string> fields;
  if (!SplitCsvRow(header, &fields, SurveyCsvDelimiter(header))) return false;
  bool latitude = false, longitude = false;
  for (const std::string& field : fields) {
    const int role = HeaderRoleOf(field, kRoles);
    latitude = latitude || role == kLatitude;
    longitude = longitude || role == kLongitude;
  }
  return latitude && longitude;
}

std::vector<SurveyPoint> ParseGeodeticSurveyCsv(std::string_view text, const std::string& name) {
  std::vector<int> column_of;
  size_t width = 0;
  char delimiter = ',';
  bool have_header = false;
  std::vector<SurveyPoint> points;
  std::vector<std::string> fields;
  LineSplitter lines(text);
  std::string_view line;
  while (lines.Next(&line)) {
    const int line_number = lines.line_number();
    if (!IsContent(line)) continue;
    if (!have_header) delimiter = SurveyCsvDelimiter(line);
    if (!SplitCsvRow(line, &fields, delimiter)) {
      throw InputError(Where(name, line_number,
                             "a quoted field is never closed; expected a closing \" on the same "
                             "line"));
    }
    if (!have_header) {
      column_of = MatchHeaderRoles(fields, kRoles, name, line_number);
      const std::string missing =
          MissingRoles(column_of, kRoles, {kId, kLatitude, kLongitude, kCode});
      if (!missing.empty()) {
        throw InputError(Where(
            name, line_number,
            "a rover survey's header names no " + missing +
                "; expected the point id (name, id, point), latitude, longitude and code (code, "
                "description), with an optional ellipsoidal height and precision (sigma, "
                "H prec), in any order and case (docs/survey-files.md)"));
      }
      width = fields.size();
      have_header = true;
      continue;
    }
    if (fields.size() != width) {
      throw InputError(Where(name, line_number,
                             std::to_string(fields.size()) + " fields; expected " +
                                 std::to_string(width) + " as in the header"));
    }
    SurveyPoint point;
    point.frame = SurveyFrame::kGeodetic;
    point.line = line_number;
    point.id = SurveyPointId(fields, column_of[kId], name, line_number);
    point.code = fields[static_cast<size_t>(column_of[kCode])];
    CheckPrintableField(point.code, "code", name, line_number);
    // A ';'- or tab-separated export may write decimal commas (European instrument software),
    // as the survey CSV reader takes them.
    const auto number = [&](Role role, const char* expected) {
      const int column = column_of[role];
      return SurveyNumber(fields[static_cast<size_t>(column)], column, kRoles[role].name,
                          delimiter != ',', name, line_number, expected);
    };
    point.lat_deg = number(kLatitude, "decimal degrees, north positive");
    point.lon_deg = number(kLongitude, "decimal degrees, east positive");
    if (std::abs(point.lat_deg) > 90.0) {
      throw InputError(Where(name, line_number,
                             SurveyColumn(column_of[kLatitude]) +
                                 " (latitude) is beyond ±90°; expected decimal degrees, north "
                                 "positive"));
    }
    if (std::abs(point.lon_deg) > 180.0) {
      throw InputError(Where(name, line_number,
                             SurveyColumn(column_of[kLongitude]) +
                                 " (longitude) is beyond ±180°; expected decimal degrees, east "
                                 "positive"));
    }
    if (column_of[kHeight] >= 0) point.z_m = number(kHeight, "metres above the ellipsoid");
    if (column_of[kSigma] >= 0) {
      point.sigma_m = number(kSigma, "the horizontal 1σ in metres, e.g. 0.010");
      if (!(point.sigma_m > 0.0) || point.sigma_m > 1.0) {
        throw InputError(Where(name, line_number,
                               SurveyColumn(column_of[kSigma]) +
                                   " (precision) is not in (0, 1] m; expected the rover's "
                                   "horizontal 1σ in metres, e.g. 0.010"));
      }
    }
    points.push_back(std::move(point));
  }
  if (!have_header) throw InputError(Where(name, 0, "no header; expected a header row"));
  if (points.empty()) throw InputError(Where(name, 0, "no survey points"));
  return points;
}

}  // namespace wallcal::io
