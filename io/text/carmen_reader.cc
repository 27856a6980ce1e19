// SPDX-License-Identifier: Apache-2.0
#include "io/text/carmen_reader.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include "common/angles.h"
#include "io/internal/decimal.h"
#include "io/input_file.h"
#include "io/text/internal/gzip_input.h"

namespace wallcal::io {
namespace {
constexpr size_t kChunkBytes = 1 << 16;
constexpr int kMaxBeams = 100000;  // far above any 2-D scanner; guards the allocation

bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

void Tokenize(const std::string& line, std::vector<std::string_view>* tokens) {
  tokens->clear();
  const char* p = line.data();
  const char* end = p + line.size();
  while (p < end) {
    while (p < end && IsSpace(*p)) ++p;
    const char* start = p;
    while (p < end && !IsSpace(*p)) ++p;
    if (p > start) tokens->emplace_back(start, static_cast<size_t>(p - start));
  }
}

// Whole-token parses: "1.5x" is not a number (numbers: io::ParseDecimal).
bool ParseInt(std::string_view token, int* value) {
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, *value);
  return result.ec == std::errc() && result.ptr == end;
}

bool IsScanKeyword(std::string_view keyword) {
  return keyword == "RAWLASER1" || keyword == "ROBOTLASER1" || keyword == "FLASER";
}

std::string_view FirstToken(const std::string& line) {
  const char* p = line.data();
  const char* end = p + line.size();
  while (p < end && IsSpace(*p)) ++p;
  const char* start = p;
  while (p < end && !IsSpace(*p)) ++p;
  return std::string_view(start, static_cast<size_t>(p - start));
}

std::string_view LastToken(const std::string& line) {
  const char* begin = line.data();
  const char* p = begin + line.size();
  while (p > begin && IsSpace(p[-1])) --p;
  const char* end = p;
  while (p > begin && !IsSpace(p[-1])) --p;
  return std::string_view(p, static_cast<size_t>(end - p));
}

// FLASER lines carry no geometry. CARMEN's own readers (carmen_laser_get_fov /
// _get_angle_increment) take a 180° field from −90°: 1° steps for 180/181 beams (a 180-beam
// scan drops the last beam), 0.5° for 360/361, 0.25° over 100° for 400/401, else π/(n−1).
void FlaserGeometry(int n, double* start_rad, double* step_rad) {
  *start_rad = -0.5 * kPi;
  if (n == 180 || n == 181) {
    *step_rad = kPi / 180.0;
  } else if (n == 360 || n == 361) {
    *step_rad = kPi / 360.0;
  } else if (n == 400 || n == 401) {
    *step_rad = kPi / 720.0;
    *start_rad = -50.0 * kPi / 180.0;
  } else {
    *step_rad = n > 1 ? kPi / (n - 1) : 0.0;
  }
}

}  // namespace

CarmenReader::CarmenReader(const std::string& path) : path_(path), chunk_(kChunkBytes) {
  // A FIFO, a device or a folder is refused before it is opened: reading one could block or
  // never end (docs/session-format.md, "Limits").
  CheckInputFile(path, "the scan log");
  const InputLimits limits = CurrentInputLimits();
  max_line_bytes_ = limits.max_line_bytes;
  max_total_bytes_ = limits.max_file_bytes;
  gz_ = OpenGzip(path, "the scan log", 1 << 18);
  tokens_.reserve(1024);
}

CarmenReader::CarmenReader(const std::string& path, int64_t start_byte, int64_t first_line)
    : CarmenReader(path) {
  if (start_byte <= 0) return;
  if (gzseek(static_cast<gzFile>(gz_), static_cast<z_off_t>(start_byte), SEEK_SET) !=
      static_cast<z_off_t>(start_byte)) {
    throw InputError(Where(path, static_cast<int>(first_line),
                           "cannot read the scan log on from byte " + std::to_string(start_byte) +
                               "; expected a log at least that long"));
  }
  start_byte_ = start_byte;
  lines_read_ = std::max<int64_t>(0, first_line - 1);
}

CarmenReader::~CarmenReader() {
  if (gz_ != nullptr) gzclose(static_cast<gzFile>(gz_));
}

