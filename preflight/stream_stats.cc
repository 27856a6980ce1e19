// SPDX-License-Identifier: Apache-2.0
// Time statistics of one stream of stamps, and of the NMEA streams (fixes, headings).
#include <cmath>
#include <sstream>

#include "common/statistics.h"
#include "preflight/internal/inspect_internal.h"

namespace wallcal::preflight {

namespace internal {

namespace {

// The stamps and log lines of one NMEA stream (fixes or headings), as ComputeStreamStats takes them.
template <class Sample>
StreamStats SampleStats(const char* name, const std::string& path,
                        const std::vector<Sample>& samples) {
  std::vector<double> stamps;
  std::vector<int> lines;
  for (const Sample& sample : samples) {
    stamps.push_back(sample.stamp_s);
    lines.push_back(sample.line);
  }
  return ComputeStreamStats(name, path, stamps, lines);
}

}  // namespace

StreamStats FixStats(const std::string& path, const io::NmeaLog& log) {
  return SampleStats("GNSS fixes (GGA)", path, log.fixes);
}

StreamStats HeadingStats(const std::string& path, const io::NmeaLog& log) {
  return SampleStats("headings (HDT/THS)", path, log.headings);
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

}  // namespace internal

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
  s.median_period_s = UpperMedian(steps, io::kNaN);
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

}  // namespace wallcal::preflight
