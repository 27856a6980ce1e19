#include "preflight/inspect.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "pipeline/calibration.h"
#include "pipeline/config_dirs.h"
#include "calib/pose_samples.h"
#include "calib/geodesy.h"
#include "calib/range_model.h"
#include "calib/survey_tie.h"
#include "calib/time_alignment.h"
#include "io/carmen_reader.h"
#include "io/input_file.h"
#include "io/nmea_reader.h"
#include "io/session_reader.h"
#include "io/survey_reader.h"
#include "io/version.h"
#include "common/angles.h"

namespace wallcal::preflight {
namespace {

namespace fs = std::filesystem;
std::string Fmt(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

std::string FileName(const std::string& path) { return fs::path(path).filename().string(); }

// Stamps on the UNIX clock (after 1973) are printed as UTC; smaller ones (a logger that counts
// from its own start, like the Radish logs) as seconds.
std::string FormatStamp(double stamp_s) {
  if (!std::isfinite(stamp_s)) return "-";
  if (stamp_s < 1e8 || stamp_s > 1e11) return Fmt("%.3f s", stamp_s);
  const double whole = std::floor(stamp_s);
  const std::time_t t = static_cast<std::time_t>(whole);
  std::tm tm_utc{};
  gmtime_r(&t, &tm_utc);
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%04d-%02d-%02d %02d:%02d:%06.3f UTC",
                tm_utc.tm_year + 1900, tm_utc.tm_mon + 1, tm_utc.tm_mday, tm_utc.tm_hour,
                tm_utc.tm_min, tm_utc.tm_sec + (stamp_s - whole));
  return buffer;
}

double Median(std::vector<double> values) {
  if (values.empty()) return io::kNaN;
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  return values[mid];
}

// Circular extent of angles (rad) about their circular mean: min and max as headings in
// [0, 360) degrees and the width in degrees (0 for fewer than one angle).
struct AngleExtent {
  double min_deg = 0.0, max_deg = 0.0, width_deg = 0.0;
  bool any = false;
};
AngleExtent Extent(const std::vector<double>& angles_rad) {
  AngleExtent extent;
  if (angles_rad.empty()) return extent;
  double sx = 0.0, sy = 0.0;
  for (double a : angles_rad) {
    sx += std::cos(a);
    sy += std::sin(a);
  }
  const double mean = std::atan2(sy, sx);
  double lo = 0.0, hi = 0.0;
  for (double a : angles_rad) {
    const double d = WrapAngle(a - mean);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  extent.any = true;
  extent.min_deg = std::fmod((mean + lo) * kRadToDeg + 720.0, 360.0);
  extent.max_deg = std::fmod((mean + hi) * kRadToDeg + 720.0, 360.0);
  extent.width_deg = (hi - lo) * kRadToDeg;
  return extent;
}

// 36 bins of 10 degrees of heading (clockwise from north), one character each: blank for
// none, then . : - = + * # % @ for a growing share of the fullest bin.
std::string Histogram(const std::vector<double>& headings_rad) {
  std::vector<int64_t> bins(36, 0);
  for (double h : headings_rad) {
    if (!std::isfinite(h)) continue;
    double deg = std::fmod(h * kRadToDeg, 360.0);
    if (deg < 0) deg += 360.0;
    const int bin = std::min(35, static_cast<int>(deg / 10.0));
    ++bins[bin];
  }
  const int64_t peak = *std::max_element(bins.begin(), bins.end());
  static const char kLevels[] = ".:-=+*#%@";
  std::string row = "[";
  for (int64_t count : bins) {
    if (count == 0 || peak == 0) {
      row += ' ';
    } else {
      const int level = static_cast<int>(std::ceil(9.0 * static_cast<double>(count) /
                                                   static_cast<double>(peak))) - 1;
      row += kLevels[std::clamp(level, 0, 8)];
    }
  }
  return row + "]";
}

int OccupiedBins(const std::vector<double>& headings_rad) {
  std::set<int> bins;
  for (double h : headings_rad) {
    if (!std::isfinite(h)) continue;
    double deg = std::fmod(h * kRadToDeg, 360.0);
    if (deg < 0) deg += 360.0;
    bins.insert(std::min(35, static_cast<int>(deg / 10.0)));
  }
  return static_cast<int>(bins.size());
}

// The axis over Histogram(): labels at 0, 90, 180, 270, 360 degrees.
std::string HistogramAxis() {
  std::string axis(40, ' ');
  const char* labels[] = {"0", "90", "180", "270", "360"};
  for (int i = 0; i < 5; ++i) {
    const std::string label = labels[i];
    const size_t column = 1 + static_cast<size_t>(9 * i);
    const size_t at = column >= label.size() / 2 ? column - label.size() / 2 : 0;
    axis.replace(at, label.size(), label);
  }
  while (!axis.empty() && axis.back() == ' ') axis.pop_back();
  return axis;
}

std::string DescribeSkips(const io::SkipCounts& skips) {
  std::ostringstream out;
  bool first = true;
  for (const auto& [reason, count] : skips.by_reason) {
    out << (first ? "" : "; ") << count << " " << reason;
    const auto line = skips.first_line.find(reason);
    if (line != skips.first_line.end() && line->second > 0) out << " (first line " << line->second << ")";
    first = false;
  }
  return first ? std::string("none") : out.str();
}

int64_t WorrisomeSkips(const io::SkipCounts& skips) { return skips.Problems(); }

std::string FormatStream(const StreamStats& s) {
  std::ostringstream out;
  out << "  " << s.name << " (" << FileName(s.file) << "): " << s.records << " records\n";
  if (s.records == 0) return out.str();
  out << "    span      " << FormatStamp(s.start_s) << " .. " << FormatStamp(s.end_s) << "  ("
      << Fmt("%.3f", s.end_s - s.start_s) << " s)\n";
  if (std::isfinite(s.median_period_s) && s.median_period_s > 0) {
    out << "    rate      median period " << Fmt("%.4f", s.median_period_s) << " s ("
        << Fmt("%.2f", 1.0 / s.median_period_s) << " Hz)\n";
    const double threshold_s = s.gap_periods * s.median_period_s;
    if (s.gaps == 0) {
      out << "    gaps      none longer than " << Fmt("%.3f", threshold_s) << " s\n";
    } else {
      out << "    gaps      " << s.gaps << " longer than " << Fmt("%.3f", threshold_s)
          << " s; longest " << Fmt("%.3f", s.longest_gap_s) << " s from +"
          << Fmt("%.3f", s.longest_gap_start_s - s.start_s) << " s (before line "
          << s.longest_gap_line << ")\n";
    }
  } else {
    out << "    rate      unknown (fewer than 2 distinct stamps)\n";
  }
  if (s.not_increasing > 0) {
    out << "    order     " << s.not_increasing << " steps back in time or repeated stamps, first at line "
        << s.first_not_increasing_line << "\n";
  }
  return out.str();
}

// ---- Sniffing ---------------------------------------------------------------------------

bool IsCarmenKeyword(const std::string& word) {
  static const std::set<std::string> kKeywords = {
      "RAWLASER1", "RAWLASER2", "RAWLASER3", "RAWLASER4", "ROBOTLASER1", "ROBOTLASER2",
      "FLASER",    "RLASER",    "LASER3",    "LASER4",    "PARAM",       "ODOM",
      "TRUEPOS",   "SYNC",      "NEFF"};
  return kKeywords.count(word) > 0;
}

// An NMEA sentence: "$" + talker/type (5 letters or digits) + ",", either at the start of the
// line (after an optional logger time "<seconds> ") or after binary bytes a receiver
// interleaved. A "$GPGGA," quoted inside text (a README) is not a sentence.
bool HasNmeaSentence(const std::string& line) {
  size_t text_start = 0;
  {
    size_t i = 0;
    while (i < line.size() && (std::isdigit(static_cast<unsigned char>(line[i])) || line[i] == '.')) ++i;
    if (i > 0 && i < line.size() && (line[i] == ' ' || line[i] == '\t')) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      text_start = i;
    }
  }
  for (size_t at = line.find('$', text_start); at != std::string::npos; at = line.find('$', at + 1)) {
    if (at + 6 >= line.size()) break;
    bool binary_before = false;
    for (size_t i = text_start; i < at; ++i) {
      const unsigned char c = static_cast<unsigned char>(line[i]);
      binary_before = binary_before || c < 32 || c >= 127;
    }
    if (at != text_start && !binary_before) continue;
    bool ok = true;
    for (size_t i = at + 1; i < at + 6 && ok; ++i) {
      const unsigned char c = static_cast<unsigned char>(line[i]);
      ok = std::isupper(c) || std::isdigit(c);
    }
    if (ok && line[at + 6] == ',') return true;
  }
  return false;
}

void RequireReadableFile(const std::string& path) {
  std::error_code error;
  if (!fs::exists(path, error)) {
    throw io::InputError(io::Where(path, 0, "no such file; expected a session or a log file"));
  }
  if (fs::is_directory(path, error)) {
    throw io::InputError(io::Where(path, 0, "is a folder without session.yaml"));
  }
  io::CheckInputFile(path, "the log");  // a FIFO or a device is refused before it is opened
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io::InputError(io::Where(path, 0, "cannot open for reading"));
}

bool IsSessionPath(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) return true;
  const std::string ext = fs::path(path).extension().string();
  return ext == ".yaml" || ext == ".yml";
}

// ---- Reading the logs for statistics -------------------------------------------------

struct ScanLogSummary {
  StreamStats stats;
  std::vector<double> stamps_s;  // with the session's time offset
  std::map<size_t, int64_t> beams;  // beam count -> scans
  calib::RangeCounts readings;
  bool have_readings = false;
  double first_start_rad = 0.0, first_step_rad = 0.0, first_max_range_m = 0.0;
  io::SkipCounts skipped;
  int64_t lines_read = 0;
};

// Valid readings of a scan without a preset: finite, positive and below the log's maximum.
int LogValid(const io::ScanRecord& scan, float* min_m, float* max_m) {
  int valid = 0;
  for (float r : scan.ranges_m) {
    if (!std::isfinite(r) || r <= 0.0f) continue;
    if (scan.max_range_m > 0.0 && r >= static_cast<float>(scan.max_range_m)) continue;
    ++valid;
    *min_m = std::min(*min_m, r);
    *max_m = std::max(*max_m, r);
  }
  return valid;
}

ScanLogSummary ReadScanLog(const std::string& path, double time_offset_s,
                           const io::ScannerPreset* preset, double min_range_m,
                           double mixed_jump_m) {
  ScanLogSummary summary;
  io::CarmenReader reader(path);
  io::ScanRecord scan;
  std::vector<int> lines;
  while (reader.Next(&scan)) {
    if (summary.stamps_s.empty()) {
      summary.first_start_rad = scan.start_angle_rad;
      summary.first_step_rad = scan.angular_step_rad;
      summary.first_max_range_m = scan.max_range_m;
    }
    summary.stamps_s.push_back(scan.stamp_s + time_offset_s);
    lines.push_back(scan.line);
    ++summary.beams[scan.ranges_m.size()];
    if (preset != nullptr) {
      calib::ToScanPoints(scan, *preset, min_range_m, mixed_jump_m, &summary.readings);
      summary.have_readings = true;
    }
  }
  summary.stats = ComputeStreamStats("scans", path, summary.stamps_s, lines);
  summary.skipped = reader.skipped();
  summary.lines_read = reader.lines_read();
  return summary;
}

StreamStats FixStats(const std::string& path, const io::NmeaLog& log) {
  std::vector<double> stamps;
  std::vector<int> lines;
  for (const io::GnssFix& fix : log.fixes) {
    stamps.push_back(fix.stamp_s);
    lines.push_back(fix.line);
  }
  return ComputeStreamStats("GNSS fixes (GGA)", path, stamps, lines);
}

StreamStats HeadingStats(const std::string& path, const io::NmeaLog& log) {
  std::vector<double> stamps;
  std::vector<int> lines;
  for (const io::HeadingSample& h : log.headings) {
    stamps.push_back(h.stamp_s);
    lines.push_back(h.line);
  }
  return ComputeStreamStats("headings (HDT/THS)", path, stamps, lines);
}

std::string FormatQualities(const io::NmeaLog& log) {
  std::ostringstream out;
  for (const auto& [quality, count] : log.fixes_by_quality) {
    out << "    quality   " << quality << " (" << io::FixQualityName(quality) << "): " << count << "\n";
  }
  return out.str();
}

// Time covered by consecutive RTK-fixed epochs (steps no longer than the gap threshold).
double TimeRtkFixed(const std::vector<io::GnssFix>& fixes, double max_step_s) {
  double total_s = 0.0;
  for (size_t i = 1; i < fixes.size(); ++i) {
    const double dt = fixes[i].stamp_s - fixes[i - 1].stamp_s;
    if (fixes[i].quality == 4 && fixes[i - 1].quality == 4 && dt > 0 && dt <= max_step_s) {
      total_s += dt;
    }
  }
  return total_s;
}

struct Interval {
  double start_s = io::kNaN, end_s = io::kNaN;
  bool Valid() const { return std::isfinite(start_s) && std::isfinite(end_s) && end_s >= start_s; }
};

Interval Intersect(const Interval& a, const Interval& b) {
  Interval out;
  if (!a.Valid() || !b.Valid()) return out;
  out.start_s = std::max(a.start_s, b.start_s);
  out.end_s = std::min(a.end_s, b.end_s);
  if (out.end_s < out.start_s) out.start_s = out.end_s = io::kNaN;
  return out;
}

std::string FormatOverlap(const Interval& i) {
  return i.Valid() ? Fmt("%.3f s", i.end_s - i.start_s) : std::string("none");
}

void CsvNumber(std::ostream& out, const char* format, double value) {
  if (std::isfinite(value)) out << Fmt(format, value);
}

}  // namespace