bool CarmenReader::FillChunk() {
  gzFile file = static_cast<gzFile>(gz_);
  chunk_begin_ = chunk_end_ = 0;
  if (at_end_) return false;
  const int got = gzread(file, chunk_.data(), static_cast<unsigned>(chunk_.size()));
  if (got <= 0) {
    at_end_ = true;
    int error = Z_OK;
    const char* message = gzerror(file, &error);
    // Z_BUF_ERROR: the gzip stream is cut off; a partial line is reported as truncated.
    if (error == Z_BUF_ERROR) {
      if (!gzip_cut_reported_) {
        gzip_cut_reported_ = true;
        skipped_.Add("gzip stream cut off", static_cast<int>(lines_read_ + 1));
      }
    } else if (got < 0 || error != Z_OK) {
      throw InputError(Where(path_, static_cast<int>(lines_read_ + 1),
                             std::string("cannot read the scan log: ") + message));
    }
    return false;
  }
  total_bytes_ += got;
  if (total_bytes_ > max_total_bytes_) {
    throw InputError(Where(path_, static_cast<int>(lines_read_ + 1),
                           "the scan log holds more than " + std::to_string(max_total_bytes_) +
                               " bytes (uncompressed); expected at most that "
                               "(WALLCAL_MAX_FILE_BYTES raises the limit)"));
  }
  chunk_end_ = static_cast<size_t>(got);
  return true;
}

bool CarmenReader::ReadLine() {
  line_.clear();
  line_has_newline_ = false;
  bool at_line_start = true;
  // Lines end at LF, CRLF or a CR alone (old Mac and some instrument downloads). A NUL byte
  // inside a line stays in it (and the line is skipped whole by Next), it never ends the line
  // early nor joins it to the next one.
  while (true) {
    if (chunk_begin_ == chunk_end_ && !FillChunk()) return !line_.empty();
    if (after_cr_) {
      after_cr_ = false;
      if (chunk_[chunk_begin_] == '\n') {
        ++chunk_begin_;
        continue;
      }
    }
    if (at_line_start) {
      at_line_start = false;
      line_start_byte_ = start_byte_ + total_bytes_ - static_cast<int64_t>(chunk_end_ - chunk_begin_);
    }
    const char* begin = chunk_.data() + chunk_begin_;
    const size_t available = chunk_end_ - chunk_begin_;
    const void* newline = std::memchr(begin, '\n', available);
    size_t take = newline != nullptr
                      ? static_cast<size_t>(static_cast<const char*>(newline) - begin)
                      : available;
    const void* cr = std::memchr(begin, '\r', take);
    const bool ends_with_cr = cr != nullptr;
    if (ends_with_cr) take = static_cast<size_t>(static_cast<const char*>(cr) - begin);
    if (static_cast<int64_t>(line_.size() + take) > max_line_bytes_) {
      throw InputError(Where(path_, static_cast<int>(lines_read_ + 1),
                             "line longer than " + std::to_string(max_line_bytes_) +
                                 " bytes; expected CARMEN lines (WALLCAL_MAX_LINE_BYTES raises "
                                 "the limit)"));
    }
    line_.append(begin, take);
    if (newline != nullptr || ends_with_cr) {
      chunk_begin_ += take + 1;
      line_has_newline_ = true;
      after_cr_ = ends_with_cr;
      return true;
    }
    chunk_begin_ = chunk_end_;
  }
}

void CarmenReader::Skip(const std::string& reason, SkipSeverity how) {
  skipped_.Add(reason, static_cast<int>(lines_read_), 1, how);
}

bool CarmenReader::ReadUsableLine() {
  while (ReadLine()) {
    ++lines_read_;
    if (lines_read_ == 1) StripUtf8Bom(&line_);
    if (line_.find('\0') != std::string::npos) {
      Skip("line with a NUL byte");
      continue;
    }
    return true;
  }
  return false;
}

bool CarmenReader::Next(ScanRecord* scan) {
  while (ReadUsableLine()) {
    if (ParseLine(scan)) {
      ++scans_read_;
      return true;
    }
  }
  return false;
}

void CarmenReader::SkipNonScan(std::string_view keyword) {
  if (keyword.empty()) {
    Skip("blank line", SkipSeverity::kInformational);
    return;
  }
  if (keyword[0] == '#') {
    Skip("comment", SkipSeverity::kInformational);
    return;
  }
  // CARMEN message names are upper-case words (PARAM, ODOM, TRUEPOS, NMEAGGA): only such a
  // word is named in the count; anything else is described, never quoted, so that a file
  // named by mistake does not show its contents.
  bool word = keyword.size() <= 24 && std::isupper(static_cast<unsigned char>(keyword[0]));
  for (char c : keyword) {
    word = word && (std::isupper(static_cast<unsigned char>(c)) ||
                    std::isdigit(static_cast<unsigned char>(c)) || c == '_');
  }
  Skip("not a scan: " + (word ? std::string(keyword) : std::string("not a CARMEN line")),
       SkipSeverity::kInformational);
}

