// SPDX-License-Identifier: Apache-2.0
#include "io/text/nmea_reader.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string_view>

#include "io/input_file.h"
#include "io/text/internal/gzip_input.h"
#include "io/text/internal/nmea_parser.h"
#include "io/text/internal/nmea_sentence.h"

namespace wallcal::io {

namespace nmea {

void ThrowLineTooLong(const std::string& name, int64_t number, int64_t max_line_bytes) {
  throw InputError(Where(name, static_cast<int>(number),
                         "line longer than " + std::to_string(max_line_bytes) +
                             " bytes; expected NMEA sentences (WALLCAL_MAX_LINE_BYTES raises "
                             "the limit)"));
}

}  // namespace nmea

namespace {

using nmea::NmeaParser;
using nmea::ParseLine;
using nmea::ThrowLineTooLong;

namespace fs = std::filesystem;

std::string_view TrimLineEnd(const std::string& line) {
  std::string_view view(line);
  while (!view.empty() && (view.back() == '\r' || view.back() == '\n')) view.remove_suffix(1);
  return view;
}

// One line of at most WALLCAL_MAX_LINE_BYTES bytes; false at the end of the stream. A longer
// line is an InputError: an NMEA sentence has at most 82 characters, so such a line is no log.
bool NextLine(std::istream& in, std::string* line, const std::string& name, int64_t number) {
  static const int64_t max_line_bytes = CurrentInputLimits().max_line_bytes;
  switch (ReadLineBounded(in, line, max_line_bytes)) {
    case LineRead::kLine:
    case LineRead::kLastLineWithoutNewline:
      return true;
    case LineRead::kEnd:
      return false;
    case LineRead::kTooLong:
      break;
  }
  ThrowLineTooLong(name, number, max_line_bytes);
}

// The first RMC/ZDA date in the file, for plain sentences logged before it.
std::optional<int64_t> FirstDate(std::istream& in, const std::string& name) {
  std::string line;
  int64_t line_number = 0;
  while (NextLine(in, &line, name, ++line_number)) {
    std::string_view text = TrimLineEnd(line);
    if (line_number == 1) StripUtf8Bom(&text);
    if (auto date = nmea::LineDate(text)) return date;
  }
  return std::nullopt;
}

}  // namespace

NmeaLog ReadNmea(const std::string& path) {
  // A FIFO or a device (/dev/zero) is refused before it is read: the log is read twice and a
  // device never ends (docs/session-format.md, "Limits").
  CheckInputFile(path, "the NMEA log");
  if (IsGzipFile(path)) {
    GzipStreamBuf buffer(path, std::min(kMaxGzipNmeaBytes, CurrentInputLimits().max_file_bytes));
    std::istream in(&buffer);
    NmeaLog log = ParseNmea(in, path);
    switch (buffer.state()) {
      case GzipState::kOk:
        break;
      case GzipState::kCutOff:  // as for a CARMEN log: keep what came before the cut, say so
        log.skipped.Add("gzip stream cut off", static_cast<int>(log.lines_read + 1));
        break;
      case GzipState::kCorrupt:
      case GzipState::kTooLarge:
        throw InputError(Where(path, 0, buffer.Problem()));
    }
    return log;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(
        Where(path, 0, std::string("cannot open the NMEA log: ") + std::strerror(errno)));
  }
  return ParseNmea(in, path);
}

NmeaLog ParseNmea(std::istream& in, const std::string& name) {
  const std::optional<int64_t> first_date = FirstDate(in, name);
  if (in.bad()) throw InputError(Where(name, 0, "read error"));
  in.clear();
  in.seekg(0);

  NmeaLog log;
  NmeaParser parser(&log, first_date);
  std::string line;
  while (NextLine(in, &line, name, log.lines_read + 1)) {
    // A byte-order mark would hide the first line's logger-time prefix (and date it 1970).
    ParseLine(TrimLineEnd(line), &log, &parser);
  }
  if (in.bad()) throw InputError(Where(name, 0, "read error"));
  parser.Finish();
  return log;
}

}  // namespace wallcal::io