// ---- Public --------------------------------------------------------------------------------

StreamStats ComputeStreamStats(const std::string& name, const std::string& file,
                               const std::vector<double>& stamps_s, const std::vector<int>& lines,
                               double gap_periods) {
  StreamStats s;
  s.name = name;
  s.file = file;
  s.gap_periods = gap_periods;
  s.records = static_cast<int64_t>(stamps_s.size());
  auto line_of = [&](size_t i) { return i < lines.size() ? lines[i] : static_cast<int>(i + 1); };
  std::vector<double> steps;
  for (size_t i = 0; i < stamps_s.size(); ++i) {
    const double t = stamps_s[i];
    if (!std::isfinite(t)) continue;
    if (!std::isfinite(s.start_s) || t < s.start_s) s.start_s = t;
    if (!std::isfinite(s.end_s) || t > s.end_s) s.end_s = t;
    if (i == 0) continue;
    const double dt = t - stamps_s[i - 1];
    if (!(dt > 0)) {
      if (s.not_increasing++ == 0) s.first_not_increasing_line = line_of(i);
      continue;
    }
    steps.push_back(dt);
  }
  s.median_period_s = Median(steps);
  if (std::isfinite(s.median_period_s) && s.median_period_s > 0) {
    const double threshold_s = gap_periods * s.median_period_s;
    for (size_t i = 1; i < stamps_s.size(); ++i) {
      const double dt = stamps_s[i] - stamps_s[i - 1];
      if (!(dt > threshold_s)) continue;
      ++s.gaps;
      if (dt > s.longest_gap_s) {
        s.longest_gap_s = dt;
        s.longest_gap_start_s = stamps_s[i - 1];
        s.longest_gap_line = line_of(i);
      }
    }
  }
  return s;
}

