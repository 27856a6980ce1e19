// SPDX-License-Identifier: Apache-2.0
#pragma once
// NMEA 0183 reader for the GNSS and heading logs (docs/session-format.md).
//
// Sentences: GGA (position; height_m = altitude + geoid separation, the separation taken as 0
// when the field is empty), GST (σ latitude / longitude in metres, attached to the GGA fix with
// the same UTC time field, before or after it), HDT and THS (heading, degrees clockwise from
// north -> heading_rad in [0, 2π); THS only with status A), $PASHR and $PTNL,AVR (the vehicle's
// roll and pitch -> NmeaLog::attitudes; fields, signs and σ: io/text/internal/nmea_attitude.h;
// a $PASHR's heading is not a heading sample), RMC and ZDA (date only). Any talker.
//
// Time: a line "<seconds> <sentence>" (logger-time prefix) is stamped with the prefix (its
// arrival on the logger clock); a GGA so stamped also keeps its epoch's UTC in utc_epoch_s (on
// the log's RMC/ZDA dates, else on the day nearest the prefix), for calib::MapGnssEpochs. A plain
// sentence is stamped with its own UTC time of day on the date of the last RMC/ZDA before it
// (the first date in the file for sentences before any date; across midnight the day is
// advanced when the time of day drops by more than 12 h); HDT/THS take the stamp of the last
// timed sentence before them, $PASHR and $PTNL,AVR their own time as a GGA does. A plain
// capture without any RMC/ZDA date is stamped with the time of day on 1970-01-01. An attitude
// sentence with a prefix is stamped with it, as a heading is (no epoch mapping).
//
// Skipped and counted in NmeaLog::skipped (never half-used): "not NMEA" (comments, blank lines,
// binary bytes), "no checksum", "bad checksum", "empty field" (a required field missing or
// empty, e.g. "$GPHDT,,T"), "bad field" (not a number, bad hemisphere letter, minutes >= 60),
// "lat/lon out of range", "GGA without a fix" (quality 0, no position), "heading out of range",
// "THS status X", "GGA fix with fewer than 4 satellites" and "GGA fix with HDOP 0" (quality
// 4 or 5 contradicted by its own satellite count or HDOP), "roll or pitch beyond 30 deg",
// "AVR without a vector fix (quality 0)", "AVR vector not RTK fixed (quality 1, 2 or 4)", "no
// time yet", "time not increasing" (a fix, heading or attitude not later than the previous one
// of its kind; a GGA dropped so is still counted in fixes_by_quality), "other sentence (GSV)"
// by type ("other sentence (PASHR,ATT)" for Ashtech's other $PASHR), "GST without its GGA".

#include <cstdint>
#include <istream>
#include <memory>
#include <string>
#include <string_view>

#include "io/types.h"

namespace wallcal::io {

// Largest uncompressed size of a gzip-compressed log (1 GiB). A .gz log is inflated piecewise
// as it is read (twice, see ParseNmea), never held whole; the cap bounds the time and the
// longest line a small hostile file can make the reader process.
inline constexpr int64_t kMaxGzipNmeaBytes = int64_t{1} << 30;

// Reads the whole log. A gzip-compressed log (recognised by its first bytes, whatever its name)
// is read as the text it holds; a cut-off gzip stream keeps the lines before the cut and counts
// "gzip stream cut off" in skipped. Throws InputError if the file cannot be opened, or its gzip
// data are corrupt or inflate to more than kMaxGzipNmeaBytes.
NmeaLog ReadNmea(const std::string& path);

// Reads a log already open as a stream (read twice: it must be seekable, as a file or a string
// stream is). `name` stands for the file in messages. Throws InputError on a read error.
// This is what ReadNmea does after opening the file; the fuzz target calls it directly.
NmeaLog ParseNmea(std::istream& in, const std::string& name);

// An NMEA log that is still being written, read on from where the last read stopped: each
// ReadMore() parses only the lines the file gained, with the reader's state carried over (the
// date of plain sentences, a GST waiting for its GGA, the last stamps of the "time not
// increasing" check, the line numbers). A last line not yet ended (no '\n', or a '\r' that a
// '\n' may follow) is parsed anew each time until it is. Log() is what ReadNmea returns for the
// file as the last ReadMore() found it, to the byte.
//
// Read whole instead: the first time, a file shorter than what was read (a new log under the
// same name), a file whose first RMC/ZDA date comes after sentences it would have dated (their
// stamps change), and a gzip-compressed log (always). Throws InputError as ReadNmea does.
class NmeaFollower {
 public:
  explicit NmeaFollower(std::string path);
  ~NmeaFollower();
  NmeaFollower(NmeaFollower&&) noexcept;
  NmeaFollower& operator=(NmeaFollower&&) noexcept;

  // Reads what the file gained. Returns the byte it read from (0: the whole file).
  int64_t ReadMore();
  // The log as read so far (the GSTs still waiting for their GGA counted as without it, as at
  // the end of a whole read; they are matched when the GGA comes).
  NmeaLog Log() const;
  // The bytes read so far (the file's size at the last ReadMore()).
  int64_t bytes_read() const;
  const std::string& path() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// NMEA lines handed over one at a time as they come (a recording's nmea_msgs/Sentence messages,
// each a logger-stamped line), parsed with the reader's state carried over as NmeaFollower
// carries it over a growing file. Log() is what ParseNmea returns for the lines added so far
// joined by '\n'. The lines are kept until the first RMC/ZDA date comes: it dates what came
// before it, which is then parsed again.
class NmeaLineFeed {
 public:
  // `name` stands for the lines' source in messages.
  explicit NmeaLineFeed(std::string name);
  ~NmeaLineFeed();
  NmeaLineFeed(NmeaLineFeed&&) noexcept;
  NmeaLineFeed& operator=(NmeaLineFeed&&) noexcept;

  // One line without its line end (it holds no '\n' or '\r'). Throws InputError for a line
  // longer than WALLCAL_MAX_LINE_BYTES, as ParseNmea does.
  void Add(std::string_view line);
  NmeaLog Log() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace wallcal::io
