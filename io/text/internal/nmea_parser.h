// SPDX-License-Identifier: Apache-2.0
#pragma once
// The NMEA reader's parser (io/text/nmea_reader.h): the state carried from one line to the next
// (the date of plain sentences, the GSTs waiting for their GGA, the last stamps of the "time not
// increasing" check) and what each sentence adds to an NmeaLog. Shared by the whole read
// (nmea_reader.cc) and the readers on (nmea_follower.cc). Private to io/.

#include <cmath>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "common/angles.h"
#include "io/input_file.h"
#include "io/text/internal/nmea_attitude.h"
#include "io/text/internal/nmea_sentence.h"
#include "io/types.h"

namespace wallcal::io::nmea {

inline constexpr size_t kGstMatchWindow = 16;  // GGA/GST pairs are adjacent; a few epochs suffice

// Throws the InputError of a line longer than `max_line_bytes` (line `number` of `name`).
[[noreturn]] void ThrowLineTooLong(const std::string& name, int64_t number,
                                   int64_t max_line_bytes);

// Adds what each line holds to an NmeaLog (the sentences and skips of io/text/nmea_reader.h).
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
    } else if (type == "PASHR" || type == "PTNL") {
      Attitude(type, prefix_s, line);
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

  // $PASHR and $PTNL,AVR: stamped as a heading is (the logger prefix when the line has one), or
  // without a prefix by the sentence's own UTC time, dated as a GGA's. A $PASHR's heading is not
  // a heading sample: the heading stream is the session's heading log.
  void Attitude(std::string_view type, std::optional<double> prefix_s, int line) {
    AttitudeSample sample;
    std::optional<double> tod_s;
    const AttitudeParse parsed = type == "PASHR" ? ParsePashr(fields_, &sample, &tod_s)
                                                 : ParsePtnlAvr(fields_, &sample, &tod_s);
    switch (parsed) {
      case AttitudeParse::kSample:
        break;
      case AttitudeParse::kOtherSentence:
        Skip("other sentence (" + std::string(type) + "," +
                 std::string(fields_.size() > 1 ? fields_[1].substr(0, 8) : std::string_view()) + ")",
             line, SkipSeverity::kInformational);
        return;
      case AttitudeParse::kEmptyField:
        Skip("empty field", line);
        return;
      case AttitudeParse::kBadField:
        Skip("bad field", line);
        return;
      case AttitudeParse::kOutOfRange:
        Skip(kAttitudeOutOfRangeReason, line);
        return;
      case AttitudeParse::kNoFix:
        Skip("AVR without a vector fix (quality 0)", line);
        return;
      case AttitudeParse::kNotRtkFixed:
        Skip("AVR vector not RTK fixed (quality 1, 2 or 4)", line);
        return;
    }
    if (!prefix_s && !tod_s) {
      Skip("empty field", line);  // neither a logger stamp nor its own time
      return;
    }
    const double stamp_s = tod_s ? Stamp(prefix_s, *tod_s) : *prefix_s;
    if (!log_->attitudes.empty() && !(stamp_s > log_->attitudes.back().stamp_s)) {
      Skip("time not increasing", line);
      return;
    }
    sample.stamp_s = stamp_s;
    sample.line = line;
    log_->attitudes.push_back(sample);
    ++log_->attitudes_by_source[type == "PASHR" ? "$PASHR" : "$PTNL,AVR"];
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
inline void ParseLine(std::string_view text, NmeaLog* log, NmeaParser* parser) {
  ++log->lines_read;
  if (log->lines_read == 1) StripUtf8Bom(&text);
  parser->Line(text, static_cast<int>(log->lines_read));
}

// The log as a whole read ends it: a copy of `log` with `last` (a line not yet ended; empty:
// none) parsed and the GSTs still waiting for their GGA counted.
inline NmeaLog FinishedCopy(const NmeaLog& log, const NmeaParser& parser, std::string_view last) {
  NmeaLog copy = log;
  NmeaParser finishing = parser;
  finishing.set_log(&copy);
  if (!last.empty()) ParseLine(last, &copy, &finishing);
  finishing.Finish();
  return copy;
}

}  // namespace wallcal::io::nmea
