// SPDX-License-Identifier: Apache-2.0
#include "io/survey/survey_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <unordered_map>
#include <string_view>

#include "io/text/internal/gzip_input.h"
#include "io/input_file.h"
#include "io/survey/internal/line_splitter.h"
#include "io/survey/internal/geodetic_csv.h"
#include "io/survey/internal/leica_gsi.h"
#include "io/survey/internal/survey_csv.h"

namespace wallcal::io {
namespace {

// The first line that is neither blank nor a CSV comment.
std::string_view FirstContentLine(std::string_view text) {
  LineSplitter lines(text);
  std::string_view line;
  while (lines.Next(&line)) {
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
    if (!line.empty() && line.front() != '#') return line;
  }
  return {};
}

std::string Fixed5(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.5f", value);
  return text;
}

std::string CsvField(const std::string& text) {
  const bool plain = text.find_first_of(",\"") == std::string::npos &&
                     (text.empty() || (text.front() != ' ' && text.back() != ' ' &&
                                       text.front() != '\t' && text.back() != '\t'));
  if (plain) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

double Distance(const SurveyPoint& a, const SurveyPoint& b) {
  return std::sqrt((a.x_m - b.x_m) * (a.x_m - b.x_m) + (a.y_m - b.y_m) * (a.y_m - b.y_m) +
                   (a.z_m - b.z_m) * (a.z_m - b.z_m));
}

std::string Metres(double value_m) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3f m", value_m);
  return text;
}

}  // namespace

std::vector<SurveyPoint> ReadSurvey(const std::string& path, SurveyColumns columns) {
  CheckInputFile(path, "the survey file");  // never a FIFO, a device or a folder
  if (IsGzipFile(path)) {
    GzipStreamBuf buffer(path, kMaxSurveyFileBytes);
    std::istream in(&buffer);
    std::vector<SurveyPoint> points;
    try {
      points = ParseSurvey(in, path, columns);
    } catch (const InputError&) {
      // A damaged stream explains a parse error better than the error itself.
      if (buffer.state() != GzipState::kOk) throw InputError(Where(path, 0, buffer.Problem()));
      throw;
    }
    // A survey is small and exact: a cut-off file would silently lose points.
    if (buffer.state() != GzipState::kOk) throw InputError(Where(path, 0, buffer.Problem()));
    return points;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(Where(path, 0, "cannot open the survey file"));
  return ParseSurvey(in, path, columns);
}

std::vector<SurveyPoint> ParseSurvey(std::istream& in, const std::string& name,
                                     SurveyColumns columns) {
  std::string text;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<size_t>(in.gcount()));
    if (static_cast<int64_t>(text.size()) > kMaxSurveyFileBytes) {
      throw InputError(Where(name, 0,
                             "larger than " + std::to_string(kMaxSurveyFileBytes >> 20) +
                                 " MiB; expected a survey file of at most that size"));
    }
  }
  if (in.bad()) throw InputError(Where(name, 0, "read error"));
  // One line end for the CSV and GSI parsers: CRLF and a CR alone (some instrument downloads)
  // become LF, so every line keeps its number.
  text = NormaliseLineEnds(std::move(text));
  // A rover's export names latitude and longitude; a headerless file has no names.
  std::vector<SurveyPoint> points =
      LooksLikeGsi(FirstContentLine(text)) ? GsiSurveyPoints(ParseGsi(text, name))
      : columns == SurveyColumns::kHeader && LooksLikeGeodeticSurvey(text)
          ? ParseGeodeticSurveyCsv(text, name)
          : ParseSurveyCsv(text, name, columns);
  for (const SurveyPoint& p : points) {
    if (std::abs(p.x_m) > kMaxSurveyCoordinateM || std::abs(p.y_m) > kMaxSurveyCoordinateM ||
        std::abs(p.z_m) > kMaxSurveyCoordinateM) {
      throw InputError(Where(name, p.line,
                             "a coordinate beyond ±1e9 m; expected metres in a local or "
                             "projected frame"));
    }
  }
  return points;
}

SurveyFileKind SniffSurveyFile(const std::string& path) {
  CheckInputFile(path, "the file");
  constexpr size_t kHeadBytes = 64 * 1024;
  std::string head(kHeadBytes, '\0');
  size_t got = 0;
  if (IsGzipFile(path)) {
    GzipStreamBuf buffer(path, kMaxSurveyFileBytes);
    std::istream in(&buffer);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    got = static_cast<size_t>(in.gcount());
  } else {
    std::ifstream in(path, std::ios::binary);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    got = static_cast<size_t>(in.gcount());
  }
  head.resize(got);
  head = NormaliseLineEnds(std::move(head));
  const std::string_view first = FirstContentLine(head);
  SurveyFileKind kind;
  if (first.empty()) return kind;
  if (LooksLikeGsi(first)) {
    kind.format = SurveyFormat::kGsi;
    return kind;
  }
  kind.delimiter = SurveyCsvDelimiter(first);
  std::vector<std::string> fields;
  if (LooksLikeGeodeticSurvey(head)) {
    kind.format = SurveyFormat::kRoverCsv;
  } else if (SplitCsvRow(first, &fields, kind.delimiter) && IsSurveyCsvHeader(fields)) {
    kind.format = SurveyFormat::kCsv;
  }
  return kind;
}