LogKind SniffLogKind(const std::string& path) {
  RequireReadableFile(path);
  // Look at the first 256 KiB only (decompressed when the file is gzip): a binary file without
  // newlines must not be read whole.
  std::string head(256 * 1024, '\0');
  gzFile file = gzopen(path.c_str(), "rb");
  if (file == nullptr) throw io::InputError(io::Where(path, 0, "cannot open"));
  const int got = gzread(file, head.data(), static_cast<unsigned>(head.size()));
  gzclose(file);
  head.resize(got > 0 ? static_cast<size_t>(got) : 0);
  if (head.empty()) throw io::InputError(io::Where(path, 0, "empty file; expected an NMEA or CARMEN log"));
  std::istringstream lines(head);
  std::string line;
  int line_number = 0;
  int first_content_line = 0;
  std::string first_content;
  while (std::getline(lines, line)) {
    ++line_number;
    size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    if (first_content_line == 0) {
      first_content_line = line_number;
      first_content = line.substr(start);
    }
    std::istringstream words(line.substr(start));
    std::string word;
    words >> word;
    if (IsCarmenKeyword(word)) return LogKind::kCarmen;
    if (HasNmeaSentence(line)) return LogKind::kNmea;
  }
  throw io::InputError(io::Where(
      path, first_content_line,
      (first_content_line == 0 ? std::string("only comments and blank lines")
                               : "neither NMEA nor CARMEN (" +
                                     io::DescribeLine(first_content) + ")") +
          "; expected NMEA sentences ($GPGGA,... optionally after a logger time) or CARMEN "
          "lines (RAWLASER1, ROBOTLASER1, FLASER)"));
}

std::string InspectLogFile(const std::string& path) {
  const LogKind kind = SniffLogKind(path);
  std::ostringstream out;
  if (kind == LogKind::kNmea) {
    const io::NmeaLog log = io::ReadNmea(path);
    out << "wallcal inspect " << io::kToolVersion << ": " << path << " (NMEA 0183, "
        << log.lines_read << " lines)\n";
    out << FormatStream(FixStats(path, log));
    out << FormatQualities(log);
    if (!log.fixes.empty()) {
      const StreamStats fixes = FixStats(path, log);
      const double max_step_s = std::isfinite(fixes.median_period_s)
                                    ? fixes.gap_periods * fixes.median_period_s
                                    : 0.0;
      const double span_s = fixes.end_s - fixes.start_s;
      const double rtk_s = TimeRtkFixed(log.fixes, max_step_s);
      out << "    RTK fixed " << Fmt("%.3f", rtk_s) << " s of " << Fmt("%.3f", span_s) << " s";
      if (span_s > 0) out << " (" << Fmt("%.1f", 100.0 * rtk_s / span_s) << " %)";
      out << "\n";
    }
    out << FormatStream(HeadingStats(path, log));
    if (!log.headings.empty()) {
      std::vector<double> headings;
      for (const io::HeadingSample& h : log.headings) headings.push_back(h.heading_rad);
      out << "    headings   " << HistogramAxis() << "\n";
      out << "    (10° bins) " << Histogram(headings) << "\n";
    }
    out << "  skipped lines: " << DescribeSkips(log.skipped) << "\n";
  } else {
    const ScanLogSummary scans = ReadScanLog(path, 0.0, nullptr, 0.0, 0.0);
    out << "wallcal inspect " << io::kToolVersion << ": " << path << " (CARMEN scan log, "
        << scans.lines_read << " lines)\n";
    out << FormatStream(scans.stats);
    if (scans.stats.records > 0) {
      out << "    beams    ";
      for (const auto& [beams, count] : scans.beams) out << " " << beams << " beams: " << count << " scans;";
      out << "\n";
      out << "    geometry  first scan: start " << Fmt("%.3f", scans.first_start_rad * kRadToDeg)
          << "°, step " << Fmt("%.4f", scans.first_step_rad * kRadToDeg) << "°, max range "
          << (scans.first_max_range_m > 0 ? Fmt("%.2f m", scans.first_max_range_m)
                                          : std::string("not in the log (FLASER)"))
          << "\n";
      // Readings valid by the log alone (no preset): finite, > 0, below the log's maximum.
      io::CarmenReader reader(path);
      io::ScanRecord scan;
      int64_t total = 0, valid = 0;
      float lo = 1e30f, hi = 0.0f;
      while (reader.Next(&scan)) {
        total += static_cast<int64_t>(scan.ranges_m.size());
        valid += LogValid(scan, &lo, &hi);
      }
      out << "    readings  " << valid << " of " << total << " valid (finite, > 0, below the maximum)";
      if (valid > 0) out << ", " << Fmt("%.3f", lo) << " .. " << Fmt("%.3f", hi) << " m";
      out << "\n";
    }
    out << "  skipped lines: " << DescribeSkips(scans.skipped) << "\n";
  }
  return out.str();
}

