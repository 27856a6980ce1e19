// SPDX-License-Identifier: Apache-2.0
#include "io/text/nmea_reader.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string_view>
#include <vector>

#include "common/angles.h"
#include "io/input_file.h"
#include "io/text/internal/gzip_input.h"
#include "io/text/internal/nmea_sentence.h"

namespace wallcal::io {
namespace {

using nmea::ExtractSentence;
using nmea::Fields;
using nmea::kSecondsPerDay;
using nmea::ParseDouble;
using nmea::ParseInt;
using nmea::ParseLatLon;
using nmea::ParseTimeOfDay;
using nmea::SentenceDate;
using nmea::SentenceType;
using nmea::Split;
using nmea::TakePrefix;

namespace fs = std::filesystem;

constexpr size_t kGstMatchWindow = 16;  // GGA/GST pairs are adjacent; a few epochs suffice


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



class NmeaParser {
 public:
  NmeaParser(NmeaLog* log, std::optional<int64_t> first_date)
      : log_(log), first_date_(first_date) {}

  void Line(std::string_view text, int line) {
    const std::optional<double> prefix_s = TakePrefix(&text);
    std::string_view body;
    const char* reason = nullptr;
    SkipSeverity severity = SkipSeverity::kProblem;
    if (!ExtractSentence(text, &body, &reason, &severity)) {
      Skip(reason, line, severity);
      return;
    }
    Split(body, &fields_);
    const std::string_view type = SentenceType(fields_[0]);
    if (type == "GGA") {
      Gga(prefix_s, line);
    } else if (type == "GST") {
      Gst(prefix_s, line);
    } else if (type == "HDT" || type == "THS") {
      Heading(type == "THS", prefix_s, line);
    } else if (type == "RMC" || type == "ZDA") {
      DateAndTime(type, prefix_s);
    } else {
      Skip("other sentence (" + std::string(type) + ")", line, SkipSeverity::kInformational);
    }
  }

  // Points the parser at another log (a copy of the one it filled, NmeaFollower::Log).
  void set_log(NmeaLog* log) { log_ = log; }

  void Finish() {
    for (const PendingGst& gst : pending_gst_) Skip("GST without its GGA", gst.line);
    pending_gst_.clear();
  }

 private:
  struct PendingGst {
    int64_t tod_ms;
    double sigma_lat_m;
    double sigma_lon_m;
    int line;
  };

  void Skip(const std::string& reason, int line, SkipSeverity how = SkipSeverity::kProblem) {
    log_->skipped.Add(reason, line, 1, how);
  }

  bool Field(size_t index, std::string_view* value) const {
    if (index >= fields_.size() || fields_[index].empty()) return false;
    *value = fields_[index];
    return true;
  }

  // The stamp of a sentence with a UTC time of day: the prefix, or date + time of day.
  double Stamp(std::optional<double> prefix_s, double tod_s) {
    const double stamp_s = prefix_s ? *prefix_s : DatedUtc(tod_s);
    last_timed_stamp_s_ = stamp_s;
    return stamp_s;
  }

  // UTC (s since 1970) of a time of day on the date of the last RMC/ZDA (the first date in the
  // file before any), advancing the day across midnight.
  double DatedUtc(double tod_s) {
    if (!day_) {
      day_ = first_date_.value_or(0);
    } else if (tod_s < last_tod_s_ - 0.5 * kSecondsPerDay) {
      ++*day_;  // past midnight before the next date sentence
    } else if (tod_s > last_tod_s_ + 0.5 * kSecondsPerDay) {
      --*day_;  // a late sentence from before midnight
    }
    last_tod_s_ = tod_s;
    return static_cast<double>(*day_) * kSecondsPerDay + tod_s;
  }

  // The epoch's UTC for a sentence that also has a logger stamp: on the log's dates when it has
  // RMC/ZDA, else on the day that puts it nearest the logger stamp (the logger clock is taken
  // to be within 12 h of UTC; calib::MapGnssEpochs checks the difference is consistent).
  double EpochUtc(double prefix_s, double tod_s) {
    if (first_date_) return DatedUtc(tod_s);
    return std::round((prefix_s - tod_s) / kSecondsPerDay) * kSecondsPerDay + tod_s;
  }

