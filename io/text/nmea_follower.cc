// SPDX-License-Identifier: Apache-2.0
// NMEA logs read on as they grow: a file (NmeaFollower) and lines handed over one at a time
// (NmeaLineFeed), with the whole read's parser (io/text/internal/nmea_parser.h).
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
#include "io/text/nmea_reader.h"

namespace wallcal::io {
namespace {

using nmea::FinishedCopy;
using nmea::NmeaParser;
using nmea::ParseLine;
using nmea::ThrowLineTooLong;

namespace fs = std::filesystem;

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
    ParseLine(text, &log, &parser);
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
  // As ReadNmea reads a last line without its end.
  std::string_view last(s.tail);
  if (!last.empty() && last.back() == '\r') last.remove_suffix(1);
  return FinishedCopy(s.log, *s.parser, last);
}

struct NmeaLineFeed::State {
  std::string name;
  NmeaLog log;
  std::optional<int64_t> first_date;
  std::optional<NmeaParser> parser;  // fills `log`
  std::vector<std::string> undated;  // the lines added before any date (none came yet)
};

NmeaLineFeed::NmeaLineFeed(std::string name) : state_(std::make_unique<State>()) {
  state_->name = std::move(name);
}
NmeaLineFeed::~NmeaLineFeed() = default;
NmeaLineFeed::NmeaLineFeed(NmeaLineFeed&&) noexcept = default;
NmeaLineFeed& NmeaLineFeed::operator=(NmeaLineFeed&&) noexcept = default;

void NmeaLineFeed::Add(std::string_view line) {
  static const int64_t max_line_bytes = CurrentInputLimits().max_line_bytes;
  State& s = *state_;
  if (static_cast<int64_t>(line.size()) > max_line_bytes) {
    ThrowLineTooLong(s.name, s.log.lines_read + 1, max_line_bytes);
  }
  if (!s.first_date) {
    std::string_view text = line;
    if (s.undated.empty()) StripUtf8Bom(&text);
    s.first_date = nmea::LineDate(text);
    if (s.first_date) {
      // ParseNmea dates the plain sentences before the first RMC/ZDA with it.
      s.log = NmeaLog{};
      s.parser.emplace(&s.log, s.first_date);
      for (const std::string& before : s.undated) ParseLine(before, &s.log, &*s.parser);
      s.undated.clear();
      s.undated.shrink_to_fit();
    } else {
      s.undated.emplace_back(line);
    }
  }
  if (!s.parser) s.parser.emplace(&s.log, s.first_date);
  ParseLine(line, &s.log, &*s.parser);
}

NmeaLog NmeaLineFeed::Log() const {
  const State& s = *state_;
  if (!s.parser) return s.log;
  return FinishedCopy(s.log, *s.parser, std::string_view());
}

}  // namespace wallcal::io