SessionInspection InspectSession(const std::string& session_path, const std::string& config_path) {
  SessionInspection result;
  const io::SessionSpec spec = io::ReadSession(session_path);
  io::CalibrateOptions options;
  if (!config_path.empty()) options = io::ReadCalibrateOptions(config_path);
  options.Validate();
  auto block = [&](const std::string& text) { result.blockers.push_back(text); };
  auto warn = [&](const std::string& text) { result.warnings.push_back(text); };

  std::ostringstream out;
  out << "wallcal inspect " << io::kToolVersion << ": session '" << spec.name << "' ("
      << spec.file << ")\n";

  // --- Scanner preset ------------------------------------------------------------------
  std::optional<io::ScannerPreset> preset;
  try {
    preset = io::LoadScannerPreset(spec.scanner_model, pipeline::PresetDirs());
    out << "  scanner   " << preset->name << ": " << preset->num_beams << " beams, "
        << Fmt("%.2f", preset->rate_hz) << " Hz, max range " << Fmt("%.1f", preset->max_range_m)
        << " m\n";
  } catch (const io::InputError& e) {
    block(std::string("scanner preset: ") + e.what());
    out << "  scanner   preset '" << spec.scanner_model << "' not found\n";
  }

  // --- Logs ------------------------------------------------------------------------------
  out << "\nlogs\n";
  std::optional<ScanLogSummary> scans;
  try {
    scans = ReadScanLog(spec.scanner_log, spec.scanner_time_offset_s,
                        preset ? &*preset : nullptr, options.detector.min_range_m,
                        options.detector.mixed_pixel_jump_m);
    out << FormatStream(scans->stats);
    if (scans->stats.records > 0) {
      out << "    beams    ";
      for (const auto& [beams, count] : scans->beams) out << " " << beams << ": " << count << " scans;";
      out << "\n";
      if (preset) {
        for (const auto& [beams, count] : scans->beams) {
          if (static_cast<int>(beams) != preset->num_beams) {
            warn(std::to_string(count) + " scans have " + std::to_string(beams) + " beams, preset " +
                 preset->name + " has " + std::to_string(preset->num_beams) + ": check scanner.model");
          }
        }
      }
    }
    if (scans->have_readings) {
      const calib::RangeCounts& r = scans->readings;
      const int64_t total = r.valid + r.error_code + r.no_return + r.too_close + r.non_finite;
      out << "    readings  " << total << ": " << r.valid << " valid, " << r.no_return
          << " no return, " << r.error_code << " error codes, " << r.too_close
          << " too close (< " << Fmt("%.2f", options.detector.min_range_m) << " m), "
          << r.non_finite << " non-finite\n";
    }
    out << "    skipped   " << DescribeSkips(scans->skipped) << "\n";
    if (scans->stats.records == 0) {
      block(spec.scanner_log + ": no scan records; expected CARMEN RAWLASER1/ROBOTLASER1/FLASER lines");
    }
    if (const int64_t bad = WorrisomeSkips(scans->skipped); bad > 0) {
      warn(FileName(spec.scanner_log) + ": " + std::to_string(bad) + " malformed scan lines skipped");
    }
    if (scans->stats.not_increasing > 0) {
      warn(FileName(spec.scanner_log) + ": scan times go back or repeat " +
           std::to_string(scans->stats.not_increasing) + " times (first at line " +
           std::to_string(scans->stats.first_not_increasing_line) + ")");
    }
  } catch (const io::InputError& e) {
    block(std::string("scan log: ") + e.what());
    out << "  scans: unreadable: " << e.what() << "\n";
  }

  std::optional<io::NmeaLog> gnss;
  try {
    gnss = io::ReadNmea(spec.gnss_log);
  } catch (const io::InputError& e) {
    block(std::string("GNSS log: ") + e.what());
    out << "  GNSS fixes: unreadable: " << e.what() << "\n";
  }
  std::optional<StreamStats> fix_stats;
  int64_t accepted_fixes = 0;
  if (gnss) {
    fix_stats = FixStats(spec.gnss_log, *gnss);
    out << FormatStream(*fix_stats);
    out << FormatQualities(*gnss);
    for (const io::GnssFix& fix : gnss->fixes) {
      if (io::FixQualityAccepted(fix.quality, spec.min_fix_quality)) ++accepted_fixes;
    }
    const double max_step_s = std::isfinite(fix_stats->median_period_s)
                                  ? fix_stats->gap_periods * fix_stats->median_period_s
                                  : 0.0;
    const double span_s = fix_stats->records > 0 ? fix_stats->end_s - fix_stats->start_s : 0.0;
    const double rtk_s = TimeRtkFixed(gnss->fixes, max_step_s);
    out << "    RTK fixed " << Fmt("%.3f", rtk_s) << " s of " << Fmt("%.3f", span_s) << " s";
    if (span_s > 0) out << " (" << Fmt("%.1f", 100.0 * rtk_s / span_s) << " %)";
    out << "; " << accepted_fixes << " fixes accepted (gnss.min_fix_quality "
        << spec.min_fix_quality << ")\n";
    out << "    skipped   " << DescribeSkips(gnss->skipped) << "\n";
    const int64_t n_fixes = static_cast<int64_t>(gnss->fixes.size());
    int dominant = -1;
    int64_t dominant_count = 0;
    for (const auto& [quality, count] : gnss->fixes_by_quality) {
      if (count > dominant_count) {
        dominant = quality;
        dominant_count = count;
      }
    }
    const std::string mostly =
        dominant >= 0 ? "; mostly quality " + std::to_string(dominant) + " (" +
                            io::FixQualityName(dominant) + ")"
                      : std::string();
    if (n_fixes == 0) {
      block(spec.gnss_log + ": no GGA fixes; expected NMEA GGA sentences");
    } else if (accepted_fixes < 2) {
      block("GNSS: " + std::to_string(accepted_fixes) + " of " + std::to_string(n_fixes) +
            " fixes have an accepted quality (gnss.min_fix_quality " +
            std::to_string(spec.min_fix_quality) + ")" + mostly +
            ": wait for RTK fixed, or accept float with min_fix_quality: 5");
    } else if (2 * accepted_fixes < n_fixes) {
      warn("GNSS: only " + std::to_string(accepted_fixes) + " of " + std::to_string(n_fixes) +
           " fixes have an accepted quality" + mostly);
    } else if (span_s > 0 && rtk_s < 0.5 * span_s && spec.min_fix_quality == 5) {
      warn("GNSS: RTK fixed only " + Fmt("%.0f", 100.0 * rtk_s / span_s) +
           " % of the time (float accepted)");
    }
    if (const int64_t bad = WorrisomeSkips(gnss->skipped); bad > 0) {
      warn(FileName(spec.gnss_log) + ": " + std::to_string(bad) + " sentences skipped (" +
           DescribeSkips(gnss->skipped) + ")");
    }
  }

  std::optional<io::NmeaLog> heading_log;
  if (spec.heading_log == spec.gnss_log) {
    heading_log = gnss;
  } else {
    try {
      heading_log = io::ReadNmea(spec.heading_log);
    } catch (const io::InputError& e) {
      block(std::string("heading log: ") + e.what());
      out << "  headings: unreadable: " << e.what() << "\n";
    }
  }
  std::optional<StreamStats> heading_stats;
  if (heading_log) {
    heading_stats = HeadingStats(spec.heading_log, *heading_log);
    out << FormatStream(*heading_stats);
    if (spec.heading_log != spec.gnss_log) {
      out << "    skipped   " << DescribeSkips(heading_log->skipped) << "\n";
      if (const int64_t bad = WorrisomeSkips(heading_log->skipped); bad > 0) {
        warn(FileName(spec.heading_log) + ": " + std::to_string(bad) + " sentences skipped (" +
             DescribeSkips(heading_log->skipped) + ")");
      }
    }
    if (heading_log->headings.size() < 2) {
      block(spec.heading_log + ": " + std::to_string(heading_log->headings.size()) +
            " usable HDT/THS headings; expected a heading log");
    }
  }

  // --- Overlap ----------------------------------------------------------------------------
  Interval scan_span, fix_span, heading_span;
  if (scans && scans->stats.records > 0) scan_span = {scans->stats.start_s, scans->stats.end_s};
  if (fix_stats && fix_stats->records > 0) fix_span = {fix_stats->start_s, fix_stats->end_s};
  if (heading_stats && heading_stats->records > 0) {
    heading_span = {heading_stats->start_s, heading_stats->end_s};
  }
  const Interval pose_span = Intersect(fix_span, heading_span);
  const Interval all_span = Intersect(scan_span, pose_span);
  if (scan_span.Valid() || fix_span.Valid() || heading_span.Valid()) {
    out << "  overlap   scans & GNSS " << FormatOverlap(Intersect(scan_span, fix_span))
        << "; scans & headings " << FormatOverlap(Intersect(scan_span, heading_span))
        << "; GNSS & headings " << FormatOverlap(pose_span) << "; all three "
        << FormatOverlap(all_span);
    if (scans && all_span.Valid()) {
      int64_t inside = 0;
      for (double t : scans->stamps_s) inside += (t >= all_span.start_s && t <= all_span.end_s);
      out << " (" << inside << " of " << scans->stats.records << " scans inside)";
      if (2 * inside < scans->stats.records) {
        warn("only " + std::to_string(inside) + " of " + std::to_string(scans->stats.records) +
             " scans fall inside the time covered by both GNSS and heading");
      }
    }
    out << "\n";
    if (scan_span.Valid() && fix_span.Valid() && heading_span.Valid() && !all_span.Valid()) {
      block("logs not overlapping in time: scans " + FormatStamp(scan_span.start_s) + " .. " +
            FormatStamp(scan_span.end_s) + ", GNSS " + FormatStamp(fix_span.start_s) + " .. " +
            FormatStamp(fix_span.end_s) + ", headings " + FormatStamp(heading_span.start_s) +
            " .. " + FormatStamp(heading_span.end_s) +
            " (check the logging clocks and scanner.time_offset_s)");
    }
  }

  // --- Survey and control points ------------------------------------------------------------
  out << "\nsurvey\n";
  std::optional<calib::LocalFrame> frame;
  if (!spec.control.empty()) {
    frame = calib::MakeLocalFrame(spec.control.front().lat_deg, spec.control.front().lon_deg,
                                  spec.utm_zone);
  }
  try {
    const std::vector<io::SurveyPoint> survey =
        io::CombineSurveyObservations(io::ReadSurvey(spec.survey_points, spec.survey_columns))
            .points;
    out << "  points    " << survey.size() << " in " << FileName(spec.survey_points) << "\n";
    if (!frame) throw io::InputError(io::Where(spec.file, 0, "no survey.control points"));
    const calib::SurveyTie tie =
        calib::TieSurvey(survey, spec.survey_points, spec, *frame, options.solver);
    out << "  control   " << tie.num_control << " points";
    if (tie.num_control >= 2) {
      out << ", fit RMS " << Fmt("%.1f", 1000.0 * tie.control_rms_m) << " mm\n";
      for (const calib::ControlResidual& r : tie.control_residuals) {
        out << "    " << r.id << "  residual east " << Fmt("%+.1f", 1000.0 * r.residual_m.x())
            << " mm, north " << Fmt("%+.1f", 1000.0 * r.residual_m.y()) << " mm ("
            << Fmt("%.1f", 1000.0 * r.residual_m.norm()) << " mm)\n";
      }
      const double expected_m =
          std::hypot(options.solver.control_sigma_m, options.solver.total_station_sigma_m);
      if (tie.control_rms_m > 3.0 * expected_m) {
        warn("control points fit the survey with RMS " + Fmt("%.1f", 1000.0 * tie.control_rms_m) +
             " mm, more than 3x the expected " + Fmt("%.1f", 1000.0 * expected_m) +
             " mm: check the control ids and their RTK positions");
      }
    } else {
      out << " (rotation given: no residuals to check)\n";
    }
    const std::vector<calib::WallGeometry> walls =
        calib::FitWalls(survey, spec.survey_points, spec, tie, options.solver);
    for (size_t w = 0; w < walls.size(); ++w) {
      out << "  wall      " << walls[w].id << " (" << spec.walls[w].code << "): "
          << walls[w].num_points << " points over "
          << Fmt("%.2f", (walls[w].end_b_local - walls[w].end_a_local).norm()) << " m, fit RMS "
          << Fmt("%.1f", 1000.0 * walls[w].rms_m) << " mm\n";
    }
  } catch (const io::InputError& e) {
    block(std::string("survey: ") + e.what());
    out << "  unusable: " << e.what() << "\n";
  }

  // --- Stations from GNSS + heading (as calibrate finds them) -------------------------------
  std::vector<calib::Dwell> dwells;
  std::vector<double> logged_grid_headings_rad;
  bool have_poses = false;
  if (gnss && heading_log && accepted_fixes >= 2 && heading_log->headings.size() >= 2) {
    std::vector<calib::PositionSample> positions;
    std::vector<const io::GnssFix*> used;
    if (!frame) {
      const io::GnssFix* first = nullptr;
      for (const io::GnssFix& fix : gnss->fixes) {
        if (io::FixQualityAccepted(fix.quality, spec.min_fix_quality)) {
          first = &fix;
          break;
        }
      }
      frame = calib::MakeLocalFrame(first->lat_deg, first->lon_deg, spec.utm_zone);
    }
    positions = calib::PositionSamples(*gnss, spec.min_fix_quality, *frame, &used);
    const std::vector<calib::YawSample> yaws =
        calib::YawSamples(*heading_log, spec.heading_reference, *frame, used);
    for (const calib::YawSample& sample : yaws) {
      logged_grid_headings_rad.push_back(kPi / 2.0 - sample.yaw_rad);
    }
    if (positions.size() >= 2 && yaws.size() >= 2) {
      try {
        const calib::PoseInterpolator poses(positions, yaws, options.alignment);
        dwells = poses.dwells();
        have_poses = poses.start_s() < poses.end_s();
      } catch (const std::exception& e) {
        block(std::string("poses: ") + e.what());
      }
    }
  } else if (heading_log) {
    for (const io::HeadingSample& h : heading_log->headings) {
      logged_grid_headings_rad.push_back(h.heading_rad);
    }
  }

  // --- Wall detection: the calibrate pipeline itself -------------------------------------
  std::optional<pipeline::CalibrationResult> calibration;
  std::string detection_note;
  if (result.blockers.empty()) {
    try {
      pipeline::CalibrateRequest request;
      request.session_path = session_path;
      request.config_path = config_path;
      calibration = pipeline::RunCalibration(request);
    } catch (const io::InputError& e) {
      block(e.what());
      detection_note = "not run to the end: " + std::string(e.what());
    }
  } else {
    detection_note = "not run: the problems listed in the verdict come first";
  }

  // The pipeline stops after the first (subsampled, wide-gate) pass when that pass finds no
  // wall or its estimate is refused; only in the first case are the detections complete.
  bool detections_complete = false;
  bool wall_never_seen = false;
  if (calibration) {
    const bool first_pass_refused = !calibration->first_pass.usable;
    wall_never_seen = first_pass_refused && calibration->first_pass.failure ==
                                                solvers::EstimateFailure::kWallNotDetected;
    detections_complete = !first_pass_refused || wall_never_seen;
    if (!detections_complete) {
      detection_note = "stopped after the first pass (estimate refused: " +
                       calibration->first_pass.message + ")";
    }
  }

  out << "\nstations (stops of at least " << Fmt("%.1f", options.alignment.min_dwell_s)
      << " s): " << dwells.size() << "\n";
  std::vector<double> seen_headings_rad;
  int stations_with_wall = 0;
  int64_t station_scans_total = 0, station_detections_total = 0;
  if (!dwells.empty()) {
    out << "     #  start       dur  heading   scans  wall seen        inliers  fit rms\n";
    // Each scan's observations (one per wall it saw), by scan index.
    std::map<int, std::vector<const calib::WallObservation*>> by_scan;
    if (calibration) {
      for (const calib::WallObservation& o : calibration->observations) {
        by_scan[o.scan_index].push_back(&o);
      }
    }
    const double t0 = scans && scans->stats.records > 0 ? scans->stats.start_s : dwells.front().start_s;
    for (size_t d = 0; d < dwells.size(); ++d) {
      const calib::Dwell& dwell = dwells[d];
      int64_t n_scans = 0;
      if (scans) {
        for (double t : scans->stamps_s) n_scans += (t >= dwell.start_s && t <= dwell.end_s);
      }
      const double heading_deg = std::fmod((kPi / 2.0 - dwell.mean_yaw_rad) * kRadToDeg + 720.0, 360.0);
      char row[256];
      std::snprintf(row, sizeof(row), "  %4zu  %+8.1f s %5.1f s %6.1f° %7lld", d + 1,
                    dwell.start_s - t0, dwell.end_s - dwell.start_s, heading_deg,
                    static_cast<long long>(n_scans));
      out << row;
      station_scans_total += n_scans;
      if (!detections_complete) {
        out << "  -\n";
        continue;
      }
      int64_t detected = 0, inliers = 0, fits = 0;
      double rms_sum = 0.0;
      for (const auto& [scan_index, list] : by_scan) {
        const double t = list.front()->pose.stamp_s;
        if (t < dwell.start_s || t > dwell.end_s) continue;
        ++detected;
        for (const calib::WallObservation* o : list) {
          inliers += o->num_inliers;
          rms_sum += o->residual_rms_m;
          ++fits;
        }
      }
      station_detections_total += detected;
      if (detected > 0) ++stations_with_wall;
      const double share = n_scans > 0 ? 100.0 * static_cast<double>(detected) / static_cast<double>(n_scans) : 0.0;
      if (fits > 0) {
        std::snprintf(row, sizeof(row), "  %6lld (%3.0f%%)   %7.0f  %5.1f mm\n",
                      static_cast<long long>(detected), share,
                      static_cast<double>(inliers) / static_cast<double>(fits),
                      1000.0 * rms_sum / static_cast<double>(fits));
      } else {
        std::snprintf(row, sizeof(row), "  %6lld (%3.0f%%)         -        -\n",
                      static_cast<long long>(detected), share);
      }
      out << row;
    }
  }
  if (calibration) {
    std::set<int> seen_scans;
    for (const calib::WallObservation& o : calibration->observations) {
      if (seen_scans.insert(o.scan_index).second) seen_headings_rad.push_back(kPi / 2.0 - o.pose.yaw_rad);
    }
  }

  // --- Wall detection and heading coverage ------------------------------------------------
  out << "\nwall detection\n";
  if (calibration && detections_complete) {
    const pipeline::CalibrationResult& c = *calibration;
    out << "  scans     " << c.scans_total << " in the log, wall seen in " << c.scans_used;
    for (const auto& [reason, count] : c.scans_skipped) {
      out << "; " << count << " " << calib::ScanSkipName(reason);
    }
    out << "\n";
    out << "  observations " << c.observations.size();
    if (!c.observations.empty()) {
      double inl = 0.0, rms = 0.0;
      for (const calib::WallObservation& o : c.observations) {
        inl += o.num_inliers;
        rms += o.residual_rms_m;
      }
      const double n = static_cast<double>(c.observations.size());
      out << ", mean " << Fmt("%.0f", inl / n) << " inliers, mean fit RMS "
          << Fmt("%.1f", 1000.0 * rms / n) << " mm";
    }
    out << "\n";
  } else {
    out << "  " << detection_note << "\n";
  }
  out << "  headings (grid, clockwise from grid north)\n";
  out << "              " << HistogramAxis() << "\n";
  if (!logged_grid_headings_rad.empty()) {
    out << "    logged    " << Histogram(logged_grid_headings_rad) << "\n";
  }
  const AngleExtent seen = Extent(seen_headings_rad);
  if (calibration && detections_complete) {
    out << "    wall seen " << Histogram(seen_headings_rad);
    if (seen.any) {
      out << "  " << OccupiedBins(seen_headings_rad) << " bins, " << Fmt("%.1f", seen.min_deg)
          << "°.." << Fmt("%.1f", seen.max_deg) << "° (" << Fmt("%.1f", seen.width_deg) << "° wide)";
    }
    out << "\n";
  }

  // --- Verdict --------------------------------------------------------------------------------
  const io::SolverOptions& so = options.solver;
  const double min_spread_deg = so.min_heading_spread_rad * kRadToDeg;
  bool geometry_named = false;
  if (!dwells.empty() && !options.alignment.use_moving_scans) {
    std::vector<double> station_headings_rad;
    for (const calib::Dwell& dwell : dwells) station_headings_rad.push_back(kPi / 2.0 - dwell.mean_yaw_rad);
    const AngleExtent stations = Extent(station_headings_rad);
    out << "  stations  at grid headings " << Fmt("%.1f", stations.min_deg) << "°.."
        << Fmt("%.1f", stations.max_deg) << "° (" << Fmt("%.1f", stations.width_deg) << "° wide)\n";
    if (stations.width_deg < min_spread_deg) {
      block("narrow heading spread: the stations' grid headings span " +
            Fmt("%.1f", stations.min_deg) + "°.." + Fmt("%.1f", stations.max_deg) + "° only (" +
            Fmt("%.1f", stations.width_deg) + "° wide; at least " + Fmt("%.0f", min_spread_deg) +
            "° needed): stop at more varied headings to the wall");
      geometry_named = true;
    }
  }
  if (dwells.empty() && have_poses && !options.alignment.use_moving_scans) {
    block("too few stations: the vehicle never stood still for " +
          Fmt("%.1f", options.alignment.min_dwell_s) + " s (scans taken while moving are not used)");
    geometry_named = true;
  }
  if (calibration) {
    const pipeline::CalibrationResult& c = *calibration;
    if (wall_never_seen) {
      block("wall never detected: " + c.first_pass.message);
      geometry_named = true;
    } else if (detections_complete) {
      if (stations_with_wall < so.min_stations && !dwells.empty() &&
          !options.alignment.use_moving_scans) {
        block("too few stations: the wall was seen at " + std::to_string(stations_with_wall) +
              " stops (at least " + std::to_string(so.min_stations) +
              " needed): stop at more places and headings in front of the wall");
        geometry_named = true;
      }
      if (seen.any && seen.width_deg < min_spread_deg && !geometry_named) {
        block("narrow heading spread: the wall was seen at grid headings " +
              Fmt("%.1f", seen.min_deg) + "°.." + Fmt("%.1f", seen.max_deg) + "° only (" +
              Fmt("%.1f", seen.width_deg) + "° wide; at least " + Fmt("%.0f", min_spread_deg) +
              "° needed): stop at more varied headings to the wall");
        geometry_named = true;
      }
      if (static_cast<int64_t>(c.observations.size()) < so.min_observations) {
        block("too few observations: " + std::to_string(c.observations.size()) + " (at least " +
              std::to_string(so.min_observations) + " needed)");
        geometry_named = true;
      }
      if (station_scans_total > 0 && 2 * station_detections_total < station_scans_total) {
        warn("wall rarely detected: in " + std::to_string(station_detections_total) + " of " +
             std::to_string(station_scans_total) +
             " scans at stations (check the wall is in range and unobstructed)");
      }
    }
    if (!c.estimate.usable && !wall_never_seen) {
      block("calibrate refuses the estimate: " + c.estimate.message);
    }
    for (const std::string& w : c.warnings) {
      if (std::find(result.warnings.begin(), result.warnings.end(), w) == result.warnings.end()) {
        warn(w);
      }
    }
    if (c.estimate.usable) {
      out << "  preview   a calibration now gives x = " << Fmt("%.3f", c.estimate.mount.x_m)
          << " m, y = " << Fmt("%.3f", c.estimate.mount.y_m) << " m, yaw = "
          << Fmt("%.2f", c.estimate.mount.yaw_rad * kRadToDeg) << "° (residual RMS "
          << Fmt("%.1f", 1000.0 * c.estimate.residual_rms_m) << " mm)\n";
    }
  }

  result.enough = result.blockers.empty();
  out << "\nverdict\n";
  for (const std::string& w : result.warnings) out << "  warning: " << w << "\n";
  if (result.enough) {
    out << "  VERDICT: enough data for a calibration\n";
  } else {
    out << "  VERDICT: NOT enough data for a calibration:\n";
    for (const std::string& b : result.blockers) out << "    - " << b << "\n";
  }
  result.report = out.str();
  return result;
}