bool CarmenReader::NextStamp(double* stamp_s, int* line) {
  while (ReadUsableLine()) {
    const std::string_view keyword = FirstToken(line_);
    if (!IsScanKeyword(keyword)) {
      SkipNonScan(keyword);
      continue;
    }
    double t = 0.0;
    // A last line without its newline may be cut off anywhere: its last field would be a range,
    // not the stamp. It is parsed whole, as is a line whose last field is not a finite number.
    if (!line_has_newline_ || !ParseDecimal(LastToken(line_), &t) || !std::isfinite(t)) {
      // Parsed whole to count it under its precise reason (a scan line whose last field is
      // not a finite number is malformed).
      ScanRecord discard;
      if (!ParseLine(&discard)) continue;
      t = discard.stamp_s;
    }
    ++scans_read_;
    *stamp_s = t;
    *line = static_cast<int>(lines_read_);
    return true;
  }
  return false;
}

bool CarmenReader::ParseCurrent(ScanRecord* scan) { return ParseLine(scan); }

bool CarmenReader::ParseLine(ScanRecord* scan) {
  Tokenize(line_, &tokens_);
  const std::string_view keyword = tokens_.empty() ? std::string_view() : tokens_[0];
  if (!IsScanKeyword(keyword)) {
    SkipNonScan(keyword);
    return false;
  }
  const bool robot = keyword == "ROBOTLASER1";
  const bool flaser = keyword == "FLASER";
  const std::string name(keyword);
  auto malformed = [&](const std::string& reason) {
    Skip(name + ": " + reason);
    return false;
  };
  // Too few fields on a last line without its newline: the log was cut off while written.
  auto short_line = [&](const std::string& reason) {
    return malformed(line_has_newline_ ? reason : "line cut off at end of file");
  };

  // Layout: [header] n r_1..r_n [remissions] [robot fields] ipc_timestamp ipc_hostname
  // logger_timestamp. The header before n: RAWLASER1/ROBOTLASER1 7 fields, FLASER none.
  const size_t count_index = flaser ? 1 : 8;
  if (tokens_.size() <= count_index) return short_line("too few fields");
  int n = 0;
  if (!ParseInt(tokens_[count_index], &n)) return malformed("non-numeric field");
  if (n < 1 || n > kMaxBeams) return malformed("beam count out of range");
  const size_t first_range = count_index + 1;
  const size_t after_ranges = first_range + static_cast<size_t>(n);
  size_t expected = 0;
  if (flaser) {
    expected = after_ranges + 6 + 3;  // laser pose, odometry pose, the three time fields
  } else {
    if (tokens_.size() <= after_ranges) return short_line("beam count disagrees with the line");
    int remissions = 0;
    if (!ParseInt(tokens_[after_ranges], &remissions) || remissions < 0 || remissions > kMaxBeams) {
      return malformed("beam count disagrees with the line");
    }
    expected = after_ranges + 1 + static_cast<size_t>(remissions) + (robot ? 11 : 0) + 3;
  }
  if (tokens_.size() < expected) return short_line("beam count disagrees with the line");
  if (tokens_.size() > expected) return malformed("beam count disagrees with the line");

  // Every numeric field must be a number, even those not used: a garbled line is not trusted.
  const size_t hostname_index = tokens_.size() - 2;
  double value = 0.0;
  for (size_t i = 1; i < tokens_.size(); ++i) {
    if (i == hostname_index || i == count_index || (i >= first_range && i < after_ranges)) {
      continue;
    }
    if (!ParseDecimal(tokens_[i], &value)) return malformed("non-numeric field");
  }

  double stamp_s = 0.0;
  ParseDecimal(tokens_.back(), &stamp_s);
  if (!std::isfinite(stamp_s)) return malformed("non-finite timestamp");

  double start_rad = 0.0;
  double step_rad = 0.0;
  double max_range_m = 0.0;
  if (flaser) {
    FlaserGeometry(n, &start_rad, &step_rad);
  } else {
    ParseDecimal(tokens_[2], &start_rad);
    ParseDecimal(tokens_[4], &step_rad);
    ParseDecimal(tokens_[5], &max_range_m);
    if (!std::isfinite(start_rad) || !std::isfinite(step_rad) || !std::isfinite(max_range_m)) {
      return malformed("non-finite scan geometry");
    }
  }

  scan->ranges_m.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    double range_m = 0.0;
    if (!ParseDecimal(tokens_[first_range + static_cast<size_t>(i)], &range_m)) {
      return malformed("non-numeric field");
    }
    // Ranges are kept as float: one beyond float's range (1e300) would become infinity.
    if (!(std::isfinite(range_m) && range_m >= 0.0 &&
          range_m <= std::numeric_limits<float>::max())) {
      return malformed("negative or non-finite range");
    }
    scan->ranges_m[static_cast<size_t>(i)] = static_cast<float>(range_m);
  }
  scan->stamp_s = stamp_s;
  scan->start_angle_rad = start_rad;
  scan->angular_step_rad = step_rad;
  scan->max_range_m = max_range_m;
  scan->line = static_cast<int>(lines_read_);
  return true;
}

}  // namespace wallcal::io
