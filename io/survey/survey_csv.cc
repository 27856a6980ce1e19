// SPDX-License-Identifier: Apache-2.0
#include "io/survey/internal/survey_csv.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "io/survey/internal/line_splitter.h"
#include "io/internal/decimal.h"

namespace wallcal::io {
namespace {

// The quantities a survey row carries, in the order of kRoles.
enum Role { kId = 0, kEasting, kNorthing, kElevation, kCode, kRoleCount };

// Header names accepted for each role, compared after lower-casing and dropping blanks, '_',
// '-' and '.' ("Point ID", "point_id" and "PointID" are one name; x_m is the dump's x). x is
// east and y north: the survey frame is right-handed with z up (docs/survey-files.md).
const std::vector<HeaderRole> kRoles = {
    {"point id",
     {"id", "point", "pointid", "pointno", "pointnumber", "pointname", "pt", "ptid", "pnt",
      "name"}},
    {"easting", {"x", "xm", "e", "east", "easting"}},
    {"northing", {"y", "ym", "n", "north", "northing"}},
    {"elevation", {"z", "zm", "h", "el", "elev", "elevation", "height", "rl"}},
    {"code", {"code", "description", "desc", "pointcode", "feature", "featurecode"}},
};

// Which column holds each role. Throws when two columns name the same role or one is missing.
std::vector<int> MatchHeader(const std::vector<std::string>& fields, const std::string& name,
                             int line) {
  std::vector<int> columns = MatchHeaderRoles(fields, kRoles, name, line);
  const std::string missing =
      MissingRoles(columns, kRoles, {kId, kEasting, kNorthing, kElevation, kCode});
  if (!missing.empty()) {
    throw InputError(Where(
        name, line,
        "the header's " + std::to_string(fields.size()) + " columns name no " + missing +
            "; expected a header naming the point id (id, point, ...), easting (x, e, easting), "
            "northing (y, n, northing), elevation (z, h, elevation) and code (code, "
            "description) in any order and case (docs/survey-files.md); a file without a "
            "header needs survey.columns: PNEZD or PENZD in session.yaml"));
  }
  return columns;
}

}  // namespace

int HeaderRoleOf(const std::string& field, const std::vector<HeaderRole>& roles) {
  const std::string normal = SurveyHeaderName(field);
  for (size_t role = 0; role < roles.size(); ++role) {
    const std::vector<std::string>& aliases = roles[role].aliases;
    if (std::find(aliases.begin(), aliases.end(), normal) != aliases.end()) {
      return static_cast<int>(role);
    }
  }
  return -1;
}

std::vector<int> MatchHeaderRoles(const std::vector<std::string>& fields,
                                  const std::vector<HeaderRole>& roles, const std::string& name,
                                  int line) {
  std::vector<int> columns(roles.size(), -1);
  for (size_t i = 0; i < fields.size(); ++i) {
    const int role = HeaderRoleOf(fields[i], roles);
    if (role < 0) continue;
    int& column = columns[static_cast<size_t>(role)];
    if (column >= 0) {
      throw InputError(Where(name, line,
                             SurveyColumn(column) + " and " +
                                 SurveyColumn(static_cast<int>(i)) + " both name the " +
                                 roles[static_cast<size_t>(role)].name +
                                 "; expected one column for it"));
    }
    column = static_cast<int>(i);
  }
  return columns;
}

std::string MissingRoles(const std::vector<int>& columns, const std::vector<HeaderRole>& roles,
                         std::initializer_list<int> required) {
  std::string missing;
  for (const int role : required) {
    if (columns[static_cast<size_t>(role)] >= 0) continue;
    missing += std::string(missing.empty() ? "" : ", ") + roles[static_cast<size_t>(role)].name;
  }
  return missing;
}

std::string SurveyColumn(int index) { return "column " + std::to_string(index + 1); }

double SurveyNumber(std::string text, int column, const char* role, bool decimal_comma,
                    const std::string& name, int line, const std::string& expected) {
  const std::string label = SurveyColumn(column) + " (" + role + ")";
  if (decimal_comma) text = WithDecimalPoint(std::move(text));
  if (text.empty()) throw InputError(Where(name, line, label + " is empty; expected " + expected));
  double value = 0.0;
  if (!ParseDecimal(text, &value) || !std::isfinite(value)) {
    throw InputError(Where(name, line,
                           label + " is not a finite number (" + std::to_string(text.size()) +
                               " characters); expected " + expected));
  }
  return value;
}

std::string SurveyPointId(const std::vector<std::string>& fields, int column,
                          const std::string& name, int line) {
  const std::string& id = fields[static_cast<size_t>(column)];
  if (id.empty()) {
    throw InputError(
        Where(name, line, SurveyColumn(column) + " (point id) is empty; expected an id"));
  }
  CheckPrintableField(id, "point id", name, line);
  return id;
}

std::string SurveyHeaderName(const std::string& field) {
  std::string name;
  int depth = 0;  // inside ( ) or [ ]
  for (char c : field) {
    if (c == '(' || c == '[') ++depth;
    if (c == ')' || c == ']') {
      depth = std::max(0, depth - 1);
      continue;
    }
    if (depth > 0) continue;
    if (c == ' ' || c == '\t' || c == '_' || c == '-' || c == '.') continue;
    name += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return name;
}

void CheckPrintableField(const std::string& text, const std::string& what,
                         const std::string& name, int line) {
  for (char c : text) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      throw InputError(Where(name, line,
                             "the " + what + " has a control character; expected printable text"));
    }
  }
}

