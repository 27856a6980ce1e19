// SPDX-License-Identifier: Apache-2.0
// The report on one log file (InspectLogFile) and the scan-log summary it and the session
// report share.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/angles.h"
#include "io/text/carmen_reader.h"
#include "io/version.h"
#include "preflight/internal/inspect_internal.h"
#include "recording/recording_streams.h"

namespace wallcal::preflight {

namespace internal {

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
                           const io::ScannerPreset* preset, double min_range_m, double mixed_jump_m,
                           const recording::ScanOpener* opener) {
  ScanLogSummary summary;
  const std::unique_ptr<io::ScanSource> source =
      opener != nullptr ? (*opener)() : std::make_unique<io::CarmenReader>(path);
  io::ScanSource& reader = *source;
  io::ScanRecord scan;
  std::vector<int> lines;
  calib::ScanPoints points;  // reused for every scan
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
      calib::FillScanPoints(scan, *preset, min_range_m, mixed_jump_m, &summary.readings, &points);
      summary.have_readings = true;
    }
  }
  summary.stats = ComputeStreamStats("scans", path, summary.stamps_s, lines);
  summary.skipped = reader.skipped();
  const auto* carmen = dynamic_cast<const io::CarmenReader*>(source.get());
  summary.lines_read = carmen != nullptr ? carmen->lines_read() : reader.scans_read();
  return summary;
}

ScanLogSummary SummaryFromTally(const std::string& path, calib::ScanLogTally tally,
                                const io::SkipCounts& skipped) {
  ScanLogSummary summary;
  summary.stats = ComputeStreamStats("scans", path, tally.stamps_s, tally.lines);
  summary.stamps_s = std::move(tally.stamps_s);
  summary.beams = std::move(tally.beams);
  summary.readings = tally.readings;
  summary.have_readings = true;  // a pass always has its preset
  summary.first_start_rad = tally.first_start_rad;
  summary.first_step_rad = tally.first_step_rad;
  summary.first_max_range_m = tally.first_max_range_m;
  summary.skipped = skipped;
  // lines_read stays 0: a pass does not count lines (only the one-log report prints them).
  return summary;
}

}  // namespace internal

using namespace internal;  // the helpers shared by the inspect files

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
    if (!log.attitudes.empty()) out << FormatAttitude(SummariseAttitude(path, "", log), false);
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
      calib::ScanPoints points;  // reused for every scan
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

}  // namespace wallcal::preflight