  void DateAndTime(std::string_view type, std::optional<double> prefix_s) {
    double tod_s = 0.0;
    const bool timed = fields_.size() > 1 && ParseTimeOfDay(fields_[1], &tod_s);
    if (const std::optional<int64_t> date = SentenceDate(type, fields_); date && timed) {
      day_ = *date;
      last_tod_s_ = tod_s;
    }
    if (timed) Stamp(prefix_s, tod_s);
  }

  void Gga(std::optional<double> prefix_s, int line) {
    std::string_view time, lat, ns, lon, ew, quality, altitude;
    const bool has_position = Field(2, &lat) && Field(3, &ns) && Field(4, &lon) && Field(5, &ew);
    if (!has_position && fields_.size() > 6 && fields_[6] == "0") {
      Skip("GGA without a fix", line);
      return;
    }
    if (!Field(1, &time) || !has_position || !Field(6, &quality) || !Field(9, &altitude)) {
      Skip("empty field", line);
      return;
    }
    GnssFix fix;
    double tod_s = 0.0;
    if (!ParseTimeOfDay(time, &tod_s) || !ParseInt(quality, &fix.quality) ||
        !ParseDouble(altitude, &fix.height_m)) {
      Skip("bad field", line);
      return;
    }
    if (!ParseLatLon(lat, ns, true, &fix.lat_deg) || !ParseLatLon(lon, ew, false, &fix.lon_deg)) {
      Skip("bad field", line);
      return;
    }
    if (std::abs(fix.lat_deg) > 90.0 || std::abs(fix.lon_deg) > 180.0) {
      Skip("lat/lon out of range", line);
      return;
    }
    std::string_view value;
    if (Field(7, &value) && !ParseInt(value, &fix.satellites)) {
      Skip("bad field", line);
      return;
    }
    if (Field(8, &value) && !ParseDouble(value, &fix.hdop)) {
      Skip("bad field", line);
      return;
    }
    double separation_m = 0.0;  // empty: the receiver reports no geoid model
    if (Field(11, &value) && !ParseDouble(value, &separation_m)) {
      Skip("bad field", line);
      return;
    }
    if (fix.satellites < 0 || (std::isfinite(fix.hdop) && fix.hdop < 0.0)) {
      Skip("bad field", line);
      return;
    }
    // An RTK solution (quality 4 or 5) needs at least four satellites; one claiming fewer (or
    // HDOP 0, which no real geometry gives) contradicts itself: counted, and not used. Lower
    // qualities are kept: receivers report 1 with 00 satellites while coasting (gpsd then
    // shows no fix), and min_fix_quality decides their use.
    const bool rtk = fix.quality == 4 || fix.quality == 5;
    if (rtk && Field(7, &value) && fix.satellites < 4) {
      Skip("GGA fix with fewer than 4 satellites", line);
      return;
    }
    if (rtk && Field(8, &value) && fix.hdop == 0.0) {
      Skip("GGA fix with HDOP 0", line);
      return;
    }
    fix.height_m += separation_m;
    if (!std::isfinite(fix.height_m)) {  // two huge finite fields can sum to infinity
      Skip("bad field", line);
      return;
    }
    fix.stamp_s = Stamp(prefix_s, tod_s);
    if (prefix_s) fix.utc_epoch_s = EpochUtc(*prefix_s, tod_s);
    fix.line = line;
    ++log_->fixes_by_quality[fix.quality];
    if (!log_->fixes.empty() && !(fix.stamp_s > log_->fixes.back().stamp_s)) {
      Skip("time not increasing", line);
      return;
    }
    const int64_t tod_ms = std::llround(tod_s * 1000.0);
    for (auto it = pending_gst_.begin(); it != pending_gst_.end(); ++it) {
      if (it->tod_ms == tod_ms) {
        fix.sigma_lat_m = it->sigma_lat_m;
        fix.sigma_lon_m = it->sigma_lon_m;
        pending_gst_.erase(it);
        break;
      }
    }
    log_->fixes.push_back(fix);
    recent_fixes_.push_back({tod_ms, log_->fixes.size() - 1});
    if (recent_fixes_.size() > kGstMatchWindow) recent_fixes_.pop_front();
  }