SurveyCombination CombineSurveyObservations(const std::vector<SurveyPoint>& observations,
                                            double tolerance_m) {
  struct Group {
    std::vector<size_t> members;  // indices into observations; the first is the anchor
  };
  // The anchors of one id lie more than tolerance_m apart (a new group starts only when no
  // anchor is within reach), so a grid of cells tolerance_m wide holds a handful of anchors per
  // cell and id: each observation looks at the 27 cells around it, not at every group of its id
  // (a hostile file of a million observations of one id would otherwise take 10^12 steps).
  struct CellKey {
    std::string id;
    int64_t cx, cy, cz;
    bool operator==(const CellKey& o) const {
      return cx == o.cx && cy == o.cy && cz == o.cz && id == o.id;
    }
  };
  struct CellHash {
    size_t operator()(const CellKey& k) const {
      size_t h = std::hash<std::string>()(k.id);
      for (int64_t c : {k.cx, k.cy, k.cz}) h = h * 1000003u ^ std::hash<int64_t>()(c);
      return h;
    }
  };
  const double cell_m = std::max(tolerance_m, 1e-6);
  const auto cell = [cell_m](double v) {  // coordinates are within ±kMaxSurveyCoordinateM
    return static_cast<int64_t>(std::floor(std::clamp(v / cell_m, -4e18, 4e18)));
  };
  std::vector<Group> groups;
  std::unordered_map<CellKey, std::vector<size_t>, CellHash> anchors;
  std::map<std::string, std::vector<size_t>> groups_of_id;
  for (size_t i = 0; i < observations.size(); ++i) {
    const SurveyPoint& p = observations[i];
    const int64_t cx = cell(p.x_m), cy = cell(p.y_m), cz = cell(p.z_m);
    size_t best = groups.size();  // the first (lowest-numbered) group within reach
    CellKey key{p.id, 0, 0, 0};
    for (int64_t dx = -1; dx <= 1; ++dx) {
      for (int64_t dy = -1; dy <= 1; ++dy) {
        for (int64_t dz = -1; dz <= 1; ++dz) {
          key.cx = cx + dx;
          key.cy = cy + dy;
          key.cz = cz + dz;
          const auto found = anchors.find(key);
          if (found == anchors.end()) continue;
          for (size_t g : found->second) {
            if (g < best && Distance(observations[groups[g].members.front()], p) <= tolerance_m) {
              best = g;
            }
          }
        }
      }
    }
    if (best < groups.size()) {
      groups[best].members.push_back(i);
      continue;
    }
    anchors[CellKey{p.id, cx, cy, cz}].push_back(groups.size());
    groups_of_id[p.id].push_back(groups.size());
    groups.push_back({{i}});
  }

  SurveyCombination result;
  for (const Group& group : groups) {
    SurveyPoint point = observations[group.members.front()];
    const double n = static_cast<double>(group.members.size());
    double x = 0.0, y = 0.0, z = 0.0, variance_m2 = 0.0;
    for (size_t i : group.members) {
      x += observations[i].x_m;
      y += observations[i].y_m;
      z += observations[i].z_m;
      variance_m2 += observations[i].sigma_m * observations[i].sigma_m;
    }
    point.x_m = x / n;
    point.y_m = y / n;
    point.z_m = z / n;
    if (point.sigma_m > 0.0) point.sigma_m = std::sqrt(variance_m2) / n;  // σ of the mean
    point.observations = static_cast<int>(group.members.size());
    if (group.members.size() > 1) {
      ++result.repeated_points;
      for (size_t i : group.members) {
        result.max_repeat_spread_m =
            std::max(result.max_repeat_spread_m, Distance(point, observations[i]));
      }
    }
    result.points.push_back(std::move(point));
  }

  // Ids naming several places: counted, with the first example by line numbers.
  std::string example;
  int example_line = std::numeric_limits<int>::max();
  for (const auto& [id, candidates] : groups_of_id) {
    if (candidates.size() < 2) continue;
    ++result.ids_naming_several_places;
    const SurveyPoint& a = observations[groups[candidates[0]].members.front()];
    const SurveyPoint& b = observations[groups[candidates[1]].members.front()];
    if (a.line < example_line) {
      example_line = a.line;
      example = "lines " + std::to_string(a.line) + " and " + std::to_string(b.line) + ", " +
                Metres(Distance(a, b)) + " apart";
    }
  }
  if (result.ids_naming_several_places > 0) {
    result.warnings.push_back(
        std::to_string(result.ids_naming_several_places) +
        " point id(s) name places farther apart than " + Metres(tolerance_m) + " (e.g. " +
        example + "); kept as separate points: a control point needs an id of its own");
  }

  int from_origin = 0, other = 0, first_origin_line = 0;
  for (const SurveyPoint& p : observations) {
    if (p.source == SurveySource::kPolarFromOrigin) {
      if (from_origin++ == 0) first_origin_line = p.line;
    } else {
      ++other;
    }
  }
  if (from_origin > 0 && other > 0) {
    result.warnings.push_back(
        std::to_string(from_origin) +
        " polar observation(s) before the file's first set-up (first at line " +
        std::to_string(first_origin_line) +
        ") were reduced from the local origin, while the other points are stored coordinates or "
        "reduced from a set-up: they may not share a frame");
  }
  return result;
}

std::string FormatSurveyDumpCsv(const std::vector<SurveyPoint>& points) {
  std::string out = "id,x_m,y_m,z_m,code\n";
  for (const SurveyPoint& p : points) {
    out += CsvField(p.id) + "," + Fixed5(p.x_m) + "," + Fixed5(p.y_m) + "," + Fixed5(p.z_m) +
           "," + CsvField(p.code) + "\n";
  }
  return out;
}

}  // namespace wallcal::io
