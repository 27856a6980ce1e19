// SPDX-License-Identifier: Apache-2.0
#pragma once
// The line-by-line state of the NMEA reader (io/text/nmea_reader.h): a line's sentence into the
// records of an io::NmeaLog, with the date of plain sentences, the GST waiting for its GGA and
// the last stamps of the "time not increasing" check carried from line to line. ParseNmea and
// io::NmeaFollower share it. Private to io/.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "io/text/internal/nmea_sentence.h"
#include "io/types.h"

namespace wallcal::io::nmea {

class NmeaParser {
 public:
  // Fills *log (not owned). first_date: the file's first RMC/ZDA date, for plain sentences
  // before it.
  NmeaParser(NmeaLog* log, std::optional<int64_t> first_date)
      : log_(log), first_date_(first_date) {}

  // One line (its text without the line end; `line` its 1-based number).
  void Line(std::string_view text, int line);

  // Points the parser at another log (a copy of the one it filled, NmeaFollower::Log).
  void set_log(NmeaLog* log) { log_ = log; }

  // The end of the file: the GSTs still waiting for their GGA are counted without it.
  void Finish();

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

  double Stamp(std::optional<double> prefix_s, double tod_s);
  double DatedUtc(double tod_s);
  double EpochUtc(double prefix_s, double tod_s);
  void DateAndTime(std::string_view type, std::optional<double> prefix_s);
  void Gga(std::optional<double> prefix_s, int line);
  void Gst(std::optional<double> prefix_s, int line);
  void Heading(bool ths, std::optional<double> prefix_s, int line);
  // $PASHR and $PTNL,AVR (io/text/internal/nmea_attitude.h).
  void Attitude(std::string_view type, std::optional<double> prefix_s, int line);

  NmeaLog* log_;
  std::optional<int64_t> first_date_;
  std::optional<int64_t> day_;  // days since 1970-01-01 of the sentences being read
  double last_tod_s_ = 0.0;
  std::optional<double> last_timed_stamp_s_;
  Fields fields_;
  std::deque<std::pair<int64_t, size_t>> recent_fixes_;  // (UTC ms of day, index in fixes)
  std::deque<PendingGst> pending_gst_;
};

}  // namespace wallcal::io::nmea
