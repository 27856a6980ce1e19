#include "io/survey_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <set>
#include <string_view>

namespace wallcal::io {
namespace {

std::string Trim(std::string_view text) {
  size_t begin = 0;
  size_t end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  std::string trimmed(text.substr(begin, end - begin));
  // Spreadsheet exports may quote every field.
  if (trimmed.size() >= 2 && trimmed.front() == '"' && trimmed.back() == '"') {
    trimmed = trimmed.substr(1, trimmed.size() - 2);
  }
  return trimmed;
}

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    fields.push_back(Trim(std::string_view(line).substr(
        start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string text;
  for (size_t i = 0; i < names.size(); ++i) text += (i > 0 ? ", " : "") + names[i];
  return text;
}

// Column index of the first header name in `aliases`; -1 if none; throws if two aliases of the
// same quantity are both present (which one would be meant?).
int FindColumn(const std::vector<std::string>& header, const std::vector<std::string>& aliases,
               const std::string& path, int line) {
  int found = -1;
  for (size_t i = 0; i < header.size(); ++i) {
    if (std::find(aliases.begin(), aliases.end(), header[i]) == aliases.end()) continue;
    if (found >= 0) {
      throw InputError(Where(path, line,
                             "columns '" + header[static_cast<size_t>(found)] + "' and '" +
                                 header[i] + "' both give the same coordinate; expected one"));
    }
    found = static_cast<int>(i);
  }
  return found;
}

}  // namespace

std::vector<SurveyPoint> ReadSurvey(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(Where(path, 0, "cannot open the survey CSV"));
  return ParseSurvey(in, path);
}

std::vector<SurveyPoint> ParseSurvey(std::istream& in, const std::string& path) {

  std::vector<std::string> header;
  int id_col = -1, code_col = -1, x_col = -1, y_col = -1, z_col = -1;
  std::vector<SurveyPoint> points;
  std::set<std::string> ids;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line_number == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);  // BOM
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#') continue;

    std::vector<std::string> fields = SplitCsv(line);
    if (header.empty()) {
      for (std::string& name : fields) header.push_back(Lower(name));
      id_col = FindColumn(header, {"id"}, path, line_number);
      code_col = FindColumn(header, {"code"}, path, line_number);
      x_col = FindColumn(header, {"x", "e", "easting"}, path, line_number);
      y_col = FindColumn(header, {"y", "n", "northing"}, path, line_number);
      z_col = FindColumn(header, {"z", "elevation"}, path, line_number);
      if (id_col < 0 || code_col < 0 || x_col < 0 || y_col < 0 || z_col < 0) {
        throw InputError(
            Where(path, line_number,
                  "header has the columns " + JoinNames(header) +
                      "; expected id, code and x,y,z (or e,n,z, or easting,northing,elevation)"));
      }
      continue;
    }
    if (fields.size() != header.size()) {
      throw InputError(Where(path, line_number,
                             std::to_string(fields.size()) + " fields; expected " +
                                 std::to_string(header.size()) + " as in the header"));
    }
    SurveyPoint point;
    point.line = line_number;
    point.id = fields[static_cast<size_t>(id_col)];
    point.code = fields[static_cast<size_t>(code_col)];
    if (point.id.empty())
      throw InputError(Where(path, line_number, "empty id; expected a point id"));
    const std::pair<int, double*> coordinates[] = {
        {x_col, &point.x_m}, {y_col, &point.y_m}, {z_col, &point.z_m}};
    for (const auto& [column, value] : coordinates) {
      const std::string& text = fields[static_cast<size_t>(column)];
      const char* begin = text.data();
      const char* end = begin + text.size();
      if (begin < end && *begin == '+') ++begin;
      const auto result = std::from_chars(begin, end, *value);
      if (text.empty() || result.ec != std::errc() || result.ptr != end || !std::isfinite(*value)) {
        throw InputError(Where(path, line_number,
                               "column '" + header[static_cast<size_t>(column)] + "' is '" + text +
                                   "'; expected a finite number in metres"));
      }
    }
    if (!ids.insert(point.id).second) {
      throw InputError(
          Where(path, line_number, "duplicate id '" + point.id + "'; expected unique point ids"));
    }
    points.push_back(std::move(point));
  }
  if (in.bad()) throw InputError(Where(path, 0, "read error"));
  if (header.empty()) {
    throw InputError(Where(path, 0,
                           "no header; expected a first row naming the columns, like "
                           "id,x,y,z,code"));
  }
  if (points.empty()) throw InputError(Where(path, 0, "no survey points after the header"));
  return points;
}

}  // namespace wallcal::io