std::string WithDecimalPoint(std::string text) {
  if (text.find('.') == std::string::npos && std::count(text.begin(), text.end(), ',') == 1) {
    text[text.find(',')] = '.';
  }
  return text;
}

bool IsSurveyCsvHeader(const std::vector<std::string>& fields) {
  try {
    MatchHeader(fields, "", 0);
    return true;
  } catch (const InputError&) {
    return false;  // not a header this reader knows: the caller treats the file as no survey
  }
}

char SurveyCsvDelimiter(std::string_view line) {
  size_t commas = 0, semicolons = 0, tabs = 0;
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    if (quoted) continue;
    commas += c == ',';
    semicolons += c == ';';
    tabs += c == '\t';
  }
  if (semicolons > 0) return ';';
  // A tab-separated row of decimal commas has as many tabs as commas or more.
  if (tabs > 0 && tabs >= commas) return '\t';
  return ',';
}

bool SplitCsvRow(std::string_view row, std::vector<std::string>* fields, char delimiter) {
  fields->clear();
  size_t i = 0;
  // Blanks around a field are dropped, but never the delimiter itself (a tab).
  auto blank = [delimiter](char c) { return c != delimiter && (c == ' ' || c == '\t'); };
  while (true) {
    while (i < row.size() && blank(row[i])) ++i;
    std::string field;
    size_t quoted = 0;  // characters of the field that came from inside quotes: never trimmed
    if (i < row.size() && row[i] == '"') {
      ++i;
      while (true) {
        if (i >= row.size()) return false;
        if (row[i] == '"') {
          if (i + 1 < row.size() && row[i + 1] == '"') {
            field += '"';
            i += 2;
            continue;
          }
          ++i;
          break;
        }
        field += row[i++];
      }
      quoted = field.size();
      while (i < row.size() && row[i] != delimiter) field += row[i++];  // text after the quote
    } else {
      while (i < row.size() && row[i] != delimiter) field += row[i++];
    }
    while (field.size() > quoted && blank(field.back())) field.pop_back();
    fields->push_back(std::move(field));
    if (i >= row.size()) return true;
    ++i;  // the delimiter
  }
}

std::vector<SurveyPoint> ParseSurveyCsv(std::string_view text, const std::string& name,
                                        SurveyColumns columns) {
  std::vector<int> column_of = {-1, -1, -1, -1, -1};
  size_t width = 0;  // fields a row must have (header mode)
  bool have_columns = columns != SurveyColumns::kHeader;
  if (columns == SurveyColumns::kPNEZD) column_of = {0, 2, 1, 3, 4};
  if (columns == SurveyColumns::kPENZD) column_of = {0, 1, 2, 3, 4};
  const char* layout = columns == SurveyColumns::kPNEZD ? "PNEZD" : "PENZD";

  std::vector<SurveyPoint> points;
  std::vector<std::string> fields;
  bool first_row = true;
  char delimiter = 0;  // from the first row (the header, or the first point of a PNEZD file)
  LineSplitter lines(text);
  std::string_view line;
  while (lines.Next(&line)) {
    const int line_number = lines.line_number();
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    size_t first = 0;
    while (first < line.size() && std::isspace(static_cast<unsigned char>(line[first]))) ++first;
    if (first == line.size() || line[first] == '#') continue;

    if (delimiter == 0) delimiter = SurveyCsvDelimiter(line.substr(first));
    if (!SplitCsvRow(line, &fields, delimiter)) {
      throw InputError(Where(name, line_number,
                             "a quoted field is never closed; expected a closing \" on the same "
                             "line"));
    }
    if (!have_columns) {
      column_of = MatchHeader(fields, name, line_number);
      width = fields.size();
      have_columns = true;
      first_row = false;
      continue;
    }
    std::string hint;
    if (columns != SurveyColumns::kHeader) {
      if (fields.size() != 4 && fields.size() != 5) {
        throw InputError(Where(name, line_number,
                               std::to_string(fields.size()) + " fields; expected 5 (" + layout +
                                   ") or 4 (without the description)"));
      }
      if (first_row) {
        hint = std::string(" (survey.columns: ") + layout + " says the file has no header row)";
      }
    } else if (fields.size() != width) {
      throw InputError(Where(name, line_number,
                             std::to_string(fields.size()) + " fields; expected " +
                                 std::to_string(width) + " as in the header"));
    }
    first_row = false;
    SurveyPoint point;
    point.line = line_number;
    point.id = SurveyPointId(fields, column_of[kId], name, line_number);
    const size_t code_column = static_cast<size_t>(column_of[kCode]);
    if (code_column < fields.size()) point.code = fields[code_column];
    CheckPrintableField(point.code, "code", name, line_number);
    // A ';'- or tab-separated file may write "12,345" for 12.345 (European instrument software).
    const auto number = [&](Role role) {
      const int column = column_of[role];
      return SurveyNumber(fields[static_cast<size_t>(column)], column, kRoles[role].name,
                          delimiter != ',', name, line_number, "a number in metres" + hint);
    };
    point.x_m = number(kEasting);
    point.y_m = number(kNorthing);
    point.z_m = number(kElevation);
    points.push_back(std::move(point));
  }
  if (!have_columns) {
    throw InputError(Where(name, 0,
                           "no header; expected a first row naming the columns, like "
                           "Point,Northing,Easting,Elevation,Description"));
  }
  if (points.empty()) throw InputError(Where(name, 0, "no survey points"));
  return points;
}

}  // namespace wallcal::io