void Dump(const std::string& path, DumpKind kind, std::ostream& out) {
  std::string log_path = path;
  std::optional<io::SessionSpec> spec;
  std::optional<io::ScannerPreset> preset;
  if (IsSessionPath(path)) {
    spec = io::ReadSession(path);
    log_path = kind == DumpKind::kGnss      ? spec->gnss_log
               : kind == DumpKind::kHeading ? spec->heading_log
                                            : spec->scanner_log;
    if (kind == DumpKind::kScans) preset = io::LoadScannerPreset(spec->scanner_model, pipeline::PresetDirs());
  }
  const LogKind found = SniffLogKind(log_path);
  const LogKind wanted = kind == DumpKind::kScans ? LogKind::kCarmen : LogKind::kNmea;
  if (found != wanted) {
    const char* what = kind == DumpKind::kGnss ? "gnss" : kind == DumpKind::kHeading ? "heading" : "scans";
    throw io::InputError(io::Where(
        log_path, 0,
        std::string("is ") + (found == LogKind::kNmea ? "an NMEA log" : "a CARMEN scan log") +
            "; --dump " + what + " expects " +
            (wanted == LogKind::kNmea ? "an NMEA log" : "a CARMEN scan log")));
  }
  if (kind == DumpKind::kGnss) {
    const io::NmeaLog log = io::ReadNmea(log_path);
    out << "time_s,lat_deg,lon_deg,height_m,quality,satellites,hdop,sigma_lat_m,sigma_lon_m,line\n";
    for (const io::GnssFix& f : log.fixes) {
      CsvNumber(out, "%.6f", f.stamp_s);
      out << ',';
      CsvNumber(out, "%.10f", f.lat_deg);
      out << ',';
      CsvNumber(out, "%.10f", f.lon_deg);
      out << ',';
      CsvNumber(out, "%.4f", f.height_m);
      out << ',' << f.quality << ',' << f.satellites << ',';
      CsvNumber(out, "%.10g", f.hdop);
      out << ',';
      CsvNumber(out, "%.10g", f.sigma_lat_m);
      out << ',';
      CsvNumber(out, "%.10g", f.sigma_lon_m);
      out << ',' << f.line << '\n';
    }
  } else if (kind == DumpKind::kHeading) {
    const io::NmeaLog log = io::ReadNmea(log_path);
    out << "time_s,heading_deg,line\n";
    for (const io::HeadingSample& h : log.headings) {
      CsvNumber(out, "%.6f", h.stamp_s);
      out << ',';
      CsvNumber(out, "%.9f", h.heading_rad * kRadToDeg);
      out << ',' << h.line << '\n';
    }
  } else {
    const double offset_s = spec ? spec->scanner_time_offset_s : 0.0;
    io::CarmenReader reader(log_path);
    io::ScanRecord scan;
    out << "time_s,beams,valid,min_range_m,max_range_m,line\n";
    while (reader.Next(&scan)) {
      int valid = 0;
      float lo = 1e30f, hi = -1.0f;
      if (preset) {
        // Valid per the preset: not an error code, not a no-return, not below its floor.
        calib::RangeCounts counts;
        const calib::ScanPoints points = calib::ToScanPoints(scan, *preset, 0.0, 1e9, &counts);
        valid = static_cast<int>(counts.valid);
        for (int beam : points.beam) {
          const float r = scan.ranges_m[static_cast<size_t>(beam)];
          lo = std::min(lo, r);
          hi = std::max(hi, r);
        }
      } else {
        valid = LogValid(scan, &lo, &hi);
      }
      CsvNumber(out, "%.6f", scan.stamp_s + offset_s);
      out << ',' << scan.ranges_m.size() << ',' << valid << ',';
      if (valid > 0) {
        out << Fmt("%.7g", lo) << ',' << Fmt("%.7g", hi);
      } else {
        out << ',';
      }
      out << ',' << scan.line << '\n';
    }
  }
}

