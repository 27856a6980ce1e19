// SPDX-License-Identifier: Apache-2.0
// Recognising a log by its content (SniffLogKind) and the path checks of inspect.
#include <zlib.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "io/input_file.h"
#include "preflight/internal/inspect_internal.h"

namespace wallcal::preflight {

namespace fs = std::filesystem;

namespace internal {

void RequireReadableFile(const std::string& path) {
  std::error_code error;
  if (!fs::exists(path, error)) {
    throw io::InputError(io::Where(path, 0, "no such file; expected a session or a log file"));
  }
  if (fs::is_directory(path, error)) {
    throw io::InputError(io::Where(path, 0, "is a folder without session.yaml"));
  }
  io::CheckInputFile(path, "the log");  // a FIFO or a device is refused before it is opened
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io::InputError(io::Where(path, 0, "cannot open for reading"));
}

}  // namespace internal

namespace {

using internal::RequireReadableFile;

// ---- Sniffing ---------------------------------------------------------------------------

bool IsCarmenKeyword(const std::string& word) {
  static const std::set<std::string> kKeywords = {
      "RAWLASER1", "RAWLASER2", "RAWLASER3", "RAWLASER4", "ROBOTLASER1", "ROBOTLASER2",
      "FLASER",    "RLASER",    "LASER3",    "LASER4",    "PARAM",       "ODOM",
      "TRUEPOS",   "SYNC",      "NEFF"};
  return kKeywords.count(word) > 0;
}

// An NMEA sentence: "$" + talker/type (5 letters or digits) + ",", either at the start of the
// line (after an optional logger time "<seconds> ") or after binary bytes a receiver
// interleaved. A "$GPGGA," quoted inside text (a README) is not a sentence.
bool HasNmeaSentence(const std::string& line) {
  size_t text_start = 0;
  {
    size_t i = 0;
    while (i < line.size() && (std::isdigit(static_cast<unsigned char>(line[i])) || line[i] == '.')) ++i;
    if (i > 0 && i < line.size() && (line[i] == ' ' || line[i] == '\t')) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      text_start = i;
    }
  }
  for (size_t at = line.find('$', text_start); at != std::string::npos; at = line.find('$', at + 1)) {
    if (at + 6 >= line.size()) break;
    bool binary_before = false;
    for (size_t i = text_start; i < at; ++i) {
      const unsigned char c = static_cast<unsigned char>(line[i]);
      binary_before = binary_before || c < 32 || c >= 127;
    }
    if (at != text_start && !binary_before) continue;
    bool ok = true;
    for (size_t i = at + 1; i < at + 6 && ok; ++i) {
      const unsigned char c = static_cast<unsigned char>(line[i]);
      ok = std::isupper(c) || std::isdigit(c);
    }
    if (ok && line[at + 6] == ',') return true;
  }
  return false;
}

}  // namespace

bool IsSessionPath(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) return true;
  const std::string ext = fs::path(path).extension().string();
  return ext == ".yaml" || ext == ".yml";
}

LogKind SniffLogKind(const std::string& path) {
  RequireReadableFile(path);
  // Look at the first 256 KiB only (decompressed when the file is gzip): a binary file without
  // newlines must not be read whole.
  std::string head(256 * 1024, '\0');
  gzFile file = gzopen(path.c_str(), "rb");
  if (file == nullptr) throw io::InputError(io::Where(path, 0, "cannot open"));
  const int got = gzread(file, head.data(), static_cast<unsigned>(head.size()));
  gzclose(file);
  head.resize(got > 0 ? static_cast<size_t>(got) : 0);
  if (head.empty()) throw io::InputError(io::Where(path, 0, "empty file; expected an NMEA or CARMEN log"));
  std::istringstream lines(io::NormaliseLineEnds(std::move(head)));
  std::string line;
  int line_number = 0;
  int first_content_line = 0;
  std::string first_content;
  while (std::getline(lines, line)) {
    ++line_number;
    size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    if (first_content_line == 0) {
      first_content_line = line_number;
      first_content = line.substr(start);
    }
    std::istringstream words(line.substr(start));
    std::string word;
    words >> word;
    if (IsCarmenKeyword(word)) return LogKind::kCarmen;
    if (HasNmeaSentence(line)) return LogKind::kNmea;
  }
  throw io::InputError(io::Where(
      path, first_content_line,
      (first_content_line == 0 ? std::string("only comments and blank lines")
                               : "neither NMEA nor CARMEN (" +
                                     io::DescribeLine(first_content) + ")") +
          "; expected NMEA sentences ($GPGGA,... optionally after a logger time) or CARMEN "
          "lines (RAWLASER1, ROBOTLASER1, FLASER)"));
}

}  // namespace wallcal::preflight
