// SPDX-License-Identifier: Apache-2.0
#pragma once
// Streaming reader of CARMEN laser logs (RAWLASER1, ROBOTLASER1, FLASER; formats in docs/session-format.md),
// plain or gzip-compressed (detected by zlib). Memory does not grow with the log: one line is
// held at a time.
//
// Every line that is not a usable scan is counted in skipped() by reason, with the first line it
// happened on: lines of other kinds ("not a scan: PARAM", "not a scan: ODOM", "comment", ...)
// and malformed scan lines ("FLASER: beam count disagrees with the line", "RAWLASER1: negative
// or non-finite range", "RAWLASER1: line cut off at end of file", ...). A malformed scan line is
// skipped whole, never half-used.
//
// Geometry: RAWLASER1 / ROBOTLASER1 carry start angle and step. FLASER carries none; CARMEN's
// own convention is used: start −90°, step 1° for 180 or 181 beams, 0.5° for 360 or 361, 0.25°
// for 400 or 401 (start −50°), otherwise 180° / (n − 1). FLASER has no maximum range:
// max_range_m = 0 (unknown).

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "io/scan_source.h"
#include "io/types.h"

namespace wallcal::io {

class CarmenReader : public ScanSource {
 public:
  // Opens the log. Throws InputError naming `path` if it cannot be opened or is not a regular
  // file (io/input_file.h). A line with a NUL byte is skipped whole ("line with a NUL byte");
  // a UTF-8 byte-order mark before the first line is ignored.
  explicit CarmenReader(const std::string& path);
  // Opens the log at byte `start_byte` of its text, the start of a line an earlier reader
  // reported by line_start_byte(), and numbers the lines from `first_line` on (a log being
  // appended, read on from where the last read stopped). A gzip-compressed log is inflated
  // from its start up to there.
  CarmenReader(const std::string& path, int64_t start_byte, int64_t first_line);
  ~CarmenReader() override;
  CarmenReader(const CarmenReader&) = delete;
  CarmenReader& operator=(const CarmenReader&) = delete;

  // Reads up to the next valid scan line and fills *scan (stamp = logger_timestamp, line =
  // 1-based line number). Returns false at the end of the file. Throws InputError on a read
  // error of the file itself (corrupt gzip stream).
  bool Next(ScanRecord* scan) override;

  // Skimming (io/scan_source.h): NextStamp reads up to the next line whose keyword is a scan's
  // and whose last field (the logger timestamp) is a finite number, without reading its
  // ranges; non-scan lines are counted as by Next. ParseCurrent parses that line whole.
  bool NextStamp(double* stamp_s, int* line) override;
  bool ParseCurrent(ScanRecord* scan) override;

  const SkipCounts& skipped() const override { return skipped_; }
  int64_t lines_read() const { return lines_read_; }
  // Where the line read last starts: bytes of text from the start of the log.
  int64_t line_start_byte() const { return line_start_byte_; }
  int64_t scans_read() const override { return scans_read_; }
  const std::string& path() const override { return path_; }

 private:
  // Reads one line into line_ (without its newline). Returns false at end of file. Throws
  // InputError for a line longer than WALLCAL_MAX_LINE_BYTES (io/input_file.h).
  bool ReadLine();
  // Reads up to the next line that is not skipped whole (a NUL byte), counting it; strips a
  // UTF-8 byte-order mark from line 1. False at the end of the file.
  bool ReadUsableLine();
  // Refills chunk_ from the file; false at its end.
  bool FillChunk();
  // Parses line_ as a scan; false (and counted) when it is not a usable one.
  bool ParseLine(ScanRecord* scan);
  // Counts a line that is not a scan by its keyword (empty: blank; '#': comment; else kind).
  void SkipNonScan(std::string_view keyword);
  void Skip(const std::string& reason, SkipSeverity how = SkipSeverity::kProblem);

  std::string path_;
  void* gz_ = nullptr;  // gzFile (kept opaque: zlib stays out of this header)
  std::string line_;
  bool line_has_newline_ = false;
  bool after_cr_ = false;  // the last line ended with a CR: a '\n' right after it is its CRLF
  bool gzip_cut_reported_ = false;
  std::vector<char> chunk_;
  size_t chunk_begin_ = 0, chunk_end_ = 0;  // unread bytes of chunk_
  bool at_end_ = false;
  int64_t total_bytes_ = 0;                   // uncompressed bytes read
  int64_t start_byte_ = 0;                    // where reading began (the constructor's)
  int64_t line_start_byte_ = 0;
  int64_t max_line_bytes_ = 0, max_total_bytes_ = 0;
  std::vector<std::string_view> tokens_;
  SkipCounts skipped_;
  int64_t lines_read_ = 0;
  int64_t scans_read_ = 0;
};

}  // namespace wallcal::io
