// SPDX-License-Identifier: Apache-2.0
#include "io/text/nmea_reader.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <deque>
#include <fstream>
#include <optional>
#include <string_view>
#include <vector>
#include "common/angles.h"

#include "io/internal/decimal.h"
#include "io/text/internal/gzip_input.h"
#include "io/input_file.h"

namespace wallcal::io {
namespace {
constexpr double kSecondsPerDay = 86400.0;
constexpr size_t kGstMatchWindow = 16;  // GGA/GST pairs are adjacent; a few epochs suffice

using Fields = std::vector<std::string_view>;

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// Finds the sentence in a line: the first '$' whose text up to the next '*' matches the two hex
// digits after it. Receivers interleave binary messages with NMEA, so bytes before a '$' (or a
// '$' inside binary data) are not trusted. On failure *reason says why.
bool ExtractSentence(std::string_view text, std::string_view* body, const char** reason,
                     SkipSeverity* severity = nullptr) {
  *reason = "not NMEA";  // no '$' at all: comments, other protocols
  if (severity != nullptr) *severity = SkipSeverity::kInformational;
  bool saw_checksum = false;
  for (size_t dollar = text.find('$'); dollar != std::string_view::npos;
       dollar = text.find('$', dollar + 1)) {
    const size_t star = text.find('*', dollar + 1);
    if (star == std::string_view::npos || star + 2 >= text.size() || HexValue(text[star + 1]) < 0 ||
        HexValue(text[star + 2]) < 0) {
      if (!saw_checksum) *reason = "no checksum";
      if (severity != nullptr) *severity = SkipSeverity::kProblem;
      continue;
    }
    saw_checksum = true;
    *reason = "bad checksum";
    if (severity != nullptr) *severity = SkipSeverity::kProblem;
    unsigned sum = 0;
    for (size_t i = dollar + 1; i < star; ++i) sum ^= static_cast<unsigned char>(text[i]);
    const unsigned expected =
        static_cast<unsigned>(HexValue(text[star + 1]) * 16 + HexValue(text[star + 2]));
    if (sum == expected) {
      *body = text.substr(dollar + 1, star - dollar - 1);
      return true;
    }
  }
  return false;
}

void Split(std::string_view body, Fields* fields) {
  fields->clear();
  size_t start = 0;
  while (true) {
    const size_t comma = body.find(',', start);
    if (comma == std::string_view::npos) {
      fields->push_back(body.substr(start));
      return;
    }
    fields->push_back(body.substr(start, comma - start));
    start = comma + 1;
  }
}

// "GPGGA" -> "GGA"; proprietary sentences ("PSTI", "PASHR") keep their whole address.
std::string_view SentenceType(std::string_view address) {
  if (!address.empty() && address[0] == 'P') return address;
  return address.size() >= 5 ? address.substr(address.size() - 3) : address;
}

bool ParseDouble(std::string_view token, double* value) {
  return ParseDecimal(token, value) && std::isfinite(*value);
}

bool ParseInt(std::string_view token, int* value) {
  const auto result = std::from_chars(token.data(), token.data() + token.size(), *value);
  return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

bool AllDigits(std::string_view text) {
  for (char c : text) {
    if (c < '0' || c > '9') return false;
  }
  return !text.empty();
}

// hhmmss[.sss] -> seconds of the UTC day.
bool ParseTimeOfDay(std::string_view field, double* tod_s) {
  if (field.size() < 6 || !AllDigits(field.substr(0, 6))) return false;
  const int hours = (field[0] - '0') * 10 + (field[1] - '0');
  const int minutes = (field[2] - '0') * 10 + (field[3] - '0');
  double seconds = 0.0;
  if (!ParseDouble(field.substr(4), &seconds)) return false;
  if (hours > 23 || minutes > 59 || seconds < 0.0 || seconds >= 61.0) return false;
  *tod_s = hours * 3600.0 + minutes * 60.0 + seconds;
  return true;
}

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
int64_t DaysFromCivil(int year, int month, int day) {
  year -= month <= 2 ? 1 : 0;
  const int64_t era = (year >= 0 ? year : year - 399) / 400;
  const int64_t year_of_era = year - era * 400;
  const int64_t day_of_year = (153 * (month + (month > 2 ? -3 : 9)) + 2) / 5 + day - 1;
  const int64_t day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
  return era * 146097 + day_of_era - 719468;
}

bool ValidDate(int year, int month, int day) {
  return year >= 1980 && year <= 2200 && month >= 1 && month <= 12 && day >= 1 && day <= 31;
}

// The date of an RMC (field 9, ddmmyy) or ZDA (fields 2-4: dd, mm, yyyy) sentence.
std::optional<int64_t> SentenceDate(std::string_view type, const Fields& fields) {
  int day = 0, month = 0, year = 0;
  if (type == "RMC") {
    if (fields.size() < 10 || fields[9].size() != 6 || !AllDigits(fields[9])) return std::nullopt;
    const std::string_view d = fields[9];
    day = (d[0] - '0') * 10 + (d[1] - '0');
    month = (d[2] - '0') * 10 + (d[3] - '0');
    const int yy = (d[4] - '0') * 10 + (d[5] - '0');
    year = yy < 80 ? 2000 + yy : 1900 + yy;
  } else if (type == "ZDA") {
    if (fields.size() < 5 || !ParseInt(fields[2], &day) || !ParseInt(fields[3], &month) ||
        !ParseInt(fields[4], &year)) {
      return std::nullopt;
    }
  } else {
    return std::nullopt;
  }
  if (!ValidDate(year, month, day)) return std::nullopt;
  return DaysFromCivil(year, month, day);
}

// Strips the logger-time prefix "<seconds> " if the line has one.
std::optional<double> TakePrefix(std::string_view* line) {
  size_t i = 0;
  while (i < line->size() && (*line)[i] >= '0' && (*line)[i] <= '9') ++i;
  if (i == 0) return std::nullopt;
  if (i < line->size() && (*line)[i] == '.') {
    ++i;
    while (i < line->size() && (*line)[i] >= '0' && (*line)[i] <= '9') ++i;
  }
  if (i >= line->size() || ((*line)[i] != ' ' && (*line)[i] != '\t')) return std::nullopt;
  double stamp_s = 0.0;
  if (!ParseDouble(line->substr(0, i), &stamp_s)) return std::nullopt;
  size_t rest = i;
  while (rest < line->size() && ((*line)[rest] == ' ' || (*line)[rest] == '\t')) ++rest;
  *line = line->substr(rest);
  return stamp_s;
}

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
  throw InputError(Where(name, static_cast<int>(number),
                         "line longer than " + std::to_string(max_line_bytes) +
                             " bytes; expected NMEA sentences (WALLCAL_MAX_LINE_BYTES raises "
                             "the limit)"));
}

// The first RMC/ZDA date in the file, for plain sentences logged before it.
std::optional<int64_t> FirstDate(std::istream& in, const std::string& name) {
  std::string line;
  Fields fields;
  int64_t line_number = 0;
  while (NextLine(in, &line, name, ++line_number)) {
    std::string_view text = TrimLineEnd(line);
    if (line_number == 1) StripUtf8Bom(&text);
    TakePrefix(&text);
    std::string_view body;
    const char* reason = nullptr;
    if (!ExtractSentence(text, &body, &reason)) continue;
    Split(body, &fields);
    if (auto date = SentenceDate(SentenceType(fields[0]), fields)) return date;
  }
  return std::nullopt;
}

// Latitude "ddmm.mmmm" + hemisphere -> degrees; false if malformed or out of range.
bool ParseLatLon(std::string_view value, std::string_view hemisphere, bool latitude, double* deg) {
  double raw = 0.0;
  if (!ParseDouble(value, &raw) || raw < 0.0) return false;
  const double whole_deg = std::floor(raw / 100.0);
  const double minutes = raw - whole_deg * 100.0;
  if (minutes >= 60.0) return false;
  double angle = whole_deg + minutes / 60.0;
  if (hemisphere.size() != 1) return false;
  const char h = hemisphere[0];
  if (latitude ? (h != 'N' && h != 'S') : (h != 'E' && h != 'W')) return false;
  if (h == 'S' || h == 'W') angle = -angle;
  *deg = angle;
  return true;
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

}  // namespace wallcal::io
