// SPDX-License-Identifier: Apache-2.0
#include "io/text/nmea_reader.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string_view>
#include <vector>

#include "io/input_file.h"
#include "io/text/internal/gzip_input.h"
#include "io/text/internal/nmea_parser.h"
#include "io/text/internal/nmea_sentence.h"

namespace wallcal::io {
namespace {

using nmea::NmeaParser;

namespace fs = std::filesystem;

std::string_view TrimLineEnd(const std::string& line) {
  std::string_view view(line);
  while (!view.empty() && (view.back() == '\r' || view.back() == '\n')) view.remove_suffix(1);
  return view;
}

// One line of at most WALLCAL_MAX_LINE_BYTES bytes; false at the end of the stream. A longer
// line is an InputError: an NMEA sentence has at most 82 characters, so such a line is no log.
[[noreturn]] void ThrowLineTooLong(const std::string& name, int64_t number,
                                   int64_t max_line_bytes) {
  throw InputError(Where(name, static_cast<int>(number),
                         "line longer than " + std::to_string(max_line_bytes) +
                             " bytes; expected NMEA sentences (WALLCAL_MAX_LINE_BYTES raises "
                             "the limit)"));
}

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
    ++log.lines_read;
    std::string_view text = TrimLineEnd(line);
    // A byte-order mark would hide the first line's logger-time prefix (and date it 1970).
    if (log.lines_read == 1) StripUtf8Bom(&text);
    parser.Line(text, static_cast<int>(log.lines_read));
  }
  if (in.bad()) throw InputError(Where(name, 0, "read error"));
  parser.Finish();
  return log;
}

namespace {

// The ended lines of `bytes` (their text without the line end), as ReadLineBounded splits them:
// '\n', "\r\n" or a lone '\r'. Returns where the last line, not yet ended, starts: a '\r' at
// the end of `bytes` may be the first half of a "\r\n" still being written.
template <typename Fn>
size_t ForEachEndedLine(std::string_view bytes, Fn&& fn) {
  size_t start = 0;
  while (true) {
    const size_t end = bytes.find_first_of("\r\n", start);
    if (end == std::string_view::npos) return start;
    size_t next = end + 1;
    if (bytes[end] == '\r') {
      if (next >= bytes.size()) return start;
      if (bytes[next] == '\n') ++next;
    }
    fn(bytes.substr(start, end - start));
    start = next;
  }
}

}  // namespace

struct NmeaFollower::State {
  std::string path;
  bool gzip = false;  // read whole each time: `log` is the whole file's
  NmeaLog log;        // the ended lines'
  std::optional<int64_t> first_date;
  bool dated = false;  // first_date found: it stays the file's first date as the file grows
  std::optional<NmeaParser> parser;  // fills `log`
  int64_t end_byte = 0;              // where the ended lines end: the next read starts there
  std::string tail;                  // the line after them, not yet ended
  int64_t bytes_read = 0;

  void Reset() {
    gzip = false;
    log = NmeaLog{};
    first_date.reset();
    dated = false;
    parser.reset();
    end_byte = 0;
    tail.clear();
    bytes_read = 0;
  }
};

NmeaFollower::NmeaFollower(std::string path) : state_(std::make_unique<State>()) {
  state_->path = std::move(path);
}
NmeaFollower::~NmeaFollower() = default;
NmeaFollower::NmeaFollower(NmeaFollower&&) noexcept = default;
NmeaFollower& NmeaFollower::operator=(NmeaFollower&&) noexcept = default;

const std::string& NmeaFollower::path() const { return state_->path; }
int64_t NmeaFollower::bytes_read() const { return state_->bytes_read; }

int64_t NmeaFollower::ReadMore() {
  State& s = *state_;
  const std::string& path = s.path;
  CheckInputFile(path, "the NMEA log");
  if (IsGzipFile(path)) {
    // Compressed: no byte of the file stands for a line; inflating on from the last one would
    // need zlib's state kept. Read whole, as ReadNmea does.
    s.Reset();
    s.log = ReadNmea(path);
    s.gzip = true;
    s.bytes_read = static_cast<int64_t>(fs::file_size(path));
    return 0;
  }
  if (s.gzip) s.Reset();
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(
        Where(path, 0, std::string("cannot open the NMEA log: ") + std::strerror(errno)));
  }
  const auto read_from = [&in, &path](int64_t from_byte) {
    in.clear();
    in.seekg(from_byte);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw InputError(Where(path, 0, "read error"));
    return bytes;
  };
  in.seekg(0, std::ios::end);
  if (static_cast<int64_t>(in.tellg()) < s.bytes_read) s.Reset();  // a new log under its name
  int64_t from_byte = s.end_byte;
  std::string bytes = read_from(from_byte);

  if (!s.dated) {
    // ParseNmea dates plain sentences before the first RMC/ZDA with it: one arriving now
    // changes the stamps of what was read, which is then read again.
    std::optional<int64_t> date;
    int64_t line = s.log.lines_read;
    const auto date_of = [&date, &line](std::string_view text) {
      if (date) return;
      if (++line == 1) StripUtf8Bom(&text);
      date = nmea::LineDate(text);
    };
    const size_t tail = ForEachEndedLine(bytes, date_of);
    std::string_view last = std::string_view(bytes).substr(tail);
    if (!last.empty() && last.back() == '\r') last.remove_suffix(1);
    if (!last.empty()) date_of(last);
    if (date) {
      if (s.log.lines_read > 0) {
        s.Reset();
        from_byte = 0;
        bytes = read_from(0);
      }
      s.first_date = date;
      s.dated = true;
      s.parser.reset();
    }
  }
  if (!s.parser) s.parser.emplace(&s.log, s.first_date);

  static const int64_t max_line_bytes = CurrentInputLimits().max_line_bytes;
  NmeaLog& log = s.log;
  NmeaParser& parser = *s.parser;
  const size_t tail = ForEachEndedLine(bytes, [&](std::string_view text) {
    if (static_cast<int64_t>(text.size()) > max_line_bytes) {
      ThrowLineTooLong(path, log.lines_read + 1, max_line_bytes);
    }
    ++log.lines_read;
    if (log.lines_read == 1) StripUtf8Bom(&text);
    parser.Line(text, static_cast<int>(log.lines_read));
  });
  s.tail.assign(bytes, tail, std::string::npos);
  const bool tail_ends_in_cr = !s.tail.empty() && s.tail.back() == '\r';
  if (static_cast<int64_t>(s.tail.size()) - (tail_ends_in_cr ? 1 : 0) > max_line_bytes) {
    ThrowLineTooLong(path, log.lines_read + 1, max_line_bytes);
  }
  s.end_byte = from_byte + static_cast<int64_t>(tail);
  s.bytes_read = from_byte + static_cast<int64_t>(bytes.size());
  return from_byte;
}

NmeaLog NmeaFollower::Log() const {
  const State& s = *state_;
  if (s.gzip || !s.parser) return s.log;
  NmeaLog log = s.log;
  NmeaParser parser = *s.parser;
  parser.set_log(&log);
  if (!s.tail.empty()) {
    // As ReadNmea reads a last line without its end.
    std::string_view text(s.tail);
    if (text.back() == '\r') text.remove_suffix(1);
    ++log.lines_read;
    if (log.lines_read == 1) StripUtf8Bom(&text);
    parser.Line(text, static_cast<int>(log.lines_read));
  }
  parser.Finish();
  return log;
}

}  // namespace wallcal::io