  void Gst(std::optional<double> prefix_s, int line) {
    std::string_view time, lat, lon;
    if (!Field(1, &time) || !Field(6, &lat) || !Field(7, &lon)) {
      Skip("empty field", line);
      return;
    }
    double tod_s = 0.0;
    PendingGst gst{0, 0.0, 0.0, line};
    if (!ParseTimeOfDay(time, &tod_s) || !ParseDouble(lat, &gst.sigma_lat_m) ||
        !ParseDouble(lon, &gst.sigma_lon_m) || gst.sigma_lat_m < 0.0 || gst.sigma_lon_m < 0.0) {
      Skip("bad field", line);
      return;
    }
    Stamp(prefix_s, tod_s);
    gst.tod_ms = std::llround(tod_s * 1000.0);
    // GST after its GGA: the usual order.
    for (auto it = recent_fixes_.rbegin(); it != recent_fixes_.rend(); ++it) {
      if (it->first != gst.tod_ms) continue;
      GnssFix& fix = log_->fixes[it->second];
      if (std::isnan(fix.sigma_lat_m)) {
        fix.sigma_lat_m = gst.sigma_lat_m;
        fix.sigma_lon_m = gst.sigma_lon_m;
        return;
      }
    }
    // GST before its GGA: wait for it.
    pending_gst_.push_back(gst);
    if (pending_gst_.size() > kGstMatchWindow) {
      Skip("GST without its GGA", pending_gst_.front().line);
      pending_gst_.pop_front();
    }
  }

  void Heading(bool ths, std::optional<double> prefix_s, int line) {
    if (ths) {
      std::string_view status;
      if (!Field(2, &status)) {
        Skip("empty field", line);
        return;
      }
      if (status != "A") {  // E estimated, M manual, S simulator, V invalid
        Skip("THS status " + std::string(status), line);
        return;
      }
    }
    std::string_view value;
    if (!Field(1, &value)) {
      Skip("empty field", line);
      return;
    }
    double heading_deg = 0.0;
    if (!ParseDouble(value, &heading_deg)) {
      Skip("bad field", line);
      return;
    }
    if (heading_deg < 0.0 || heading_deg > 360.0) {
      Skip("heading out of range", line);
      return;
    }
    double stamp_s = 0.0;
    if (prefix_s) {
      stamp_s = *prefix_s;
    } else if (last_timed_stamp_s_) {
      stamp_s = *last_timed_stamp_s_;
    } else {
      Skip("no time yet", line);
      return;
    }
    if (!log_->headings.empty() && !(stamp_s > log_->headings.back().stamp_s)) {
      Skip("time not increasing", line);
      return;
    }
    HeadingSample sample;
    sample.stamp_s = stamp_s;
    sample.heading_rad = heading_deg * kPi / 180.0;
    if (sample.heading_rad >= 2.0 * kPi) sample.heading_rad -= 2.0 * kPi;
    sample.line = line;
    log_->headings.push_back(sample);
  }

  NmeaLog* log_;
  std::optional<int64_t> first_date_;
  std::optional<int64_t> day_;  // days since 1970-01-01 of the sentences being read
  double last_tod_s_ = 0.0;
  std::optional<double> last_timed_stamp_s_;
  Fields fields_;
  std::deque<std::pair<int64_t, size_t>> recent_fixes_;  // (UTC ms of day, index in fixes)
  std::deque<PendingGst> pending_gst_;
};

// Parses one ended line (its text without the line end) as ParseNmea does: numbered, its BOM
// stripped when it is the first.
void ParseLine(std::string_view text, NmeaLog* log, NmeaParser* parser) {
  ++log->lines_read;
  if (log->lines_read == 1) StripUtf8Bom(&text);
  parser->Line(text, static_cast<int>(log->lines_read));
}

// The log as a whole read ends it: a copy of `log` with `last` (a line not yet ended; empty:
// none) parsed and the GSTs still waiting for their GGA counted.
NmeaLog FinishedCopy(const NmeaLog& log, const NmeaParser& parser, std::string_view last) {
  NmeaLog copy = log;
  NmeaParser finishing = parser;
  finishing.set_log(&copy);
  if (!last.empty()) ParseLine(last, &copy, &finishing);
  finishing.Finish();
  return copy;
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
