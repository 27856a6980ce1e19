// SPDX-License-Identifier: Apache-2.0
// The "logs" part of a session's inspection: each stream's statistics, its skipped lines, and
// their overlap in time.
#include <sstream>

#include "io/scanner_geometry.h"
#include "io/text/nmea_reader.h"
#include "preflight/internal/inspect_internal.h"

namespace wallcal::preflight::internal {

SessionLogs InspectSessionLogs(
    const io::SessionSpec& spec, const pipeline::CalibrateOptions& options,
    const io::ScannerPreset* preset,
    const std::function<std::optional<ScanLogSummary>()>& shared_scan_log,
    SessionInspection* result, std::ostream& out) {
  auto block = [&](const std::string& text) { result->blockers.push_back(text); };
  auto warn = [&](const std::string& text) { result->warnings.push_back(text); };
  SessionLogs logs;
  out << "\nlogs\n";
  std::optional<ScanLogSummary>& scans = logs.scans;
  try {
    // A CARMEN log or a recording's LaserScan topic (checked against the preset).
    if (shared_scan_log) scans = shared_scan_log();
    if (!scans) {
      const recording::ScanOpener opener = recording::MakeScanOpener(spec, preset);
      scans = ReadScanLog(spec.scanner_log, spec.scanner_time_offset_s, preset,
                          options.detector.min_range_m, options.detector.mixed_pixel_jump_m,
                          &opener);
    }
    out << FormatStream(scans->stats);
    if (scans->stats.records > 0) {
      out << "    beams    ";
      for (const auto& [beams, count] : scans->beams) out << " " << beams << ": " << count << " scans;";
      out << "\n";
      if (preset) {
        for (const auto& [beams, count] : scans->beams) {
          if (!io::BeamCountFits(static_cast<int64_t>(beams), *preset)) {
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

  // The GNSS or the heading stream (NMEA text or a recording topic); an unreadable one blocks.
  const auto read_pose_log = [&](bool gnss_stream, const std::string& what,
                                 const std::string& label) {
    std::optional<io::NmeaLog> log;
    try {
      recording::PoseLogs read =
          recording::ReadPoseLogs(spec, gnss_stream, !gnss_stream, /*attitude=*/false);
      log = std::move(gnss_stream ? read.gnss : read.headings);
      for (const std::string& w : read.warnings) warn(w);
    } catch (const io::InputError& e) {
      block(what + ": " + e.what());
      out << "  " << label << ": unreadable: " << e.what() << "\n";
    }
    return log;
  };

  std::optional<io::NmeaLog>& gnss = logs.gnss;
  gnss = read_pose_log(true, "GNSS log", "GNSS fixes");
  std::optional<StreamStats>& fix_stats = logs.fix_stats;
  int64_t& accepted_fixes = logs.accepted_fixes;
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

  std::optional<io::NmeaLog>& heading_log = logs.heading_log;
  if (spec.heading_log == spec.gnss_log && spec.heading_topic == spec.gnss_topic) {
    heading_log = gnss;
  } else {
    heading_log = read_pose_log(false, "heading log", "headings");
  }
  std::optional<StreamStats>& heading_stats = logs.heading_stats;
  if (heading_log) {
    heading_stats = HeadingStats(spec.heading_log, *heading_log);
    out << FormatStream(*heading_stats);
    if (spec.heading_log != spec.gnss_log || spec.heading_topic != spec.gnss_topic) {
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

  InspectSessionAttitude(spec, logs, result, out);

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
  return logs;
}

}  // namespace wallcal::preflight::internal
