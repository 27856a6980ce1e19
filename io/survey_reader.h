#pragma once
// Total-station export as CSV (SESSION.md): a header row naming the columns (case-insensitive,
// trimmed, any order, extra columns ignored): `id`, `code`, and the coordinates as `x,y,z`,
// `e,n,z` or `easting,northing,elevation` (metres, the station's local right-handed frame).
// Lines starting with `#` and blank lines are skipped; CRLF line ends and a UTF-8 BOM accepted.

#include <istream>
#include <string>
#include <vector>

#include "io/types.h"

namespace wallcal::io {

// Reads all points in file order. Throws InputError (with file:line) on a missing file, no
// header, a missing column, a row with the wrong number of fields, an empty id, a duplicate id,
// a non-numeric or non-finite coordinate, or a file without points.
std::vector<SurveyPoint> ReadSurvey(const std::string& path);

// The same from an open stream; `name` stands for the file in messages (the fuzz target's entry).
std::vector<SurveyPoint> ParseSurvey(std::istream& in, const std::string& name);

}  // namespace wallcal::io
