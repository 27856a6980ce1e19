// SPDX-License-Identifier: Apache-2.0
#pragma once
// The rover half of the survey reader: wall points measured directly by an RTK rover, in
// latitude, longitude and ellipsoidal height (docs/survey-files.md, "Rover points").
// Internal to io/.

#include <string>
#include <string_view>
#include <vector>

#include "io/types.h"

namespace wallcal::io {

// True when the first line of `text` (LF line ends) that is neither blank nor a `#` comment
// names a latitude and a longitude column: the file is a rover export, read by
// ParseGeodeticSurveyCsv.
bool LooksLikeGeodeticSurvey(std::string_view text);

// Every point row, in file order, with frame kGeodetic: lat_deg, lon_deg (decimal degrees),
// z_m the ellipsoidal height (m; 0 without a height column) and sigma_m from a precision
// column (m; 0 without one). The delimiter is the header's: a comma, a semicolon (then a
// decimal comma is accepted) or a tab, as io/survey/internal/survey_csv.h splits rows; `text`
// has LF line ends (ParseSurvey makes them so). Throws InputError "name:line: ..." on a header without id, latitude, longitude or code, two columns for one
// quantity, a row with the wrong number of fields, an empty id, a number that is not finite,
// a latitude outside ±90° or a longitude outside ±180°, a precision that is not in (0, 1] m,
// a control character in an id or code, or a file without points.
std::vector<SurveyPoint> ParseGeodeticSurveyCsv(std::string_view text, const std::string& name);

}  // namespace wallcal::io