int RunInspect(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  static const char* kUsage =
      R"(usage: inspect PATH [--dump gnss|heading|scans] [--config FILE]

The pre-flight check of a wall session: run it before leaving the site.

  PATH            a session (session.yaml or its folder), or one log file: NMEA (GNSS,
                  heading) or CARMEN (scans, plain or gzip), recognised by content
  --dump KIND     write the decoded records as CSV on stdout instead of the report:
                    gnss     time_s,lat_deg,lon_deg,height_m,quality,satellites,hdop,
                             sigma_lat_m,sigma_lon_m,line
                    heading  time_s,heading_deg,line
                    scans    time_s,beams,valid,min_range_m,max_range_m,line
                  (on a session: that log of the session)
  --config FILE   calibrate options used for the detection and the checks (as calibrate)
  --help          this text

On a session: each log's time span, rate, gaps and their overlap; GNSS fix qualities and time
RTK fixed; survey control residuals; stations and how well the wall was detected at each; the
headings at which the wall was seen; and a verdict: enough data for a calibration, or what is
missing. On one log: its time span, rate, gaps, counts and skipped lines.
Exit status: 0 report or dump written (whatever the verdict); 2 unusable input or bad usage
(one line on stderr naming the file, the line and what was expected).
)";
  std::string path, dump, config;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--help" || arg == "-h") {
      out << kUsage;
      return 0;
    } else if (arg == "--dump" || arg == "--config") {
      if (i + 1 >= args.size()) {
        err << "inspect: " << arg << " needs a value (run 'inspect --help' for usage)\n";
        return 2;
      }
      (arg == "--dump" ? dump : config) = args[++i];
    } else if (!arg.empty() && arg[0] == '-') {
      err << "inspect: unknown option '" << arg << "' (run 'inspect --help' for usage)\n";
      return 2;
    } else if (path.empty()) {
      path = arg;
    } else {
      err << "inspect: more than one PATH given ('" << path << "' and '" << arg << "')\n";
      return 2;
    }
  }
  if (path.empty()) {
    err << "inspect: no PATH given (run 'inspect --help' for usage)\n";
    return 2;
  }
  try {
    if (!dump.empty()) {
      DumpKind kind;
      if (dump == "gnss") {
        kind = DumpKind::kGnss;
      } else if (dump == "heading") {
        kind = DumpKind::kHeading;
      } else if (dump == "scans") {
        kind = DumpKind::kScans;
      } else {
        err << "inspect: --dump: unknown kind '" << dump << "'; expected gnss, heading or scans\n";
        return 2;
      }
      // Build the whole dump first: an error half-way leaves stdout without half a table.
      std::ostringstream table;
      Dump(path, kind, table);
      out << table.str();
      return 0;
    }
    if (IsSessionPath(path)) {
      out << InspectSession(path, config).report;
    } else {
      out << InspectLogFile(path);
    }
    return 0;
  } catch (const io::InputError& error) {
    err << "inspect: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    err << "inspect: internal error: " << error.what() << "\n";
    return 3;
  }
}

}  // namespace wallcal::preflight
