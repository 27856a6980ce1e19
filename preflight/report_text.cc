// SPDX-License-Identifier: Apache-2.0
// Text formatting shared by the inspect reports: numbers, stamps, heading histograms, stream
// statistics.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <set>
#include <sstream>

#include "common/angles.h"
#include "common/circular.h"
#include "preflight/internal/inspect_internal.h"

namespace wallcal::preflight::internal {

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

// Circular extent of angles (rad) about their circular mean: min and max as headings in
// [0, 360) degrees and the width in degrees (0 for fewer than one angle).
AngleExtent Extent(const std::vector<double>& angles_rad) {
  AngleExtent extent;
  const CircularExtent circular = CircularExtentOf(angles_rad);
  if (circular.empty) return extent;
  extent.any = true;
  extent.min_deg = std::fmod(circular.min_rad * kRadToDeg + 720.0, 360.0);
  extent.max_deg = std::fmod(circular.max_rad * kRadToDeg + 720.0, 360.0);
  extent.width_deg = (circular.max_rad - circular.min_rad) * kRadToDeg;
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
  return skips.Total() == 0 ? std::string("none") : skips.ListReasons(false);
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


}  // namespace wallcal::preflight::internal
